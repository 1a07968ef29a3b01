#include <penumbra/optics/shading.hpp>

#include <gtest/gtest.h>

namespace penumbra::optics {
namespace {

TEST(BlinnPhong, HeadOnLightGivesFullDiffuseAndSpecular) {
    const LightTerms t = blinn_phong({0, 0, 1}, {0, 0, 1}, {0, 0, 1}, 16.0);
    EXPECT_DOUBLE_EQ(t.diffuse, 1.0);
    EXPECT_DOUBLE_EQ(t.specular, 1.0);
}

TEST(BlinnPhong, IsTwoSided) {
    const LightTerms front = blinn_phong({0, 0, 1}, {0, 0, 1}, {0, 0, 1}, 8.0);
    const LightTerms back = blinn_phong({0, 0, -1}, {0, 0, 1}, {0, 0, 1}, 8.0);
    EXPECT_DOUBLE_EQ(front.diffuse, back.diffuse);
}

TEST(BlinnPhong, NoNormalMeansLitWithoutHighlight) {
    const LightTerms t = blinn_phong(glm::dvec3(0.0), {0, 0, 1}, {1, 0, 0}, 8.0);
    EXPECT_DOUBLE_EQ(t.diffuse, 1.0);
    EXPECT_DOUBLE_EQ(t.specular, 0.0);
}

TEST(Shade, CombinesAmbientDiffuseAndSpecular) {
    scene::Light light;
    light.color = {1.0, 0.5, 0.25};
    light.intensity = 2.0;
    light.ambient = 0.1;
    scene::Shading shading{0.5, 0.25, 8.0};
    const glm::dvec3 c = shade({1.0, 1.0, 0.0}, {0.5, 1.0}, light, shading);
    // radiance (2, 1, 0.5); tf * radiance * (0.1 + 0.25) + radiance * 0.25
    EXPECT_DOUBLE_EQ(c.r, 2.0 * 0.35 + 0.5);
    EXPECT_DOUBLE_EQ(c.g, 1.0 * 0.35 + 0.25);
    EXPECT_DOUBLE_EQ(c.b, 0.125);
}

}  // namespace
}  // namespace penumbra::optics
