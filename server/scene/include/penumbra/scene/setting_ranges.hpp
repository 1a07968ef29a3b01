#pragma once

#include <array>
#include <string>
#include <string_view>

namespace penumbra::scene {

// The values one setting may take, both ends included, under its protocol name (the path in
// proto/v1/common.schema.json's $defs: "settings/light_buffer/compensation"). Each setting's
// range is declared once, here: scene::validate, the protocol parser and the command line read
// it, and a test holds the JSON Schemas' minimum and maximum against kSettingRanges.
struct SettingRange {
    std::string_view field;
    double min;
    double max;
    bool integer = false;

    // NaN and infinities are never within.
    [[nodiscard]] constexpr bool contains(double value) const {
        return value >= min && value <= max;
    }

    // "within [0.0001, 0.5]" or "within 1..4", for error messages.
    [[nodiscard]] std::string describe() const;
};

// The number of points per light slab is capped: past 16 the slab is sampled finer than any
// volume needs and the build only slows down.
inline constexpr int kMaxSlabSamples = 16;

namespace setting {

// Coordinates of the camera and a point light; the volume's longest side is 1.
inline constexpr SettingRange coordinate{"vec3", -1000.0, 1000.0};
// Colours (light, background), each channel.
inline constexpr SettingRange colour{"rgb", 0.0, 1.0};

inline constexpr SettingRange fov_degrees{"camera/fov", 1.0, 170.0};
inline constexpr SettingRange orbit_azimuth{"camera/orbit/azimuth", -36000.0, 36000.0};
inline constexpr SettingRange orbit_elevation{"camera/orbit/elevation", -90.0, 90.0};
inline constexpr SettingRange orbit_distance{"camera/orbit/distance", 0.01, 100.0};

inline constexpr SettingRange light_intensity{"light/intensity", 0.0, 100.0};
inline constexpr SettingRange light_ambient{"light/ambient", 0.0, 1.0};

// Finer than 1/16384 of the box resolves nothing more (volumes have at most a few thousand voxels
// a side) and only multiplies the work; at 2 a ray takes one sample inside the box. What a frame
// may cost is bounded separately (FrameWork against the server's max_frame_work).
inline constexpr SettingRange sample_distance{"settings/sample_distance", 1.0 / 16384.0, 2.0};
inline constexpr SettingRange opacity_unit_distance{"settings/opacity_unit_distance", 1e-4, 1.0};
inline constexpr SettingRange early_termination{"settings/early_termination", 0.01, 1.0};
inline constexpr SettingRange frame_budget_ms{"settings/frame_budget_ms", 0.0, 60000.0};

inline constexpr SettingRange diffuse{"settings/shading/diffuse", 0.0, 4.0};
inline constexpr SettingRange specular{"settings/shading/specular", 0.0, 4.0};
inline constexpr SettingRange shininess{"settings/shading/shininess", 1.0, 1024.0};

inline constexpr SettingRange compensation{"settings/light_buffer/compensation", 0.0, 1000.0};
inline constexpr SettingRange slab_samples{"settings/light_buffer/slab_samples", 0.0,
                                           kMaxSlabSamples, true};

inline constexpr SettingRange shell_radius{"settings/scattering/shell_radius", 1e-4, 0.5};
inline constexpr SettingRange shell_rings{"settings/scattering/shell_rings", 1.0, 4.0, true};
inline constexpr SettingRange shell_center_weight{"settings/scattering/shell_center_weight", 0.0,
                                                  1.0};
inline constexpr SettingRange cone_angle_degrees{"settings/scattering/cone_angle", 0.1, 80.0};
inline constexpr SettingRange cone_center_weight{"settings/scattering/cone_center_weight", 0.0,
                                                 1.0};

}  // namespace setting

// Every range above. Image size, light-buffer slices and resolution are bounded by the device
// and the server's configuration instead (scene::Limits, protocol::Limits).
inline constexpr std::array<const SettingRange*, 22> kSettingRanges{
        &setting::coordinate,
        &setting::colour,
        &setting::fov_degrees,
        &setting::orbit_azimuth,
        &setting::orbit_elevation,
        &setting::orbit_distance,
        &setting::light_intensity,
        &setting::light_ambient,
        &setting::sample_distance,
        &setting::opacity_unit_distance,
        &setting::early_termination,
        &setting::frame_budget_ms,
        &setting::diffuse,
        &setting::specular,
        &setting::shininess,
        &setting::compensation,
        &setting::slab_samples,
        &setting::shell_radius,
        &setting::shell_rings,
        &setting::shell_center_weight,
        &setting::cone_angle_degrees,
        &setting::cone_center_weight,
};

}  // namespace penumbra::scene
