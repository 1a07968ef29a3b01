#include "penumbra/protocol/frame_header.hpp"

#include <penumbra/protocol/limits.hpp>

#include <nlohmann/json.hpp>

#include <cstring>

namespace penumbra::protocol {
namespace {

using nlohmann::json;

constexpr std::uint8_t magic[4] = {'P', 'N', 'B', 'F'};
constexpr std::size_t prefix_bytes = 10;

void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v & 0xFF));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
        out.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
    }
}

base::Error bad_frame(const std::string& message) {
    return base::make_error(base::ErrorCode::invalid_frame, message, "frame");
}

}  // namespace

std::vector<std::uint8_t> pack_frame(const FrameHeader& h, std::span<const std::uint8_t> image) {
    json passes = json::array();
    for (const auto& pass : h.passes) {
        passes.push_back({{"name", pass.name}, {"gpu_ms", pass.gpu_ms}, {"wall_ms", pass.wall_ms}});
    }
    const std::string header = json{
            {"frame", h.frame},
            {"request", h.request},
            {"session", h.session},
            {"width", h.width},
            {"height", h.height},
            {"encoding", h.encoding},
            {"independent", h.independent},
            {"mode", h.mode},
            {"interactive", h.interactive},
            {"light_buffer", h.light_buffer},
            {"passes", passes},
            {"timings",
             {{"queued_ms", h.queued_ms},
              {"render_ms", h.render_ms},
              {"readback_ms", h.readback_ms},
              {"encode_ms", h.encode_ms}}},
            {"quality", h.quality},
            {"refinement", h.refinement},
            {"refining", h.refining},
            {"preview", h.preview}}.dump();
    std::vector<std::uint8_t> out;
    out.reserve(prefix_bytes + header.size() + image.size());
    for (const std::uint8_t byte : magic) {
        out.push_back(byte);
    }
    put_u16(out, static_cast<std::uint16_t>(protocol_version));
    put_u32(out, static_cast<std::uint32_t>(header.size()));
    out.insert(out.end(), header.begin(), header.end());
    out.insert(out.end(), image.begin(), image.end());
    return out;
}

base::Result<UnpackedFrame> unpack_frame(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < prefix_bytes || std::memcmp(bytes.data(), magic, 4) != 0) {
        return bad_frame("not a Penumbra frame (magic PNBF missing)");
    }
    const auto version = static_cast<int>(bytes[4] | (bytes[5] << 8));
    if (version != protocol_version) {
        return bad_frame("frame version " + std::to_string(version) + " is not supported");
    }
    const std::uint32_t length = static_cast<std::uint32_t>(bytes[6]) |
                                 (static_cast<std::uint32_t>(bytes[7]) << 8) |
                                 (static_cast<std::uint32_t>(bytes[8]) << 16) |
                                 (static_cast<std::uint32_t>(bytes[9]) << 24);
    if (length > bytes.size() - prefix_bytes) {
        return bad_frame("header length exceeds the message");
    }
    UnpackedFrame out;
    out.header_json.assign(reinterpret_cast<const char*>(bytes.data() + prefix_bytes), length);
    const json j = json::parse(out.header_json, nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
        return bad_frame("header is not a JSON object");
    }
    try {
        FrameHeader& h = out.header;
        h.frame = j.at("frame").get<std::uint64_t>();
        h.request = j.at("request").get<std::int64_t>();
        h.session = j.at("session").get<std::string>();
        h.width = j.at("width").get<int>();
        h.height = j.at("height").get<int>();
        h.encoding = j.at("encoding").get<std::string>();
        h.independent = j.value("independent", true);
        h.mode = j.at("mode").get<std::string>();
        h.interactive = j.at("interactive").get<bool>();
        h.light_buffer = j.at("light_buffer").get<std::string>();
        for (const auto& pass : j.at("passes")) {
            h.passes.push_back({pass.at("name").get<std::string>(), pass.at("gpu_ms").get<double>(),
                                pass.at("wall_ms").get<double>()});
        }
        const json& t = j.at("timings");
        h.queued_ms = t.at("queued_ms").get<double>();
        h.render_ms = t.at("render_ms").get<double>();
        h.readback_ms = t.at("readback_ms").get<double>();
        h.encode_ms = t.at("encode_ms").get<double>();
        h.quality = j.at("quality").get<std::string>();
        h.refinement = j.value("refinement", 0);
        h.refining = j.value("refining", false);
        h.preview = j.value("preview", false);
    } catch (const json::exception& e) {
        return bad_frame(std::string("header field missing or of the wrong type: ") + e.what());
    }
    out.image.assign(bytes.begin() + static_cast<std::ptrdiff_t>(prefix_bytes + length),
                     bytes.end());
    return out;
}

}  // namespace penumbra::protocol
