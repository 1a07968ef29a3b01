#pragma once

// Sample types found in volume files and their conversion to the types a Volume keeps. Private to
// the volume module.

#include <penumbra/volume/volume.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace penumbra::volume::detail {

enum class SampleType {
    int8,
    uint8,
    int16,
    uint16,
    int32,
    uint32,
    int64,
    uint64,
    float32,
    float64
};

inline std::size_t sample_size(SampleType type) {
    switch (type) {
        case SampleType::int8:
        case SampleType::uint8:
            return 1;
        case SampleType::int16:
        case SampleType::uint16:
            return 2;
        case SampleType::int32:
        case SampleType::uint32:
        case SampleType::float32:
            return 4;
        case SampleType::int64:
        case SampleType::uint64:
        case SampleType::float64:
            return 8;
    }
    return 1;
}

inline const char* sample_name(SampleType type) {
    switch (type) {
        case SampleType::int8:
            return "int8";
        case SampleType::uint8:
            return "uint8";
        case SampleType::int16:
            return "int16";
        case SampleType::uint16:
            return "uint16";
        case SampleType::int32:
            return "int32";
        case SampleType::uint32:
            return "uint32";
        case SampleType::int64:
            return "int64";
        case SampleType::uint64:
            return "uint64";
        case SampleType::float32:
            return "float32";
        case SampleType::float64:
            return "float64";
    }
    return "?";
}

// The type a Volume keeps for samples of `type`: the GPU-friendly types as they are, all others
// as float32.
inline VoxelType stored_type(SampleType type) {
    switch (type) {
        case SampleType::uint8:
            return VoxelType::uint8;
        case SampleType::uint16:
            return VoxelType::uint16;
        default:
            return VoxelType::float32;
    }
}

inline bool is_kept(SampleType type) {
    return type == SampleType::uint8 || type == SampleType::uint16 || type == SampleType::float32;
}

// Reverses the byte order of each `width`-byte sample (big-endian files).
inline void byteswap_samples(std::span<std::byte> data, std::size_t width) {
    if (width < 2) {
        return;
    }
    for (std::size_t i = 0; i + width <= data.size(); i += width) {
        for (std::size_t a = i, b = i + width - 1; a < b; ++a, --b) {
            std::swap(data[a], data[b]);
        }
    }
}

template <class T>
void convert_samples_to_float32(std::span<const std::byte> in, std::span<std::byte> out,
                                double slope, double inter) {
    const std::size_t count = in.size() / sizeof(T);
    const bool identity = slope == 1.0 && inter == 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        T sample;
        std::memcpy(&sample, in.data() + i * sizeof(T), sizeof(T));
        double value = static_cast<double>(sample);
        if (!identity) {
            value = value * slope + inter;
        }
        // A finite double beyond float's range has no float value (the cast would be
        // undefined), so it becomes the infinity IEEE rounding gives; NaN stays NaN.
        constexpr float infinity = std::numeric_limits<float>::infinity();
        const float converted = std::abs(value) > std::numeric_limits<float>::max()
                                        ? (value > 0 ? infinity : -infinity)
                                        : static_cast<float>(value);
        std::memcpy(out.data() + i * sizeof(float), &converted, sizeof(float));
    }
}

// Converts native-order samples to float32 as value * slope + inter, computed in double so that
// wide integers lose precision only once. Values beyond float's range become ±Inf, which
// make_volume then counts as non-finite.
inline std::vector<std::byte> to_float32(SampleType type, std::span<const std::byte> in,
                                         double slope = 1.0, double inter = 0.0) {
    std::vector<std::byte> out(in.size() / sample_size(type) * sizeof(float));
    switch (type) {
        case SampleType::int8:
            convert_samples_to_float32<std::int8_t>(in, out, slope, inter);
            break;
        case SampleType::uint8:
            convert_samples_to_float32<std::uint8_t>(in, out, slope, inter);
            break;
        case SampleType::int16:
            convert_samples_to_float32<std::int16_t>(in, out, slope, inter);
            break;
        case SampleType::uint16:
            convert_samples_to_float32<std::uint16_t>(in, out, slope, inter);
            break;
        case SampleType::int32:
            convert_samples_to_float32<std::int32_t>(in, out, slope, inter);
            break;
        case SampleType::uint32:
            convert_samples_to_float32<std::uint32_t>(in, out, slope, inter);
            break;
        case SampleType::int64:
            convert_samples_to_float32<std::int64_t>(in, out, slope, inter);
            break;
        case SampleType::uint64:
            convert_samples_to_float32<std::uint64_t>(in, out, slope, inter);
            break;
        case SampleType::float32:
            convert_samples_to_float32<float>(in, out, slope, inter);
            break;
        case SampleType::float64:
            convert_samples_to_float32<double>(in, out, slope, inter);
            break;
    }
    return out;
}

// The bytes a Volume stores for native-order samples: the buffer itself when the type is kept,
// float32 otherwise.
inline std::vector<std::byte> to_stored(SampleType type, std::vector<std::byte> samples) {
    if (is_kept(type)) {
        return samples;
    }
    return to_float32(type, samples);
}

}  // namespace penumbra::volume::detail
