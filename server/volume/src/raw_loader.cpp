// Open SciVis raw volumes: the file name carries everything (name_XxYxZ_type.raw[.gz]) and the
// file holds nothing but the little-endian samples, x fastest.

#include "file_io.hpp"
#include "file_name.hpp"
#include "memory_budget.hpp"
#include "samples.hpp"

#include <penumbra/volume/volume.hpp>

#include <array>
#include <charconv>
#include <optional>
#include <string_view>
#include <utility>

namespace penumbra::volume {
namespace {

using detail::SampleType;

constexpr const char* expected_pattern =
        "expected name_XxYxZ_type.raw or name_XxYxZ_type.raw.gz (e.g. "
        "engine_256x256x128_uint8.raw) with type uint8, uint16, int16, float32, float64, int8, "
        "uint32 or int32";

struct RawName {
    std::string name;
    glm::uvec3 dims{0};
    SampleType type = SampleType::uint8;
    bool gzip = false;
};

std::optional<SampleType> parse_sample_type(std::string_view text) {
    constexpr std::array<std::pair<std::string_view, SampleType>, 8> types{{
            {"uint8", SampleType::uint8},
            {"uint16", SampleType::uint16},
            {"int16", SampleType::int16},
            {"float32", SampleType::float32},
            {"float64", SampleType::float64},
            {"int8", SampleType::int8},
            {"uint32", SampleType::uint32},
            {"int32", SampleType::int32},
    }};
    for (const auto& [spelling, type] : types) {
        if (text == spelling) {
            return type;
        }
    }
    return std::nullopt;
}

std::optional<std::uint32_t> parse_extent(std::string_view text) {
    if (text.empty() || text.front() < '0' || text.front() > '9') {
        return std::nullopt;
    }
    std::uint32_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc{} || end != text.data() + text.size() || value == 0) {
        return std::nullopt;
    }
    return value;
}

std::optional<glm::uvec3> parse_dims(std::string_view text) {
    glm::uvec3 dims{0};
    for (int axis = 0; axis < 3; ++axis) {
        const std::size_t cut = axis < 2 ? text.find('x') : text.size();
        if (cut == std::string_view::npos) {
            return std::nullopt;
        }
        const auto extent = parse_extent(text.substr(0, cut));
        if (!extent) {
            return std::nullopt;
        }
        dims[axis] = *extent;
        text = axis < 2 ? text.substr(cut + 1) : std::string_view{};
    }
    return dims;
}

base::Result<RawName> parse_raw_name(const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) {
        return base::make_error(base::ErrorCode::bad_file_name, what + "; " + expected_pattern,
                                detail::at_file(path));
    };
    RawName parsed;
    const std::string lower = detail::lower_file_name(path);
    parsed.gzip = detail::has_suffix(lower, ".raw.gz");
    if (!parsed.gzip && !detail::has_suffix(lower, ".raw")) {
        return fail("the file name does not end in .raw or .raw.gz");
    }
    const std::string stem =
            detail::strip_suffix(path, std::array<std::string_view, 2>{".raw.gz", ".raw"});
    const std::string_view text(stem);

    const std::size_t type_cut = text.rfind('_');
    if (type_cut == std::string_view::npos) {
        return fail("the file name has no _XxYxZ_type part");
    }
    const std::string_view type_text = text.substr(type_cut + 1);
    const auto type = parse_sample_type(type_text);
    if (!type) {
        return fail("unknown sample type '" + std::string(type_text) + "'");
    }
    const std::size_t dims_cut = text.rfind('_', type_cut == 0 ? 0 : type_cut - 1);
    if (type_cut == 0 || dims_cut == std::string_view::npos) {
        return fail("the file name has no _XxYxZ part before the type");
    }
    const std::string_view dims_text = text.substr(dims_cut + 1, type_cut - dims_cut - 1);
    const auto dims = parse_dims(dims_text);
    if (!dims) {
        return fail("'" + std::string(dims_text) + "' is not three positive sizes written XxYxZ");
    }
    if (dims_cut == 0) {
        return fail("the file name has no name before _XxYxZ");
    }
    parsed.name = std::string(text.substr(0, dims_cut));
    parsed.dims = *dims;
    parsed.type = *type;
    return parsed;
}

std::string describe(const RawName& raw) {
    return std::to_string(raw.dims.x) + "x" + std::to_string(raw.dims.y) + "x" +
           std::to_string(raw.dims.z) + " " + detail::sample_name(raw.type);
}

