#pragma once

// Sample types found in volume files and their conversion to the types a Volume keeps. Private to
// the volume module.

#include <penumbra/volume/volume.hpp>

#include <algorithm>
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
        case SampleType::int16:
            return VoxelType::int16;
        default:
            return VoxelType::float32;
    }
}

inline bool is_kept(SampleType type) {
    return type == SampleType::uint8 || type == SampleType::uint16 || type == SampleType::int16 ||
           type == SampleType::float32;
}

inline bool is_whole(double value) {
    return std::isfinite(value) && value == std::round(value);
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
inline void convert_to_float32(SampleType type, std::span<const std::byte> in,
                               std::span<std::byte> out, double slope, double inter) {
    switch (type) {
        case SampleType::int8:
            return convert_samples_to_float32<std::int8_t>(in, out, slope, inter);
        case SampleType::uint8:
            return convert_samples_to_float32<std::uint8_t>(in, out, slope, inter);
        case SampleType::int16:
            return convert_samples_to_float32<std::int16_t>(in, out, slope, inter);
        case SampleType::uint16:
            return convert_samples_to_float32<std::uint16_t>(in, out, slope, inter);
        case SampleType::int32:
            return convert_samples_to_float32<std::int32_t>(in, out, slope, inter);
        case SampleType::uint32:
            return convert_samples_to_float32<std::uint32_t>(in, out, slope, inter);
        case SampleType::int64:
            return convert_samples_to_float32<std::int64_t>(in, out, slope, inter);
        case SampleType::uint64:
            return convert_samples_to_float32<std::uint64_t>(in, out, slope, inter);
        case SampleType::float32:
            return convert_samples_to_float32<float>(in, out, slope, inter);
        case SampleType::float64:
            return convert_samples_to_float32<double>(in, out, slope, inter);
    }
}

// How a file's samples become a Volume's data. A rescale (sample * slope + inter) of integers on
// a kept integer type stays a Volume::Rescale, exact without widening the data; any other rescale
// is applied at load into float32.
struct SampleLayout {
    SampleType type = SampleType::uint8;
    std::uint64_t voxels = 0;
    bool big_endian = false;
    double slope = 1.0;
    double inter = 0.0;

    [[nodiscard]] bool kept_with_rescale() const {
        return is_kept(type) && type != SampleType::float32 && is_whole(slope) && slope != 0.0 &&
               is_whole(inter);
    }

    // Whether the samples are converted with the rescale applied.
    [[nodiscard]] bool scaled() const {
        return !(slope == 1.0 && inter == 0.0) && !kept_with_rescale();
    }

    // The type the volume keeps: the sample type where it is kept and not converted, else
    // float32.
    [[nodiscard]] VoxelType stored() const {
        return scaled() ? VoxelType::float32 : stored_type(type);
    }

    // The rescale the volume keeps (identity where the samples were converted).
    [[nodiscard]] Rescale rescale() const {
        return kept_with_rescale() ? Rescale{slope, inter} : Rescale{};
    }

    [[nodiscard]] std::uint64_t file_bytes() const { return voxels * sample_size(type); }

    [[nodiscard]] std::uint64_t stored_bytes() const { return voxels * bytes_per_voxel(stored()); }
};

// Bytes of converted samples staged at a time: what a load needs beyond the volume itself.
inline constexpr std::size_t conversion_chunk_bytes = std::size_t{1} << 20;

// Receives a file's samples in order and builds the volume's data from them, holding one copy of
// the volume: samples that are kept as they are go straight into the volume's buffer (byte order
// fixed in place at the end); others pass through a small staging buffer, converted chunk by
// chunk. A reader asks for window(), writes up to its size and calls commit() with the count.
class SampleSink {
public:
    explicit SampleSink(const SampleLayout& layout)
        : layout_(layout)
        , direct_(!layout.scaled() && is_kept(layout.type))
        , data_(layout.stored_bytes()) {
        if (!direct_) {
            const std::size_t width = sample_size(layout.type);
            staging_.resize(conversion_chunk_bytes / width * width);
        }
    }

    // Where the next bytes go; empty once every expected byte has arrived.
    [[nodiscard]] std::span<std::byte> window() {
        const std::uint64_t left = layout_.file_bytes() - received_;
        if (direct_) {
            return std::span<std::byte>(data_).subspan(static_cast<std::size_t>(received_));
        }
        const std::size_t room = std::min<std::uint64_t>(staging_.size() - staged_, left);
        return std::span<std::byte>(staging_).subspan(staged_, room);
    }

    void commit(std::size_t bytes) {
        received_ += bytes;
        if (direct_) {
            return;
        }
        staged_ += bytes;
        if (staged_ == staging_.size() || received_ == layout_.file_bytes()) {
            flush();
        }
    }

    [[nodiscard]] std::uint64_t received() const { return received_; }

    [[nodiscard]] bool full() const { return received_ == layout_.file_bytes(); }

    // The volume's data; call once, when full().
    std::vector<std::byte> take() {
        if (direct_ && layout_.big_endian) {
            byteswap_samples(data_, sample_size(layout_.type));
        }
        return std::move(data_);
    }

private:
    void flush() {
        const std::size_t width = sample_size(layout_.type);
        const std::size_t whole = staged_ / width * width;
        const std::span<std::byte> samples = std::span<std::byte>(staging_).first(whole);
        if (layout_.big_endian) {
            byteswap_samples(samples, width);
        }
        const std::size_t out_bytes = whole / width * sizeof(float);
        convert_to_float32(layout_.type, samples,
                           std::span<std::byte>(data_).subspan(written_, out_bytes), layout_.slope,
                           layout_.inter);
        written_ += out_bytes;
        // A partial sample (a read that stopped mid-sample) waits for the rest of its bytes.
        std::memmove(staging_.data(), staging_.data() + whole, staged_ - whole);
        staged_ -= whole;
    }

    SampleLayout layout_;
    bool direct_;
    std::vector<std::byte> data_;
    std::vector<std::byte> staging_;
    std::size_t staged_ = 0;
    std::uint64_t received_ = 0;
    std::size_t written_ = 0;
};

}  // namespace penumbra::volume::detail
