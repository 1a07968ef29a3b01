#include "settings_block.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace penumbra::render {
namespace {

// std140 aligns a scalar (float, int) to its own 4 bytes, so scalars follow each other without
// padding; the block as a whole is padded to the 16 bytes of a vec4.
constexpr std::size_t scalar_bytes = 4;
constexpr std::size_t vec4_bytes = 16;

static_assert(sizeof(float) == scalar_bytes && sizeof(std::int32_t) == scalar_bytes);

std::vector<SettingsMember> make_members() {
    std::vector<SettingsMember> members;
    for (const scene::SettingRange* row : scene::kSettingRanges) {
        if (row->read != nullptr) {
            members.push_back(
                    {row, settings_member_name(row->field), members.size() * scalar_bytes});
        }
    }
    return members;
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

const std::vector<SettingsMember>& settings_members() {
    static const std::vector<SettingsMember> members = make_members();
    return members;
}

std::size_t settings_block_bytes() {
    const std::size_t used = settings_members().size() * scalar_bytes;
    return std::max(vec4_bytes, (used + vec4_bytes - 1) / vec4_bytes * vec4_bytes);
}

std::string settings_block_glsl() {
    std::string text =
            "// Generated from scene::kSettingRanges (server/render/src/settings_block.cpp): "
            "each request setting\n// with a range, the request's value as is.\n";
    text += "layout(std140, binding = " + std::to_string(settings_block_binding) +
            ") uniform Settings {\n";
    for (const SettingsMember& member : settings_members()) {
        text += std::string("    ") + (member.row->integer ? "int " : "float ") + member.name +
                ";  // " + std::string(member.row->field) + "\n";
    }
    text += "} settings;\n";
    return text;
}

std::vector<std::byte> settings_block_data(const scene::FrameRequest& request) {
    std::vector<std::byte> data(settings_block_bytes());
    for (const SettingsMember& member : settings_members()) {
        const double value = member.row->read(request);
        if (member.row->integer) {
            const auto whole = static_cast<std::int32_t>(value);
            std::memcpy(data.data() + member.offset, &whole, scalar_bytes);
        } else {
            const auto single = static_cast<float>(value);
            std::memcpy(data.data() + member.offset, &single, scalar_bytes);
        }
    }
    return data;
}

}  // namespace penumbra::render
