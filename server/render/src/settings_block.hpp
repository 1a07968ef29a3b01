#pragma once

#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/setting.hpp>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::render {

// The request's settings as every shader reads them: the std140 uniform block `settings` holds one
// member per row of scene::kSettings that every frame carries (a row with `read_frame`), named
// after the row's path (settings_member_name), in the table's order: `float` for a number, `int`
// for a whole number, a boolean (0, 1) and a choice (the index of its name, with a define per name:
// SETTINGS_COMPOSITING_EXTINCTION), `vec3` for a vector, `ivec2` for a size. The declaration is
// generated from the table and included by shaders/include/uniforms.glsl, and one function fills
// the buffer from the same rows, so a setting added to the table reaches the shaders
// (`settings.light_buffer_compensation`) with no line here, in the renderer or in the GLSL. The
// values are the request's own; what the renderer derives from them (a resolved count, a
// tangent) travels in FrameUniforms.
inline constexpr unsigned settings_block_binding = 1;

// The path the shaders include the declaration by (gpu::GeneratedFiles).
inline constexpr std::string_view settings_block_file = "generated/settings.glsl";

struct SettingsMember {
    const scene::Setting* row = nullptr;
    std::string name;        // "light_buffer_compensation"
    std::size_t offset = 0;  // bytes from the start of the block (std140)
};

// "settings/light_buffer/compensation" -> "light_buffer_compensation",
// "camera/fov" -> "camera_fov": the path without the leading "settings/", '/' made '_'.
std::string settings_member_name(std::string_view path);

// The define that names a choice's value in GLSL: SETTINGS_LIGHT_BUFFER_BUILDER_PER_SLICE.
std::string settings_choice_define(const SettingsMember& member, std::string_view choice);

// The block's members, in the table's order.
const std::vector<SettingsMember>& settings_members();

// The block's size in bytes, padded to a whole vec4 as std140 pads a block.
std::size_t settings_block_bytes();

// The GLSL declaration: `layout(std140, binding = 1) uniform Settings { ... } settings;`.
std::string settings_block_glsl();

// The block's bytes for `request` (settings_block_bytes() of them).
std::vector<std::byte> settings_block_data(const scene::FrameRequest& request);

}  // namespace penumbra::render
