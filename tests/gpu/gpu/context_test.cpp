#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>

#include <gtest/gtest.h>

namespace penumbra::gpu {
namespace {

TEST(Context, CreatesAHeadlessOpenGl45CoreContext) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const ContextInfo& info = context->info();
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_TRUE(info.platform == "EGL_EXT_platform_device" ||
                info.platform == "EGL_MESA_platform_surfaceless")
            << info.platform;
    EXPECT_GE(info.max_3d_texture_size, 256);
    EXPECT_GE(info.max_array_texture_layers, 256);
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
}

TEST(Objects, OwnershipMovesAndResetDeletes) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok());
    Texture a = create_texture(GL_TEXTURE_2D);
    const GLuint name = a.name();
    ASSERT_NE(name, 0u);
    EXPECT_TRUE(glIsTexture(name));
    Texture b = std::move(a);
    EXPECT_EQ(a.name(), 0u);  // NOLINT(bugprone-use-after-move): checking the moved-from state
    EXPECT_EQ(b.name(), name);
    b.reset();
    EXPECT_FALSE(glIsTexture(name));
    Buffer buffer = create_buffer();
    const GLuint released = buffer.release();
    EXPECT_FALSE(buffer);
    EXPECT_TRUE(glIsBuffer(released));
    glDeleteBuffers(1, &released);
}

}  // namespace
}  // namespace penumbra::gpu
