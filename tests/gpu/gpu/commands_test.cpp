// The texture helpers the render passes use: content goes up and comes back as packed rows.

#include <penumbra/gpu/commands.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace penumbra::gpu {
namespace {

TEST(Commands, RowsOfAnyWidthGoUpAndComeBackPacked) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    // Rows of 3 bytes: a 4-byte alignment would pad each one.
    std::vector<std::uint8_t> voxels(3 * 2 * 2);
    std::iota(voxels.begin(), voxels.end(), std::uint8_t{1});
    const Texture texture = create_texture_3d(GL_R8, 3, 2, 2);
    upload_3d(texture, 3, 2, 2, GL_RED, GL_UNSIGNED_BYTE, voxels.data());
    std::vector<std::uint8_t> back(voxels.size());
    read_texture(texture, GL_RED, GL_UNSIGNED_BYTE, std::as_writable_bytes(std::span(back)));
    EXPECT_EQ(back, voxels);
    EXPECT_EQ(take_error(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(Commands, ALayerCopiedIntoAnArrayReadsBackAlone) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const Texture layers = create_texture_array(GL_R32F, 5, 3, 2);
    clear(layers, {0.25f, 0.0f, 0.0f, 0.0f});
    const Texture layer = create_texture_2d(GL_R32F, 5, 3);
    clear(layer, {0.75f, 0.0f, 0.0f, 0.0f});
    copy_into_layer(layer, layers, 1, 5, 3);
    std::array<float, 15> values{};
    read_texture_layer(layers, 0, 5, 3, GL_RED, GL_FLOAT,
                       std::as_writable_bytes(std::span(values)));
    EXPECT_EQ(values, (std::array<float, 15>{0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f,
                                             0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f}));
    read_texture_layer(layers, 1, 5, 3, GL_RED, GL_FLOAT,
                       std::as_writable_bytes(std::span(values)));
    EXPECT_EQ(values[0], 0.75f);
    EXPECT_EQ(values[14], 0.75f);
    EXPECT_EQ(take_error(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(Commands, ACoveringDispatchHasAGroupForEveryInvocation) {
    const Groups groups = groups_covering(8, 17, 8);
    EXPECT_EQ(groups.x, 3u);
    EXPECT_EQ(groups.y, 1u);
    EXPECT_EQ(groups.z, 1u);
    EXPECT_EQ(groups_covering(4, 1, 4, 9).z, 3u);
}

}  // namespace
}  // namespace penumbra::gpu
