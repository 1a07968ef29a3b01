#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>

namespace penumbra::reference {

// What lies under a pixel of a view.
struct Pick {
    bool hit = false;           // the pixel's ray met what the view shows
    glm::dvec3 patient{0.0};    // where, in patient coordinates (RAS millimetres)
    double value = 0.0;         // the scan's value there (its real values: HU for a CT)
    bool hounsfield = false;    // `value` is in Hounsfield units
    std::int64_t label_id = 0;  // the label there; 0 for none (or no label map drawn)
    std::string label_name;
};

// The point a user points at through pixel (x, y) of `request`'s view (row 0 at the top): where
// the pixel's ray has gathered half of its opacity, the surface the eye sees there (a faint haze
// in front of it is not what a user means), classified as the frame classifies: the transfer
// function, the labels' opacities and visibility (`labels`, when the request styles them), the
// cut; each sample by itself (a pre-integrated frame's segments may put the surface a fraction
// of a step away). No hit where the ray never gathers that much. One ray on the CPU, in double,
// with the frame's reconstruction and its step or half the finest voxel, whichever is longer (a
// pick's cost bounded by the volume's size), reading `volume` in place (no copy of it: a server
// answers picks between frames).
base::Result<Pick> pick(const volume::Volume& volume, const scene::FrameRequest& request,
                        const volume::LabelMap* labels, int x, int y);

// The value `volume` holds at `patient` (RAS millimetres) as a frame samples it (trilinear, the
// edge's value beyond it), in its real values (HU for a CT): what a pick says of the scan where
// the view draws a label map alone.
[[nodiscard]] double value_at(const volume::Volume& volume, glm::dvec3 patient);

}  // namespace penumbra::reference
