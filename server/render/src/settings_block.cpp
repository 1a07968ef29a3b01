#include "settings_block.hpp"

#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>

namespace penumbra::render {
namespace {

// std140: a scalar (float, int) is aligned to its own 4 bytes, an ivec2 to 8, a vec3 to 16 while
// it takes 12 (a scalar may follow in the last 4); the block as a whole is padded to a vec4's 16.
constexpr std::size_t scalar_bytes = 4;
constexpr std::size_t vec4_bytes = 16;

static_assert(sizeof(float) == scalar_bytes && sizeof(std::int32_t) == scalar_bytes);

struct Std140 {
    const char* glsl_type;
    std::size_t alignment;
    std::size_t bytes;
};

Std140 layout_of(scene::SettingKind kind) {
    switch (kind) {
        case scene::SettingKind::number:
            return {"float", scalar_bytes, scalar_bytes};
        case scene::SettingKind::whole:
        case scene::SettingKind::boolean:
        case scene::SettingKind::choice:
            return {"int", scalar_bytes, scalar_bytes};
        case scene::SettingKind::vector:
            return {"vec3", vec4_bytes, 3 * scalar_bytes};
        case scene::SettingKind::size:
            return {"ivec2", 2 * scalar_bytes, 2 * scalar_bytes};
    }
    return {"float", scalar_bytes, scalar_bytes};
}

// The components a member stores: one, three for a vector, two for a size.
std::size_t components_of(scene::SettingKind kind) {
    return layout_of(kind).bytes / scalar_bytes;
}

std::size_t aligned(std::size_t offset, std::size_t alignment) {
    return (offset + alignment - 1) / alignment * alignment;
}

std::vector<SettingsMember> make_members() {
    std::vector<SettingsMember> members;
    std::size_t offset = 0;
    for (const scene::Setting* row : scene::kSettings) {
        if (row->in_frame()) {
            const Std140 layout = layout_of(row->kind);
            offset = aligned(offset, layout.alignment);
            members.push_back({row, settings_member_name(row->path), offset});
            offset += layout.bytes;
        }
    }
    return members;
}

std::string upper(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return out;
}

}  // namespace

std::string settings_member_name(std::string_view path) {
    constexpr std::string_view request_settings = "settings/";
    if (path.starts_with(request_settings)) {
        path.remove_prefix(request_settings.size());
    }
    std::string name(path);
    std::replace(name.begin(), name.end(), '/', '_');
    return name;
}

std::string settings_choice_define(const SettingsMember& member, std::string_view choice) {
    return "SETTINGS_" + upper(member.name) + "_" + upper(choice);
}

const std::vector<SettingsMember>& settings_members() {
    static const std::vector<SettingsMember> members = make_members();
    return members;
}

std::size_t settings_block_bytes() {
    const std::vector<SettingsMember>& members = settings_members();
    const std::size_t used =
            members.empty() ? 0 : members.back().offset + layout_of(members.back().row->kind).bytes;
    return std::max(vec4_bytes, aligned(used, vec4_bytes));
}

std::string settings_block_glsl() {
    std::string text =
            "// Generated from scene::kSettings (server/render/src/settings_block.cpp): each "
            "setting of a\n// frame, the request's value as is; a choice is the index of its "
            "name, a boolean 0 or 1.\n";
    for (const SettingsMember& member : settings_members()) {
        for (std::size_t i = 0; i < member.row->choices.size(); ++i) {
            text += "#define " + settings_choice_define(member, member.row->choices[i]) + " " +
                    std::to_string(i) + "\n";
        }
    }
    text += "layout(std140, binding = " + std::to_string(settings_block_binding) +
            ") uniform Settings {\n";
    for (const SettingsMember& member : settings_members()) {
        text += std::string("    ") + layout_of(member.row->kind).glsl_type + " " + member.name +
                ";  // " + std::string(member.row->path) + "\n";
    }
    text += "} settings;\n";
    return text;
}

std::vector<std::byte> settings_block_data(const scene::FrameRequest& request) {
    std::vector<std::byte> data(settings_block_bytes());
    for (const SettingsMember& member : settings_members()) {
        const scene::SettingValue value = member.row->read_frame(request);
        const bool floating = member.row->kind == scene::SettingKind::number ||
                              member.row->kind == scene::SettingKind::vector;
        for (std::size_t i = 0; i < components_of(member.row->kind); ++i) {
            std::byte* at = data.data() + member.offset + i * scalar_bytes;
            if (floating) {
                const auto single = static_cast<float>(value[static_cast<int>(i)]);
                std::memcpy(at, &single, scalar_bytes);
            } else {
                const auto whole = static_cast<std::int32_t>(value[static_cast<int>(i)]);
                std::memcpy(at, &whole, scalar_bytes);
            }
        }
    }
    return data;
}

}  // namespace penumbra::render
