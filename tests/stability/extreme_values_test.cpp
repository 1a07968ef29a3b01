// Voxel values at the edges of what the types hold: 16-bit volumes over the full range and over a
// narrow range at the top, float volumes spanning ±1e30 and nearly ±FLT_MAX, ranges 1e-30 wide,
// a narrow range far from zero, NaN and ±Inf voxels, all-NaN and constant volumes. The TF sees
// values normalised to the volume's range, so an affinely rescaled volume must look exactly like
// the original: every mode is checked against the unit volume's image as well as by the checks
// of stability.hpp (CPU reference included).

#include "stability.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace penumbra::stability {
namespace {

constexpr glm::uvec3 dims{20, 20, 20};

// Radial, stretched so its range is exactly [0, 1].
std::vector<float> unit_values() {
    std::vector<float> values;
    values.reserve(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 0; y < dims.y; ++y) {
            for (unsigned x = 0; x < dims.x; ++x) {
                values.push_back(radial((glm::dvec3(x, y, z) + 0.5) / glm::dvec3(dims)));
            }
        }
    }
    float largest = 0.0f;
    for (const float v : values) {
        largest = std::max(largest, v);
    }
    for (float& v : values) {
        v /= largest;
    }
    return values;
}

volume::Volume make_float(const std::vector<float>& values) {
    auto made = volume::make_volume("extreme", dims, glm::dvec3(1.0), values);
    EXPECT_TRUE(made.ok()) << made.error().to_string();
    return made.ok() ? std::move(made.value()) : volume::Volume{};
}

// The unit volume mapped by v -> offset + scale * v in float.
volume::Volume scaled_float(double offset, double scale) {
    std::vector<float> values = unit_values();
    for (float& v : values) {
        v = static_cast<float>(offset + scale * static_cast<double>(v));
    }
    return make_float(values);
}

// The unit volume mapped to 16 bits: offset + scale * v, rounded.
volume::Volume scaled_uint16(double offset, double scale) {
    const std::vector<float> values = unit_values();
    std::vector<std::byte> bytes(values.size() * 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        const auto v = static_cast<std::uint16_t>(
                std::lround(offset + scale * static_cast<double>(values[i])));
        std::memcpy(&bytes[i * 2], &v, 2);
    }
    auto made = volume::make_volume("extreme16", dims, glm::dvec3(1.0), volume::VoxelType::uint16,
                                    std::move(bytes));
    EXPECT_TRUE(made.ok()) << made.error().to_string();
    return made.ok() ? std::move(made.value()) : volume::Volume{};
}

class ExtremeValuesTest : public ModeTest {
protected:
    std::vector<scene::FrameRequest> requests() const {
        std::vector<scene::FrameRequest> out;
        auto request = base_request(mode(), 16);
        out.push_back(request);
        request.settings.phong = true;
        request.light.direction = {1.0, 1.0, 1.0};
        request.settings.compositing = scene::Compositing::extinction;
        out.push_back(request);
        // The ray caster as a fragment shader (the slicing modes ignore the stage).
        request.settings.stage = scene::RaycastStage::fragment;
        out.push_back(request);
        return out;
    }

    // Renders the unit volume's frames once per mode, for comparison.
    void render_unit_frames() {
        use(make_float(unit_values()));
        for (const auto& request : requests()) {
            auto frame = render(request);
            ASSERT_TRUE(frame.has_value());
            unit_frames_[mode()].push_back(std::move(frame->image));
        }
    }

    // `volume` holds the unit volume's values up to an affine map (and `levels` of rounding of the
    // normalised value, in 8-bit image levels): every frame passes the stability checks and
    // differs from the unit volume's by at most `levels` per channel.
    void expect_like_unit(const volume::Volume& volume, const std::string& label, int levels = 1) {
        SCOPED_TRACE(label);
        if (unit_frames_[mode()].empty()) {
            render_unit_frames();
        }
        use(volume);
        const auto all = requests();
        for (std::size_t i = 0; i < all.size(); ++i) {
            auto frame = render_and_check(all[i]);
            ASSERT_TRUE(frame.has_value());
            int worst = 0;
            int worst_x = 0;
            int worst_y = 0;
            for (int y = 0; y < frame->image.height; ++y) {
                for (int x = 0; x < frame->image.width; ++x) {
                    for (int c = 0; c < 3; ++c) {
                        const int d = std::abs(int{frame->image.pixel(x, y)[c]} -
                                               int{unit_frames_[mode()][i].pixel(x, y)[c]});
                        if (d > worst) {
                            worst = d;
                            worst_x = x;
                            worst_y = y;
                        }
                    }
                }
            }
            EXPECT_LE(worst, levels)
                    << describe(all[i]) << ": differs from the unit volume's "
                    << "image by " << worst << " levels at (" << worst_x << ", " << worst_y << ")";
        }
    }

