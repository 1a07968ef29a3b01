#include "synthetic_volumes.hpp"

#include <glm/geometric.hpp>

namespace penumbra::test {
namespace {

template <class F>
volume::Volume generate(const char* name, glm::uvec3 dims, F&& value_at) {
    std::vector<float> values(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
    std::size_t i = 0;
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 0; y < dims.y; ++y) {
            for (unsigned x = 0; x < dims.x; ++x) {
                values[i++] = value_at(x, y, z);
            }
        }
    }
    return volume::make_volume(name, dims, glm::dvec3(1.0), values).value();
}

}  // namespace

volume::Volume sphere_volume(unsigned n, float radius, float inside, float outside) {
    const glm::vec3 centre(static_cast<float>(n) * 0.5f);
    const float r = radius * static_cast<float>(n) * 0.5f;
    return generate("sphere", glm::uvec3(n), [&](unsigned x, unsigned y, unsigned z) {
        const glm::vec3 p(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f,
                          static_cast<float>(z) + 0.5f);
        return glm::distance(p, centre) <= r ? inside : outside;
    });
}

volume::Volume radial_volume(unsigned n) {
    const glm::vec3 centre(static_cast<float>(n) * 0.5f);
    const float half = static_cast<float>(n) * 0.5f;
    return generate("radial", glm::uvec3(n), [&](unsigned x, unsigned y, unsigned z) {
        const glm::vec3 p(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f,
                          static_cast<float>(z) + 0.5f);
        return glm::max(0.0f, 1.0f - glm::distance(p, centre) / half);
    });
}

volume::Volume constant_volume(glm::uvec3 dims, float value) {
    return generate("constant", dims, [&](unsigned, unsigned, unsigned) { return value; });
}

volume::Volume slab_volume(glm::uvec3 dims, unsigned z_begin, unsigned z_end) {
    return generate("slab", dims, [&](unsigned, unsigned, unsigned z) {
        return z >= z_begin && z < z_end ? 1.0f : 0.0f;
    });
}

volume::Volume shadow_scene(unsigned n) {
    return generate("shadow_scene", glm::uvec3(n), [&](unsigned x, unsigned y, unsigned) {
        if (x >= n / 8 && x < 3 * n / 8) {
            return 1.0f;
        }
        if (x >= 3 * n / 4 && x < 7 * n / 8 && y < n / 2) {
            return 0.5f;
        }
        return 0.0f;
    });
}

}  // namespace penumbra::test
