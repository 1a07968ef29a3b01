// Light directions that put slicing and shading on their degenerate paths: along the axes (slice
// planes parallel to faces), along face and main diagonals (planes through edges and corners),
// equal and opposite to the view (half-angle's flip, a zero Blinn-Phong half vector), and random
// directions with a printed seed. Every mode, every frame checked (stability.hpp).

#include "stability.hpp"

#include <glm/geometric.hpp>

#include <vector>

namespace penumbra::stability {
namespace {

class LightDirectionTest : public ModeTest {
protected:
    void SetUp() override {
        ModeTest::SetUp();
        use(float_volume(glm::uvec3(24), glm::dvec3(1.0), radial));
    }

    // Every direction under a generic camera and under one looking down -y (the default camera),
    // with and without Blinn-Phong on top of shadows.
    void check_directions(const std::vector<glm::dvec3>& directions) {
        for (const glm::dvec3& direction : directions) {
            for (const bool axis_camera : {false, true}) {
                auto request = base_request(mode(), 17);
                if (axis_camera) {
                    request.camera = scene::Camera{};
                }
                request.light.direction = direction;
                for (const bool phong : {false, true}) {
                    request.settings.phong = phong;
                    render_and_check(request);
                    if (phong && mode() == scene::Mode::dvr) {
                        break;  // dvr never shades
                    }
                }
            }
        }
    }

    // "Equal to the view": the light sits behind the viewer and shines along the view direction;
    // "opposite": it sits behind the volume and shines at the viewer. The image is 17 pixels wide
    // so the centre pixel's ray is exactly the view direction.
    void check_light_along_view(double sign) {
        for (const bool axis_camera : {true, false}) {
            auto request = base_request(mode(), 17);
            if (axis_camera) {
                request.camera = scene::Camera{};
            }
            const glm::dvec3 to_eye = glm::normalize(request.camera.eye - request.camera.target);
            for (const bool point : {false, true}) {
                request.light.type =
                        point ? scene::LightType::point : scene::LightType::directional;
                request.light.direction = sign * to_eye;
                request.light.position = sign * 3.0 * to_eye;
                for (const bool phong : {false, true}) {
                    request.settings.phong = phong;
                    for (const auto builder : {scene::LightBufferBuilder::multi_slice,
                                               scene::LightBufferBuilder::per_slice}) {
                        request.settings.light_buffer.builder = builder;
                        render_and_check(request);
                    }
                }
            }
        }
    }
};

std::vector<glm::dvec3> signed_permutations(glm::dvec3 v) {
    std::vector<glm::dvec3> out;
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 p(v[axis], v[(axis + 1) % 3], v[(axis + 2) % 3]);
        for (int signs = 0; signs < 8; ++signs) {
            const glm::dvec3 q((signs & 1) ? -p.x : p.x, (signs & 2) ? -p.y : p.y,
                               (signs & 4) ? -p.z : p.z);
            bool seen = false;
            for (const auto& o : out) {
                seen = seen || o == q;
            }
            if (!seen) {
                out.push_back(q);
            }
        }
    }
    return out;
}

TEST_F(LightDirectionTest, LightAlongEachAxisGivesASaneImage) {
    const auto directions = signed_permutations({1.0, 0.0, 0.0});
    ASSERT_EQ(directions.size(), 6u);
    for_each_mode(all_modes, [&] { check_directions(directions); });
}

TEST_F(LightDirectionTest, LightAlongEachFaceDiagonalGivesASaneImage) {
    const auto directions = signed_permutations({1.0, 1.0, 0.0});
    ASSERT_EQ(directions.size(), 12u);
    for_each_mode(all_modes, [&] { check_directions(directions); });
}

TEST_F(LightDirectionTest, LightAlongEachMainDiagonalGivesASaneImage) {
    const auto directions = signed_permutations({1.0, 1.0, 1.0});
    ASSERT_EQ(directions.size(), 8u);
    for_each_mode(all_modes, [&] { check_directions(directions); });
}

TEST_F(LightDirectionTest, LightEqualToTheViewDirectionGivesASaneImage) {
    for_each_mode(all_modes, [&] { check_light_along_view(1.0); });
}

TEST_F(LightDirectionTest, LightOppositeToTheViewDirectionGivesASaneImage) {
    for_each_mode(all_modes, [&] { check_light_along_view(-1.0); });
}

// Property: any direction, any compositing, Blinn-Phong on or off, either builder.
TEST_F(LightDirectionTest, RandomLightDirectionsGiveSaneImages) {
    for_each_mode(all_modes, [&] {
        const std::uint64_t seed = property_seed(0x5eed'11947);
        SCOPED_TRACE("seed " + std::to_string(seed) +
                     " (replay with PENUMBRA_STABILITY_SEED=" + std::to_string(seed) + ")");
        std::mt19937_64 rng(seed);
        for (int i = 0; i < 10; ++i) {
            auto request = base_request(mode(), 16);
            request.light.direction = random_direction(rng);
            request.camera =
                    scene::orbit_camera(std::uniform_real_distribution<double>(0, 360)(rng),
                                        std::uniform_real_distribution<double>(-80, 80)(rng), 2.4);
            request.settings.phong = (rng() & 1) != 0;
            request.settings.compositing =
                    (rng() & 1) != 0 ? scene::Compositing::alpha : scene::Compositing::extinction;
            request.settings.light_buffer.builder = (rng() & 1) != 0
                                                            ? scene::LightBufferBuilder::multi_slice
                                                            : scene::LightBufferBuilder::per_slice;
            SCOPED_TRACE("draw " + std::to_string(i));
            render_and_check(request);
        }
    });
}

}  // namespace
}  // namespace penumbra::stability
