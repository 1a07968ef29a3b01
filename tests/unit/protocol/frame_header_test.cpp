#include <penumbra/protocol/frame_header.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::protocol {
namespace {

FrameHeader sample_header() {
    FrameHeader h;
    h.frame = 17;
    h.request = 12345678901234LL;
    h.session = "s1";
    h.width = 640;
    h.height = 480;
    h.encoding = "jpeg";
    h.mode = "sbrc_cone";
    h.interactive = true;
    h.light_buffer = "reused";
    h.passes = {{"light_buffer", -1.0, 0.25}, {"raycast", 3.5, 3.75}};
    h.queued_ms = 0.5;
    h.render_ms = 4.25;
    h.readback_ms = 0.75;
    h.encode_ms = 1.5;
    h.quality = "interactive: half resolution";
    return h;
}

const std::vector<std::uint8_t> image = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 0xFF, 0xD9};

std::uint32_t header_length(const std::vector<std::uint8_t>& bytes) {
    return bytes[6] | (bytes[7] << 8) | (bytes[8] << 16) |
           (static_cast<std::uint32_t>(bytes[9]) << 24);
}

void expect_invalid_frame(const std::vector<std::uint8_t>& bytes, const std::string& why) {
    const auto frame = unpack_frame(bytes);
    ASSERT_FALSE(frame.ok()) << why;
    EXPECT_EQ(frame.error().code, base::ErrorCode::invalid_frame) << why;
}

TEST(Frame, PackedFrameStartsWithMagicVersionAndHeaderLength) {
    const auto bytes = pack_frame(sample_header(), image);
    ASSERT_GE(bytes.size(), 10U);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "PNBF");
    EXPECT_EQ(bytes[4], 1);
    EXPECT_EQ(bytes[5], 0);
    const std::uint32_t length = header_length(bytes);
    EXPECT_EQ(bytes.size(), 10U + length + image.size());
    EXPECT_EQ(bytes[10], '{');
    EXPECT_EQ(bytes[10 + length - 1], '}');
}

TEST(Frame, UnpackReturnsWhatWasPacked) {
    const FrameHeader h = sample_header();
    const auto frame = unpack_frame(pack_frame(h, image));
    ASSERT_TRUE(frame.ok()) << frame.error().to_string();
    const FrameHeader& u = frame->header;
    EXPECT_EQ(u.frame, h.frame);
    EXPECT_EQ(u.request, h.request);
    EXPECT_EQ(u.session, h.session);
    EXPECT_EQ(u.width, h.width);
    EXPECT_EQ(u.height, h.height);
    EXPECT_EQ(u.encoding, h.encoding);
    EXPECT_EQ(u.mode, h.mode);
    EXPECT_EQ(u.interactive, h.interactive);
    EXPECT_EQ(u.light_buffer, h.light_buffer);
    ASSERT_EQ(u.passes.size(), h.passes.size());
    for (std::size_t i = 0; i < h.passes.size(); ++i) {
        EXPECT_EQ(u.passes[i].name, h.passes[i].name);
        EXPECT_EQ(u.passes[i].gpu_ms, h.passes[i].gpu_ms);
        EXPECT_EQ(u.passes[i].wall_ms, h.passes[i].wall_ms);
    }
    EXPECT_EQ(u.queued_ms, h.queued_ms);
    EXPECT_EQ(u.render_ms, h.render_ms);
    EXPECT_EQ(u.readback_ms, h.readback_ms);
    EXPECT_EQ(u.encode_ms, h.encode_ms);
    EXPECT_EQ(u.quality, h.quality);
    EXPECT_EQ(frame->image, image);
    EXPECT_EQ(frame->header_json.front(), '{');
}

TEST(Frame, EmptyImageAndNoRequestRoundTrip) {
    FrameHeader h = sample_header();
    h.request = -1;
    h.passes.clear();
    const auto frame = unpack_frame(pack_frame(h, {}));
    ASSERT_TRUE(frame.ok());
    EXPECT_EQ(frame->header.request, -1);
    EXPECT_TRUE(frame->header.passes.empty());
    EXPECT_TRUE(frame->image.empty());
}

TEST(Frame, RejectsFramesCutBeforeTheEndOfTheHeader) {
    const auto bytes = pack_frame(sample_header(), image);
    const std::size_t header_end = 10 + header_length(bytes);
    for (std::size_t size = 0; size < header_end; ++size) {
        expect_invalid_frame({bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(size)},
                             "cut at " + std::to_string(size));
    }
}

TEST(Frame, RejectsWrongMagicVersionOrLength) {
    const auto good = pack_frame(sample_header(), image);
    auto magic = good;
    magic[3] = 'X';
    expect_invalid_frame(magic, "magic");
    auto version = good;
    version[4] = 2;
    expect_invalid_frame(version, "version 2");
    auto high_version = good;
    high_version[5] = 1;
    expect_invalid_frame(high_version, "version 257");
    auto length = good;
    length[9] = 0x7F;
    expect_invalid_frame(length, "header length beyond the message");
}

TEST(Frame, RejectsHeadersThatAreNotTheFrameHeaderObject) {
    const auto frame_with = [](const std::string& header) {
        std::vector<std::uint8_t> bytes = {'P', 'N', 'B', 'F', 1, 0};
        const auto n = static_cast<std::uint32_t>(header.size());
        for (int i = 0; i < 4; ++i) {
            bytes.push_back(static_cast<std::uint8_t>((n >> (8 * i)) & 0xFF));
        }
        bytes.insert(bytes.end(), header.begin(), header.end());
        return bytes;
    };
    expect_invalid_frame(frame_with(""), "empty header");
    expect_invalid_frame(frame_with("{\"frame\":"), "cut JSON");
    expect_invalid_frame(frame_with("[1,2,3]"), "array");
    expect_invalid_frame(frame_with("{}"), "no members");
    const auto good = unpack_frame(pack_frame(sample_header(), image));
    ASSERT_TRUE(good.ok());
    std::string wrong_type = good->header_json;
    const auto at = wrong_type.find("\"width\":640");
    ASSERT_NE(at, std::string::npos);
    wrong_type.replace(at, 11, "\"width\":\"640\"");
    expect_invalid_frame(frame_with(wrong_type), "width as a string");
}

TEST(Frame, RejectsGarbage) {
    std::vector<std::uint8_t> bytes(64);
    std::uint32_t x = 12345;
    for (auto& b : bytes) {
        x = x * 1103515245U + 12345U;
        b = static_cast<std::uint8_t>(x >> 24);
    }
    expect_invalid_frame(bytes, "random bytes");
    expect_invalid_frame({'P', 'N', 'B', 'F', 1, 0, 0xFF, 0xFF, 0xFF, 0xFF}, "huge length");
}

}  // namespace
}  // namespace penumbra::protocol
