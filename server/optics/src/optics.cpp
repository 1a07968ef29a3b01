#include <penumbra/optics/compositing.hpp>
#include <penumbra/optics/ray.hpp>
#include <penumbra/optics/shading.hpp>