    std::map<scene::Mode, std::vector<base::ImageRgba8>> unit_frames_;  // per mode
};

TEST_F(ExtremeValuesTest, Uint16OverTheFullRangeLooksLikeTheUnitVolume) {
    for_each_mode(all_modes, [&] {
        const volume::Volume volume = scaled_uint16(0.0, 65535.0);
        EXPECT_EQ(volume.range.min, 0.0);
        EXPECT_EQ(volume.range.max, 65535.0);
        expect_like_unit(volume, "uint16 0..65535");
    });
}

// 536 levels: the normalised value is rounded to 1/535, about half an 8-bit level of the TF.
TEST_F(ExtremeValuesTest, Uint16OverANarrowRangeAtTheTopLooksLikeTheUnitVolume) {
    for_each_mode(all_modes, [&] {
        const volume::Volume volume = scaled_uint16(65000.0, 535.0);
        EXPECT_EQ(volume.range.max, 65535.0);
        // Central differences see the 1/535 rounding of two voxels at once; at the jittered
        // sample positions one difference of a shaded pixel straddles one more rounding step
        // than at the midpoints (4 levels at one pixel of `phong`, 2 elsewhere).
        expect_like_unit(volume, "uint16 65000..65535",
                         scene::uses_gradients(base_request(mode()).settings) ? 4 : 2);
    });
}

TEST_F(ExtremeValuesTest, FloatSpanningPlusMinus1e30LooksLikeTheUnitVolume) {
    for_each_mode(all_modes,
                  [&] { expect_like_unit(scaled_float(-1e30, 2e30), "float -1e30..1e30"); });
}

// Nearly the whole float range: the range's width (6e38) overflows float, and 1 / width is below
// the smallest normal float.
TEST_F(ExtremeValuesTest, FloatSpanningNearlyTheWholeFloatRangeLooksLikeTheUnitVolume) {
    for_each_mode(all_modes, [&] {
        const double big = 3.0e38;
        expect_like_unit(scaled_float(-big, 2.0 * big), "float -3e38..3e38");
    });
}

TEST_F(ExtremeValuesTest, FloatRange1e30WideLooksLikeTheUnitVolume) {
    for_each_mode(all_modes, [&] {
        expect_like_unit(scaled_float(0.0, 1e-30), "float 0..1e-30");
        expect_like_unit(scaled_float(1e-28, 1e-30), "float 1e-28..1.01e-28");
    });
}

// A range of 1 at 1000: float steps of 6e-5 there, below the TF's resolution.
TEST_F(ExtremeValuesTest, FloatRangeFarFromZeroLooksLikeTheUnitVolume) {
    for_each_mode(all_modes, [&] {
        expect_like_unit(scaled_float(1000.0, 1.0), "float 1000..1001");
        expect_like_unit(scaled_float(-1000.0, 1.0), "float -1000..-999");
    });
}

// A range of 100 at -5e6, where floats step by 0.5: the voxels themselves hold the normalised
// value only to 1/200. The renderer normalises float volumes before interpolating, so samples
// lose nothing more (render_and_check holds them to the CPU reference at 3/255); but central
// differences one voxel apart turn the data's own 1/200 steps into normal directions that differ
// from the unit volume's where gradients are weak, which moves shaded pixels by a few levels.
TEST_F(ExtremeValuesTest, FloatNarrowRangeAtAHugeOffsetLooksLikeTheUnitVolume) {
    for_each_mode(all_modes,
                  [&] { expect_like_unit(scaled_float(-5e6, 100.0), "float -5e6..-4.9999e6", 8); });
}

