#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/light.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace penumbra::scene {

// The rendering methods of DESIGN.md §1.
enum class Mode { dvr, phong, half_angle, sbrc, sbrc_shell, sbrc_cone, reference };

// alpha: classic alpha blending with opacity correction a' = 1 - (1 - a)^(dt/dt0).
// extinction: the TF opacity is an extinction coefficient tau = a / dt0, a' = 1 - exp(-tau dt).
enum class Compositing { alpha, extinction };

// Where the ray caster runs: a compute shader writing an image, or a fragment shader over a
// full-screen triangle. Both share one source (DESIGN.md §5 asks that both be measurable).
enum class RaycastStage { compute, fragment };

const char* to_string(Mode mode);
const char* to_string(Compositing compositing);
const char* to_string(RaycastStage stage);
std::optional<Mode> parse_mode(std::string_view text);
std::optional<Compositing> parse_compositing(std::string_view text);
std::optional<RaycastStage> parse_raycast_stage(std::string_view text);

struct RenderSettings {
    int width = 512;
    int height = 512;
    Mode mode = Mode::dvr;
    Compositing compositing = Compositing::alpha;
    RaycastStage stage = RaycastStage::compute;
    double sample_distance = 1.0 / 256.0;        // world units (the box's longest side is 1)
    double opacity_unit_distance = 1.0 / 256.0;  // dt0: the distance the TF opacity refers to
    double early_termination = 0.99;             // stop a ray once its opacity reaches this
    glm::dvec3 background{0.0};
    Shading shading;
};

// Everything one frame depends on besides the volume itself.
struct FrameRequest {
    Camera camera;
    Light light;
    TransferFunction transfer_function;
    RenderSettings settings;
};

// Rejects what would make a frame meaningless or unbounded: sizes outside [1, max_image_side],
// non-finite or non-positive distances, a degenerate camera, invalid TF.
base::Status validate(const FrameRequest& request, int max_image_side = 8192);

}  // namespace penumbra::scene