// What a load of `raw` holds: the volume in the type it keeps.
std::string describe_stored(const RawName& raw, const detail::SampleLayout& layout) {
    const VoxelType stored = layout.stored();
    return describe(raw) + (detail::is_kept(raw.type)
                                    ? std::string()
                                    : std::string(" kept as ") + to_string(stored));
}

base::Status read_plain(std::FILE* file, const std::filesystem::path& path, const RawName& raw,
                        detail::SampleSink& sink, std::uint64_t expected) {
    auto size = detail::regular_file_size(path);
    if (!size) {
        return size.error();
    }
    if (*size < expected) {
        return base::make_error(base::ErrorCode::truncated,
                                "the file holds " + std::to_string(*size) +
                                        " bytes but its name implies " + std::to_string(expected) +
                                        " (" + describe(raw) + ")",
                                detail::at_byte(path, *size));
    }
    if (*size > expected) {
        return base::make_error(base::ErrorCode::too_long,
                                "the file holds " + std::to_string(*size) +
                                        " bytes, more than the " + std::to_string(expected) +
                                        " its name implies (" + describe(raw) + ")",
                                detail::at_byte(path, expected));
    }
    auto got = detail::read_into(file, path, 0, sink);
    if (!got) {
        return got.error();
    }
    if (*got != expected) {
        return base::make_error(base::ErrorCode::truncated,
                                "the file ended after " + std::to_string(*got) + " of " +
                                        std::to_string(expected) + " bytes while reading",
                                detail::at_byte(path, *got));
    }
    return base::Ok{};
}

base::Status read_gzip(std::FILE* file, const std::filesystem::path& path, const RawName& raw,
                       detail::SampleSink& sink, std::uint64_t expected) {
    auto inflated = detail::inflate_file(file, path, 0, 0, sink);
    if (!inflated) {
        return inflated.error();
    }
    if (inflated->more) {
        return base::make_error(base::ErrorCode::too_long,
                                "the decompressed data is longer than the " +
                                        std::to_string(expected) + " bytes its name implies (" +
                                        describe(raw) + ")",
                                detail::at_file(path));
    }
    if (inflated->produced < expected) {
        return base::make_error(
                base::ErrorCode::truncated,
                "the decompressed data holds " + std::to_string(inflated->produced) +
                        " bytes but the name implies " + std::to_string(expected) + " (" +
                        describe(raw) + ")" +
                        (inflated->complete ? "" : "; the compressed stream is cut short"),
                detail::at_file(path));
    }
    if (!inflated->complete) {
        return base::make_error(base::ErrorCode::truncated,
                                "the compressed stream is cut short before its end marker",
                                detail::at_file(path));
    }
    return base::Ok{};
}

base::Result<Volume> load_raw_file(const std::filesystem::path& path, const LoadOptions& options) {
    auto raw = parse_raw_name(path);
    if (!raw) {
        return raw.error();
    }
    const std::uint64_t voxels = std::uint64_t{raw->dims.x} * raw->dims.y * raw->dims.z;
    if (voxels > max_voxels) {
        return base::make_error(base::ErrorCode::too_large,
                                describe(*raw) + " is " + std::to_string(voxels) +
                                        " voxels, more than the limit of " +
                                        std::to_string(max_voxels),
                                detail::at_file(path));
    }
    const detail::SampleLayout layout{.type = raw->type, .voxels = voxels};
    if (auto status = detail::check_budget(layout.stored_bytes(), describe_stored(*raw, layout),
                                           path, options);
        !status) {
        return status.error();
    }
    auto file = detail::open_file(path);
    if (!file) {
        return file.error();
    }
    const std::uint64_t expected = layout.file_bytes();
    detail::SampleSink sink(layout);
    auto status = raw->gzip ? read_gzip(file->get(), path, *raw, sink, expected)
                            : read_plain(file->get(), path, *raw, sink, expected);
    if (!status) {
        return status.error();
    }
    auto volume = make_volume(raw->name, raw->dims, glm::dvec3(1.0), layout.stored(), sink.take());
    if (!volume) {
        base::Error error = volume.error();
        error.where = detail::at_file(path);
        return error;
    }
    return volume;
}

}  // namespace

base::Result<Volume> load_raw(const std::filesystem::path& path, const LoadOptions& options) {
    return detail::guard_allocation(path, [&] { return load_raw_file(path, options); });
}

}  // namespace penumbra::volume