// NaN and ±Inf voxels are replaced by the finite minimum when the volume is made; the frame must
// then equal exactly that of a volume holding the minimum there in the first place.
TEST_F(ExtremeValuesTest, NanAndInfVoxelsRenderLikeTheFiniteMinimum) {
    for_each_mode(all_modes, [&] {
        std::vector<float> values = unit_values();
        std::vector<float> cleaned = values;
        const float inf = std::numeric_limits<float>::infinity();
        const float specials[] = {std::numeric_limits<float>::quiet_NaN(), inf, -inf,
                                  std::numeric_limits<float>::signaling_NaN()};
        std::size_t planted = 0;
        // A block in the dense middle and a scatter of single voxels.
        for (unsigned z = 8; z < 12; ++z) {
            for (unsigned y = 9; y < 11; ++y) {
                for (unsigned x = 6; x < 14; ++x) {
                    const std::size_t i = (static_cast<std::size_t>(z) * dims.y + y) * dims.x + x;
                    values[i] = specials[planted % 4];
                    cleaned[i] = 0.0f;
                    ++planted;
                }
            }
        }
        for (std::size_t i = 7; i < values.size(); i += 97) {
            if (std::isfinite(values[i])) {
                values[i] = specials[planted % 4];
                cleaned[i] = 0.0f;
                ++planted;
            }
        }
        const volume::Volume dirty = make_float(values);
        EXPECT_EQ(dirty.nonfinite_voxels, planted);
        EXPECT_EQ(dirty.range.min, 0.0);
        EXPECT_EQ(dirty.range.max, make_float(cleaned).range.max);
        use(make_float(cleaned));
        std::vector<base::ImageRgba8> clean_frames;
        for (const auto& request : requests()) {
            auto frame = render(request);
            ASSERT_TRUE(frame.has_value());
            clean_frames.push_back(std::move(frame->image));
        }
        use(dirty);
        const auto all = requests();
        for (std::size_t i = 0; i < all.size(); ++i) {
            auto frame = render_and_check(all[i]);
            ASSERT_TRUE(frame.has_value());
            EXPECT_EQ(frame->image.pixels, clean_frames[i].pixels) << describe(all[i]);
        }
    });
}

// With huge finite values around the NaNs, the replacement must not break the range either.
TEST_F(ExtremeValuesTest, NanVoxelsInAHugeRangeVolumeStayFinite) {
    for_each_mode(all_modes, [&] {
        std::vector<float> values = unit_values();
        for (float& v : values) {
            v = static_cast<float>(-1e30 + 2e30 * static_cast<double>(v));
        }
        for (std::size_t i = 0; i < values.size(); i += 13) {
            values[i] = std::numeric_limits<float>::quiet_NaN();
        }
        const volume::Volume volume = make_float(values);
        EXPECT_GT(volume.nonfinite_voxels, 0u);
        EXPECT_TRUE(std::isfinite(volume.range.min) && std::isfinite(volume.range.max));
        use(volume);
        for (const auto& request : requests()) {
            render_and_check(request);
        }
    });
}

// No finite voxel at all: the volume is constant (range [0, 0]) and classifies as value 0.
TEST_F(ExtremeValuesTest, AllNanVolumeIsConstant) {
    for_each_mode(all_modes, [&] {
        const volume::Volume volume =
                make_float(std::vector<float>(static_cast<std::size_t>(dims.x) * dims.y * dims.z,
                                              std::numeric_limits<float>::quiet_NaN()));
        EXPECT_EQ(volume.nonfinite_voxels, volume.voxel_count());
        EXPECT_EQ(volume.range.min, volume.range.max);
        use(volume);
        for (auto request : requests()) {
            CheckOptions hidden;
            hidden.expect_background = true;
            render_and_check(request, hidden);
            request.transfer_function = visible_at_zero();
            CheckOptions shown;
            shown.min_visible_fraction = 0.2;
            render_and_check(request, shown);
        }
    });
}

TEST_F(ExtremeValuesTest, ConstantVolumesClassifyAsTheirMinimum) {
    for_each_mode(all_modes, [&] {
        const auto constant_uint16 = [] {
            std::vector<std::byte> bytes(static_cast<std::size_t>(dims.x) * dims.y * dims.z * 2,
                                         std::byte{0xff});
            return volume::make_volume("max16", dims, glm::dvec3(1.0), volume::VoxelType::uint16,
                                       std::move(bytes))
                    .value();
        };
        const std::vector<std::pair<std::string, volume::Volume>> volumes = {
                {"float 3e38", make_float(std::vector<float>(unit_values().size(), 3e38f))},
                {"float -1e-38", make_float(std::vector<float>(unit_values().size(), -1e-38f))},
                {"uint16 65535", constant_uint16()}};
        for (const auto& [label, volume] : volumes) {
            SCOPED_TRACE(label);
            use(volume);
            for (auto request : requests()) {
                CheckOptions hidden;
                hidden.expect_background = true;
                render_and_check(request, hidden);
                request.transfer_function = visible_at_zero();
                CheckOptions shown;
                shown.min_visible_fraction = 0.2;
                render_and_check(request, shown);
            }
        }
    });
}

}  // namespace
}  // namespace penumbra::stability
