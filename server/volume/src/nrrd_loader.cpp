// NRRD (teem's "nearly raw raster data"): a text header, then the samples in the same file
// (.nrrd) or in the file that "data file" names (.nhdr). Format reference:
// https://teem.sourceforge.net/nrrd/format.html

#include "file_io.hpp"
#include "file_name.hpp"
#include "memory_budget.hpp"
#include "samples.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <utility>

#include <bzlib.h>

namespace penumbra::volume {
namespace {

using detail::SampleType;

// Real headers are a few KB even with long DWI gradient tables; the cap stops a binary file that
// happens to start with the magic from being read whole as "header".
constexpr std::uint64_t max_header_bytes = std::uint64_t{16} << 20;

enum class Encoding { raw, gzip, bzip2, ascii, hex };

// A header value and the line it came from, for error messages.
template <class T>
struct Field {
    std::optional<T> value;
    std::size_t line = 0;
};

struct Header {
    Field<SampleType> type;
    Field<int> dimension;
    Field<std::vector<std::uint32_t>> sizes;
    Field<Encoding> encoding;
    Field<bool> big_endian;
    Field<std::vector<double>> spacings;
    Field<std::vector<std::vector<double>>> directions;  // empty for a "none" axis
    Field<glm::dvec3> space_to_ras;                      // from "space"
    Field<std::vector<double>> space_origin;
    Field<std::string> data_file;
    Field<std::int64_t> byte_skip;
    Field<std::int64_t> line_skip;
    Field<std::vector<std::string>> kinds;  // lower case, one per axis
    bool hounsfield = false;                // the key/value penumbra_units:=HU
    NrrdKeyValues key_values;  // every key:=value line, in order (bounded by max_header_bytes)
    bool ended_by_blank_line = false;
    std::uint64_t data_offset = 0;  // where attached data starts
};

std::string_view trim(std::string_view text) {
    constexpr std::string_view space = " \t\r\n";
    const std::size_t first = text.find_first_not_of(space);
    if (first == std::string_view::npos) {
        return {};
    }
    const std::size_t last = text.find_last_not_of(space);
    return text.substr(first, last - first + 1);
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) {
        if (c >= 'A' && c <= 'Z') {
            c = static_cast<char>(c - 'A' + 'a');
        }
    }
    return out;
}

std::vector<std::string_view> split_words(std::string_view text) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) {
            ++i;
        }
        const std::size_t start = i;
        while (i < text.size() && text[i] != ' ' && text[i] != '\t') {
            ++i;
        }
        if (i > start) {
            words.push_back(text.substr(start, i - start));
        }
    }
    return words;
}

template <class T>
std::optional<T> parse_number(std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '+') {
        text.remove_prefix(1);
    }
    T value{};
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc{} || end != text.data() + text.size()) {
        return std::nullopt;
    }
    return value;
}

std::optional<SampleType> parse_type(std::string_view text) {
    static const std::map<std::string, SampleType, std::less<>> spellings{
            {"signed char", SampleType::int8},
            {"int8", SampleType::int8},
            {"int8_t", SampleType::int8},
            {"uchar", SampleType::uint8},
            {"unsigned char", SampleType::uint8},
            {"uint8", SampleType::uint8},
            {"uint8_t", SampleType::uint8},
            {"short", SampleType::int16},
            {"short int", SampleType::int16},
            {"signed short", SampleType::int16},
            {"signed short int", SampleType::int16},
            {"int16", SampleType::int16},
            {"int16_t", SampleType::int16},
            {"ushort", SampleType::uint16},
            {"unsigned short", SampleType::uint16},
            {"unsigned short int", SampleType::uint16},
            {"uint16", SampleType::uint16},
            {"uint16_t", SampleType::uint16},
            {"int", SampleType::int32},
            {"signed int", SampleType::int32},
            {"int32", SampleType::int32},
            {"int32_t", SampleType::int32},
            {"uint", SampleType::uint32},
            {"unsigned int", SampleType::uint32},
            {"uint32", SampleType::uint32},
            {"uint32_t", SampleType::uint32},
            {"longlong", SampleType::int64},
            {"long long", SampleType::int64},
            {"long long int", SampleType::int64},
            {"signed long long", SampleType::int64},
            {"signed long long int", SampleType::int64},
            {"int64", SampleType::int64},
            {"int64_t", SampleType::int64},
            {"ulonglong", SampleType::uint64},
            {"unsigned long long", SampleType::uint64},
            {"unsigned long long int", SampleType::uint64},
            {"uint64", SampleType::uint64},
            {"uint64_t", SampleType::uint64},
            {"float", SampleType::float32},
            {"double", SampleType::float64},
    };
    // Writers differ in spacing ("unsigned  char"), so compare word by word.
    std::string normal;
    for (std::string_view word : split_words(text)) {
        normal += normal.empty() ? "" : " ";
        normal += lower(word);
    }
    const auto found = spellings.find(normal);
    if (found == spellings.end()) {
        return std::nullopt;
    }
    return found->second;
}

// Parses "(x,y,z)" vectors or "none" entries (an empty vector); every vector has as many
// components as the first.
std::optional<std::vector<std::vector<double>>> parse_vectors(std::string_view text) {
    std::vector<std::vector<double>> vectors;
    std::size_t components = 0;
    while (true) {
        text = trim(text);
        if (text.empty()) {
            return vectors;
        }
        if (text.substr(0, 4) == "none") {
            vectors.emplace_back();
            text.remove_prefix(4);
            continue;
        }
        if (text.front() != '(') {
            return std::nullopt;
        }
        const std::size_t close = text.find(')');
        if (close == std::string_view::npos) {
            return std::nullopt;
        }
        std::string_view inside = text.substr(1, close - 1);
        text.remove_prefix(close + 1);
        std::vector<double> vector;
        while (true) {
            const std::size_t comma = inside.find(',');
            const auto component = parse_number<double>(trim(inside.substr(0, comma)));
            if (!component || !std::isfinite(*component)) {
                return std::nullopt;
            }
            vector.push_back(*component);
            if (comma == std::string_view::npos) {
                break;
            }
            inside.remove_prefix(comma + 1);
        }
        if (components != 0 && vector.size() != components) {
            return std::nullopt;  // every vector lives in the same space
        }
        components = vector.size();
        vectors.push_back(std::move(vector));
    }
}

// How a NRRD "space" maps to RAS: the sign of each patient coordinate. The scanner and generic
// right-handed spaces name no anatomy; their coordinates are taken as RAS. A left-handed space
// mirrors x.
std::optional<glm::dvec3> space_to_ras(std::string_view space) {
    static const std::map<std::string, glm::dvec3, std::less<>> spaces{
            {"right-anterior-superior", {1, 1, 1}},
            {"ras", {1, 1, 1}},
            {"left-anterior-superior", {-1, 1, 1}},
            {"las", {-1, 1, 1}},
            {"left-posterior-superior", {-1, -1, 1}},
            {"lps", {-1, -1, 1}},
            {"right-anterior-superior-time", {1, 1, 1}},
            {"rast", {1, 1, 1}},
            {"left-anterior-superior-time", {-1, 1, 1}},
            {"last", {-1, 1, 1}},
            {"left-posterior-superior-time", {-1, -1, 1}},
            {"lpst", {-1, -1, 1}},
            {"scanner-xyz", {1, 1, 1}},
            {"scanner-xyz-time", {1, 1, 1}},
            {"3d-right-handed", {1, 1, 1}},
            {"3d-right-handed-time", {1, 1, 1}},
            {"3d-left-handed", {-1, 1, 1}},
            {"3d-left-handed-time", {-1, 1, 1}}};
    const auto found = spaces.find(space);
    if (found == spaces.end()) {
        return std::nullopt;
    }
    return found->second;
}

class HeaderParser {
public:
    HeaderParser(std::FILE* file, const std::filesystem::path& path)
        : file_(file)
        , path_(path) {}

    base::Result<Header> parse() {
        auto magic = read_line();
        if (!magic) {
            return magic.error();
        }
        const std::string first_line = magic->value_or("");
        const std::string_view text = trim(first_line);
        if (text.size() != 8 || text.substr(0, 7) != "NRRD000" || text[7] < '1' || text[7] > '9') {
            return base::make_error(base::ErrorCode::bad_header,
                                    "not a NRRD file: it must start with the magic NRRD0001 to "
                                    "NRRD0005",
                                    detail::at_line(path_, 1));
        }
        for (;;) {
            auto line = read_line();
            if (!line) {
                return line.error();
            }
            if (!line->has_value()) {
                break;  // the end of a detached header
            }
            const std::string_view content = **line;
            if (trim(content).empty()) {
                header_.ended_by_blank_line = true;
                header_.data_offset = offset_;
                break;
            }
            if (content.front() == '#') {
                continue;
            }
            if (auto status = parse_line(content); !status) {
                return status.error();
            }
        }
        return std::move(header_);
    }

private:
    // The next line without its end-of-line, or nullopt at the end of the file.
    base::Result<std::optional<std::string>> read_line() {
        std::string line;
        for (;;) {
            const int c = std::fgetc(file_);
            if (c == EOF) {
                if (std::ferror(file_)) {
                    return base::make_error(base::ErrorCode::read_failed,
                                            "read error in the header",
                                            detail::at_byte(path_, offset_));
                }
                if (line.empty()) {
                    return std::optional<std::string>{};
                }
                break;
            }
            ++offset_;
            if (offset_ > max_header_bytes) {
                return base::make_error(base::ErrorCode::bad_header,
                                        "no end of the header within the first " +
                                                std::to_string(max_header_bytes) + " bytes",
                                        detail::at_byte(path_, offset_));
            }
            if (c == '\n') {
                break;
            }
            line.push_back(static_cast<char>(c));
        }
        ++line_number_;
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        return std::optional<std::string>(std::move(line));
    }

    base::Error error(base::ErrorCode code, const std::string& message) const {
        return base::make_error(code, message, detail::at_line(path_, line_number_));
    }

    template <class T>
    base::Status claim(Field<T>& field, const std::string& name) {
        if (field.line != 0) {
            return error(base::ErrorCode::bad_header, "field '" + name +
                                                              "' appears twice (first on line " +
                                                              std::to_string(field.line) + ")");
        }
        field.line = line_number_;
        return base::Ok{};
    }

    base::Status parse_line(std::string_view content) {
        const std::size_t colon = content.find(':');
        if (colon == std::string_view::npos) {
            return error(
                    base::ErrorCode::bad_header,
                    "expected 'field: value' or 'key:=value', got '" + std::string(content) + "'");
        }
        if (colon + 1 < content.size() && content[colon + 1] == '=') {
            // Key/value pairs carry metadata; Penumbra reads one of its own: values in
            // Hounsfield units ("penumbra_units:=HU"), which NRRD has no field for.
            const std::string key(trim(content.substr(0, colon)));
            const std::string value(trim(content.substr(colon + 2)));
            if (key == "penumbra_units") {
                header_.hounsfield = lower(value) == "hu";
            }
            header_.key_values.emplace_back(key, value);
            return base::Ok{};
        }
        const std::string name = lower(trim(content.substr(0, colon)));
        const std::string_view value = trim(content.substr(colon + 1));

        if (name == "type") {
            return parse_type_field(value);
        }
        if (name == "dimension") {
            return parse_dimension(value);
        }
        if (name == "sizes") {
            return parse_sizes(value);
        }
        if (name == "encoding") {
            return parse_encoding(value);
        }
        if (name == "endian") {
            if (auto status = claim(header_.big_endian, name); !status) {
                return status;
            }
            const std::string endian = lower(value);
            if (endian != "little" && endian != "big") {
                return error(base::ErrorCode::bad_header,
                             "endian must be 'little' or 'big', got '" + std::string(value) + "'");
            }
            header_.big_endian.value = endian == "big";
            return base::Ok{};
        }
        if (name == "spacings") {
            return parse_spacings(value);
        }
        if (name == "space directions") {
            if (auto status = claim(header_.directions, name); !status) {
                return status;
            }
            header_.directions.value = parse_vectors(value);
            if (!header_.directions.value) {
                return error(base::ErrorCode::bad_header,
                             "space directions must be '(x,y,z)' vectors of finite numbers or "
                             "'none', got '" +
                                     std::string(value) + "'");
            }
            return base::Ok{};
        }
        if (name == "space") {
            if (auto status = claim(header_.space_to_ras, name); !status) {
                return status;
            }
            header_.space_to_ras.value = space_to_ras(lower(value));
            if (!header_.space_to_ras.value) {
                return error(base::ErrorCode::bad_header,
                             "unknown space '" + std::string(value) +
                                     "' (known: right-anterior-superior, left-anterior-superior, "
                                     "left-posterior-superior, their -time forms, scanner-xyz, "
                                     "3D-right-handed, 3D-left-handed)");
            }
            return base::Ok{};
        }
        if (name == "space origin") {
            if (auto status = claim(header_.space_origin, name); !status) {
                return status;
            }
            auto vectors = parse_vectors(value);
            if (!vectors || vectors->size() != 1 || vectors->front().empty()) {
                return error(base::ErrorCode::bad_header,
                             "space origin must be one '(x,y,z)' vector, got '" +
                                     std::string(value) + "'");
            }
            header_.space_origin.value = std::move(vectors->front());
            return base::Ok{};
        }
        if (name == "data file" || name == "datafile") {
            if (auto status = claim(header_.data_file, "data file"); !status) {
                return status;
            }
            header_.data_file.value = std::string(value);
            return base::Ok{};
        }
        if (name == "byte skip" || name == "byteskip") {
            return parse_skip(header_.byte_skip, "byte skip", value, -1);
        }
        if (name == "line skip" || name == "lineskip") {
            return parse_skip(header_.line_skip, "line skip", value, 0);
        }
        if (name == "kinds") {
            if (auto status = claim(header_.kinds, "kinds"); !status) {
                return status;
            }
            std::vector<std::string> kinds;
            for (std::string_view word : split_words(value)) {
                kinds.push_back(lower(word));
            }
            header_.kinds.value = std::move(kinds);
            return base::Ok{};
        }
        // Other fields (content, centers, units, min, max, ...) only describe the data.
        return base::Ok{};
    }

    base::Status parse_type_field(std::string_view value) {
        if (auto status = claim(header_.type, "type"); !status) {
            return status;
        }
        header_.type.value = parse_type(value);
        if (!header_.type.value) {
            return error(base::ErrorCode::unsupported_type,
                         "unknown or unsupported type '" + std::string(value) +
                                 "' (supported: the integer types up to 64 bits, float, double)");
        }
        return base::Ok{};
    }

    base::Status parse_dimension(std::string_view value) {
        if (auto status = claim(header_.dimension, "dimension"); !status) {
            return status;
        }
        const auto dimension = parse_number<int>(value);
        if (!dimension || *dimension < 1) {
            return error(base::ErrorCode::bad_header,
                         "dimension must be a positive integer, got '" + std::string(value) + "'");
        }
        if (*dimension != 3 && *dimension != 4) {
            return error(base::ErrorCode::unsupported_dimension,
                         "dimension " + std::to_string(*dimension) +
                                 " is not supported: Penumbra reads 3-D scalar volumes "
                                 "(dimension: 3) and the first volume of 4-D ones");
        }
        header_.dimension.value = *dimension;
        return base::Ok{};
    }

    base::Status parse_sizes(std::string_view value) {
        if (auto status = claim(header_.sizes, "sizes"); !status) {
            return status;
        }
        std::vector<std::uint32_t> sizes;
        std::uint64_t voxels = 1;
        for (std::string_view word : split_words(value)) {
            const auto size = parse_number<std::int64_t>(word);
            if (!size || *size < 1) {
                return error(base::ErrorCode::bad_header,
                             "sizes must be positive integers, got '" + std::string(value) + "'");
            }
            // Checked before anything is allocated: an absurd header must not cost memory.
            if (static_cast<std::uint64_t>(*size) > max_voxels / voxels) {
                return error(base::ErrorCode::too_large,
                             "sizes '" + std::string(value) + "' exceed the limit of " +
                                     std::to_string(max_voxels) + " voxels");
            }
            voxels *= static_cast<std::uint64_t>(*size);
            sizes.push_back(static_cast<std::uint32_t>(*size));
        }
        if (sizes.empty()) {
            return error(base::ErrorCode::bad_header, "sizes has no values");
        }
        header_.sizes.value = std::move(sizes);
        return base::Ok{};
    }

    base::Status parse_encoding(std::string_view value) {
        if (auto status = claim(header_.encoding, "encoding"); !status) {
            return status;
        }
        const std::string encoding = lower(value);
        if (encoding == "raw") {
            header_.encoding.value = Encoding::raw;
        } else if (encoding == "gzip" || encoding == "gz") {
            header_.encoding.value = Encoding::gzip;
        } else if (encoding == "bzip2" || encoding == "bz2") {
            header_.encoding.value = Encoding::bzip2;
        } else if (encoding == "ascii" || encoding == "text" || encoding == "txt") {
            header_.encoding.value = Encoding::ascii;
        } else if (encoding == "hex") {
            header_.encoding.value = Encoding::hex;
        } else {
            return error(base::ErrorCode::unsupported_encoding,
                         "encoding '" + std::string(value) +
                                 "' is not supported (supported: raw, gzip, bzip2, ascii, hex)");
        }
        return base::Ok{};
    }

    base::Status parse_spacings(std::string_view value) {
        if (auto status = claim(header_.spacings, "spacings"); !status) {
            return status;
        }
        std::vector<double> spacings;
        for (std::string_view word : split_words(value)) {
            const std::string token = lower(word);
            if (token == "nan") {
                spacings.push_back(std::nan(""));
                continue;
            }
            const auto spacing = parse_number<double>(word);
            if (!spacing || !std::isfinite(*spacing) || *spacing == 0.0) {
                return error(base::ErrorCode::bad_header,
                             "spacings must be non-zero finite numbers or nan, got '" +
                                     std::string(value) + "'");
            }
            spacings.push_back(std::abs(*spacing));
        }
        header_.spacings.value = std::move(spacings);
        return base::Ok{};
    }

    base::Status parse_skip(Field<std::int64_t>& field, const std::string& name,
                            std::string_view value, std::int64_t minimum) {
        if (auto status = claim(field, name); !status) {
            return status;
        }
        const auto skip = parse_number<std::int64_t>(value);
        if (!skip || *skip < minimum) {
            return error(base::ErrorCode::bad_header, name + " must be an integer of at least " +
                                                              std::to_string(minimum) + ", got '" +
                                                              std::string(value) + "'");
        }
        field.value = *skip;
        return base::Ok{};
    }

    std::FILE* file_;
    const std::filesystem::path& path_;
    Header header_;
    std::uint64_t offset_ = 0;
    std::size_t line_number_ = 0;
};

// The geometry and sample layout a complete header describes.
struct Layout {
    glm::uvec3 dims{0};
    Geometry geometry;
    SampleType type = SampleType::uint8;
    Encoding encoding = Encoding::raw;
    bool big_endian = false;
    std::uint64_t voxels = 0;   // samples read: the volume's voxels times its components
    std::uint64_t bytes = 0;    // of the samples read (the first volume of a 4-D file)
    std::uint64_t volumes = 1;  // a 4-D file's 4th size
    // Values per voxel along a first axis that is no axis of space (kinds list, vector, ...):
    // the first is kept.
    std::uint32_t components = 1;
};

// What an axis of a NRRD file is, by its kind: space (or time: a 4th axis of volumes), values
// per voxel, or a colour's channels.
enum class AxisRole { space, components, colour };

AxisRole axis_role(const std::string& kind) {
    static const std::array<std::string_view, 6> space{"domain", "space", "time",
                                                       "???",    "none",  ""};
    static const std::array<std::string_view, 6> colour{"3-color",   "rgb-color", "hsv-color",
                                                        "xyz-color", "4-color",   "rgba-color"};
    if (std::find(space.begin(), space.end(), kind) != space.end()) {
        return AxisRole::space;
    }
    if (std::find(colour.begin(), colour.end(), kind) != colour.end()) {
        return AxisRole::colour;
    }
    return AxisRole::components;  // list, point, vector, scalar, complex, 3-vector, matrices...
}

base::Result<Layout> check_header(const Header& header, const std::filesystem::path& path) {
    const auto missing = [&](const char* field) {
        return base::make_error(base::ErrorCode::bad_header,
                                std::string("the header has no '") + field + "' field",
                                detail::at_file(path));
    };
    if (!header.type.value) {
        return missing("type");
    }
    if (!header.dimension.value) {
        return missing("dimension");
    }
    if (!header.sizes.value) {
        return missing("sizes");
    }
    if (!header.encoding.value) {
        return missing("encoding");
    }
    const auto at = [&](std::size_t line) { return detail::at_line(path, line); };
    const auto& sizes = *header.sizes.value;
    const std::size_t dimension = static_cast<std::size_t>(*header.dimension.value);
    const std::string is_dimension = " but the dimension is " + std::to_string(dimension);
    if (sizes.size() != dimension) {
        return base::make_error(
                base::ErrorCode::bad_header,
                "sizes lists " + std::to_string(sizes.size()) + " values" + is_dimension,
                at(header.sizes.line));
    }
    // What each axis holds: its kind where "kinds" says; else a first axis of a 4-D file whose
    // spacing is nan, or that has no direction while the 4th has one, holds values per voxel.
    std::vector<AxisRole> roles(dimension, AxisRole::space);
    if (header.kinds.value) {
        if (header.kinds.value->size() != dimension) {
            return base::make_error(base::ErrorCode::bad_header,
                                    "kinds lists " + std::to_string(header.kinds.value->size()) +
                                            " values" + is_dimension,
                                    at(header.kinds.line));
        }
        for (std::size_t axis = 0; axis < dimension; ++axis) {
            roles[axis] = axis_role((*header.kinds.value)[axis]);
        }
    } else if (dimension == 4) {
        const bool nan_spacing = header.spacings.value && header.spacings.value->size() == 4 &&
                                 std::isnan((*header.spacings.value)[0]);
        const bool no_direction = header.directions.value && header.directions.value->size() == 4 &&
                                  (*header.directions.value)[0].empty() &&
                                  !(*header.directions.value)[3].empty();
        if (nan_spacing || no_direction) {
            roles[0] = AxisRole::components;
        }
    }
    for (std::size_t axis = 0; axis < dimension; ++axis) {
        if (roles[axis] == AxisRole::colour) {
            return base::make_error(base::ErrorCode::unsupported_type,
                                    "a colour image (kinds: " + (*header.kinds.value)[axis] +
                                            "), not a scalar volume",
                                    at(header.kinds.line));
        }
    }
    // Values per voxel are read along the first axis only (each voxel's values together); the
    // three axes after it are space; a 4th of those, whatever its kind, is a stack of volumes,
    // the first of which is read, as 4-D NIfTI.
    const bool has_components = roles[0] == AxisRole::components;
    const std::size_t first_space = has_components ? 1 : 0;
    std::size_t space_axes = 0;
    while (first_space + space_axes < dimension && space_axes < 3 &&
           roles[first_space + space_axes] == AxisRole::space) {
        ++space_axes;
    }
    if (space_axes < 3) {
        return base::make_error(base::ErrorCode::unsupported_dimension,
                                "a 2-D image (" + std::to_string(space_axes) +
                                        " axes of space before values per voxel or the end), "
                                        "not a volume",
                                at(header.kinds.value ? header.kinds.line : header.sizes.line));
    }
    Layout layout;
    layout.dims = glm::uvec3(sizes[first_space], sizes[first_space + 1], sizes[first_space + 2]);
    layout.components = has_components ? sizes[0] : 1;
    layout.type = *header.type.value;
    layout.encoding = *header.encoding.value;
    layout.voxels =
            std::uint64_t{layout.dims.x} * layout.dims.y * layout.dims.z * layout.components;
    layout.bytes = layout.voxels * detail::sample_size(layout.type);
    layout.volumes = dimension - first_space == 4 ? sizes[first_space + 3] : 1;

    const bool endian_matters =
            detail::sample_size(layout.type) > 1 && layout.encoding != Encoding::ascii;
    if (endian_matters && !header.big_endian.value) {
        return base::make_error(base::ErrorCode::bad_header,
                                std::string("the header has no 'endian' field, which ") +
                                        detail::sample_name(layout.type) + " data needs",
                                detail::at_file(path));
    }
    layout.big_endian = header.big_endian.value.value_or(false);

    if (header.byte_skip.value == -1 && layout.encoding != Encoding::raw) {
        return base::make_error(base::ErrorCode::bad_header,
                                "byte skip -1 is only allowed with raw encoding",
                                at(header.byte_skip.line));
    }

    // "space directions" supersedes "spacings" (NRRD0004+ files write one or the other); with
    // them and "space", the axes and origin are the file's, converted to RAS.
    const glm::dvec3 to_ras = header.space_to_ras.value.value_or(glm::dvec3(1.0));
    glm::dvec3 origin(0.0);
    if (header.space_origin.value) {
        const auto& components = *header.space_origin.value;
        if (components.size() != 3) {
            return base::make_error(base::ErrorCode::bad_header,
                                    "space origin has " + std::to_string(components.size()) +
                                            " components; a 3-D space needs 3",
                                    at(header.space_origin.line));
        }
        origin = to_ras * glm::dvec3(components[0], components[1], components[2]);
    }
    glm::dmat3 steps(1.0);
    if (header.directions.value) {
        const auto& directions = *header.directions.value;
        if (directions.size() != dimension) {
            return base::make_error(base::ErrorCode::bad_header,
                                    "space directions lists " + std::to_string(directions.size()) +
                                            " entries" + is_dimension,
                                    at(header.directions.line));
        }
        for (int axis = 0; axis < 3; ++axis) {
            const auto& direction = directions[first_space + static_cast<std::size_t>(axis)];
            if (direction.empty()) {
                continue;  // "none": an axis without a direction keeps unit steps along itself
            }
            if (direction.size() != 3) {
                return base::make_error(base::ErrorCode::bad_header,
                                        "space direction " + std::to_string(axis) + " has " +
                                                std::to_string(direction.size()) +
                                                " components; a 3-D space needs 3",
                                        at(header.directions.line));
            }
            const glm::dvec3 step(direction[0], direction[1], direction[2]);
            if (step == glm::dvec3(0.0)) {
                return base::make_error(
                        base::ErrorCode::bad_header,
                        "space direction " + std::to_string(axis) + " is the zero vector",
                        at(header.directions.line));
            }
            steps[axis] = to_ras * step;
        }
    } else if (header.spacings.value) {
        const auto& spacings = *header.spacings.value;
        if (spacings.size() != dimension) {
            return base::make_error(
                    base::ErrorCode::bad_header,
                    "spacings lists " + std::to_string(spacings.size()) + " values" + is_dimension,
                    at(header.spacings.line));
        }
        for (int axis = 0; axis < 3; ++axis) {
            const double spacing = spacings[first_space + static_cast<std::size_t>(axis)];
            steps[axis][axis] = std::isnan(spacing) ? 1.0 : spacing;
        }
    }
    auto geometry = placed_geometry(steps, origin);
    if (!geometry) {
        base::Error error = geometry.error();
        error.where = at(header.directions.line);
        return error;
    }
    layout.geometry = *geometry;
    return layout;
}

// Whether `inside` lies in `folder` or below it, both canonical (absolute, no "..", no links).
bool lies_within(const std::filesystem::path& inside, const std::filesystem::path& folder) {
    auto a = folder.begin();
    auto b = inside.begin();
    for (; a != folder.end(); ++a, ++b) {
        if (a->empty() && std::next(a) == folder.end()) {
            break;  // a trailing separator: "/data/" holds what "/data" holds
        }
        if (b == inside.end() || *a != *b) {
            return false;
        }
    }
    return true;
}

// Resolves the file that holds the samples: the header file itself, or "data file" relative to
// the header's folder. A header comes from whoever wrote the file, so "data file" may only name a
// file in the header's folder or below it, also when written as an absolute path, and never one
// that leaves the folder through ".." or a symbolic link (else a header could expose /etc/passwd
// as a volume).
base::Result<std::filesystem::path> data_path(const Header& header,
                                              const std::filesystem::path& path) {
    if (!header.data_file.value) {
        if (!header.ended_by_blank_line) {
            return base::make_error(base::ErrorCode::bad_header,
                                    "the header has neither a blank line followed by data nor a "
                                    "'data file' field",
                                    detail::at_file(path));
        }
        return path;
    }
    const std::string& name = *header.data_file.value;
    const auto at_field = detail::at_line(path, header.data_file.line);
    const auto words = split_words(name);
    if (!words.empty() && words.front() == "LIST") {
        return base::make_error(base::ErrorCode::unsupported_data_file,
                                "'data file: LIST' (data split over several files) is not "
                                "supported; name a single data file",
                                at_field);
    }
    if (words.size() >= 4 && words.front().find('%') != std::string_view::npos) {
        return base::make_error(base::ErrorCode::unsupported_data_file,
                                "a numbered 'data file' pattern (data split over several files) "
                                "is not supported; name a single data file",
                                at_field);
    }
    if (name.empty()) {
        return base::make_error(base::ErrorCode::bad_header, "'data file' names no file", at_field);
    }
    const std::filesystem::path data(name);
    const auto outside = [&] {
        return base::make_error(base::ErrorCode::data_file_outside,
                                "'data file' must name a file in the header's folder or below "
                                "it, not '" +
                                        name + "'",
                                at_field);
    };
    std::error_code ec;
    // The header's own folder, also when `path` is a link to it (a data folder may hold links).
    const auto folder = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec)
                                .parent_path();
    if (ec) {
        return base::make_error(base::ErrorCode::read_failed,
                                "cannot resolve the header's folder: " + ec.message(),
                                detail::at_file(path));
    }
    const auto resolved = std::filesystem::weakly_canonical(folder / data, ec);
    if (ec) {
        return base::make_error(base::ErrorCode::read_failed,
                                "cannot resolve 'data file' '" + name + "': " + ec.message(),
                                at_field);
    }
    if (!lies_within(resolved, folder)) {
        return outside();
    }
    return data.is_absolute() ? data : folder / data;
}

// Skips `lines` newline-terminated lines of the data file, as "line skip" asks.
base::Status skip_lines(std::FILE* file, const std::filesystem::path& path, std::int64_t lines,
                        std::uint64_t& offset) {
    for (std::int64_t skipped = 0; skipped < lines;) {
        const int c = std::fgetc(file);
        if (c == EOF) {
            return base::make_error(base::ErrorCode::truncated,
                                    "the data file ended after " + std::to_string(skipped) +
                                            " of the " + std::to_string(lines) +
                                            " lines that 'line skip' asks to skip",
                                    detail::at_byte(path, offset));
        }
        ++offset;
        if (c == '\n') {
            ++skipped;
        }
    }
    return base::Ok{};
}

// Where the samples of raw encoding start: after "byte skip" bytes, or (byte skip -1) so that
// they are the last bytes of the file. Checks that the file holds them.
base::Result<std::uint64_t> raw_data_offset(const std::filesystem::path& path, const Layout& layout,
                                            std::int64_t byte_skip, std::uint64_t offset) {
    auto size = detail::regular_file_size(path);
    if (!size) {
        return size.error();
    }
    if (byte_skip == -1) {
        // "byte skip: -1" means the data are the last bytes of the file (all volumes of a 4-D
        // file, the first of which is read).
        const std::uint64_t all_bytes = layout.bytes * layout.volumes;
        if (*size < offset || *size - offset < all_bytes) {
            return base::make_error(base::ErrorCode::truncated,
                                    "expected " + std::to_string(all_bytes) +
                                            " bytes of data at the end of the file, after byte " +
                                            std::to_string(offset) + ", but the file holds " +
                                            std::to_string(*size) + " bytes",
                                    detail::at_byte(path, *size));
        }
        offset = *size - all_bytes;
    } else {
        offset += static_cast<std::uint64_t>(byte_skip);
    }
    if (*size < offset || *size - offset < layout.bytes) {
        const std::uint64_t available = *size > offset ? *size - offset : 0;
        return base::make_error(base::ErrorCode::truncated,
                                "expected " + std::to_string(layout.bytes) +
                                        " bytes of data from byte " + std::to_string(offset) +
                                        ", the file holds only " + std::to_string(available),
                                detail::at_byte(path, *size));
    }
    return offset;
}

base::Status read_raw(std::FILE* file, const std::filesystem::path& path, const Layout& layout,
                      std::uint64_t offset, detail::SampleSink& sink) {
    if (auto status = detail::seek_to(file, path, offset); !status) {
        return status.error();
    }
    auto got = detail::read_into(file, path, offset, sink);
    if (!got) {
        return got.error();
    }
    if (*got != layout.bytes) {
        return base::make_error(base::ErrorCode::truncated,
                                "expected " + std::to_string(layout.bytes) +
                                        " bytes of data from byte " + std::to_string(offset) +
                                        ", read only " + std::to_string(*got),
                                detail::at_byte(path, offset + *got));
    }
    return base::Ok{};
}

// Decompresses the bzip2 stream at the file's current position (libbz2), drops the first
// `byte_skip` bytes of output (NRRD applies it to the decompressed data) and fills `sink`. It stops
// once the sink is full, so a small file that expands to terabytes costs neither memory nor much
// time.
base::Status read_bzip2(std::FILE* file, const std::filesystem::path& path, const Layout& layout,
                        std::int64_t byte_skip, std::uint64_t offset, detail::SampleSink& sink) {
    bz_stream bz{};
    if (BZ2_bzDecompressInit(&bz, 0, 0) != BZ_OK) {
        return base::make_error(base::ErrorCode::read_failed,
                                "libbz2 could not start a decompressor", detail::at_file(path));
    }

    struct EndDecompress {
        bz_stream* bz;

        ~EndDecompress() { BZ2_bzDecompressEnd(bz); }
    } end_decompress{&bz};

    std::vector<char> input(std::size_t{1} << 16);
    std::array<char, 1 << 14> scratch{};
    std::uint64_t skip_left = static_cast<std::uint64_t>(byte_skip);
    std::uint64_t produced = 0;
    std::uint64_t consumed = 0;
    bool input_ended = false;
    while (produced < layout.bytes) {
        if (bz.avail_in == 0 && !input_ended) {
            const std::size_t got = std::fread(input.data(), 1, input.size(), file);
            if (got < input.size() && std::ferror(file)) {
                return base::make_error(base::ErrorCode::read_failed,
                                        std::string("read error: ") + std::strerror(errno),
                                        detail::at_byte(path, offset + consumed));
            }
            input_ended = got == 0;
            bz.next_in = input.data();
            bz.avail_in = static_cast<unsigned>(got);
        }
        const bool skipping = skip_left > 0;
        const std::span<std::byte> window = skipping ? std::span<std::byte>() : sink.window();
        if (skipping) {
            bz.next_out = scratch.data();
            bz.avail_out =
                    static_cast<unsigned>(std::min<std::uint64_t>(scratch.size(), skip_left));
        } else {
            bz.next_out = reinterpret_cast<char*>(window.data());
            bz.avail_out = static_cast<unsigned>(std::min<std::uint64_t>(window.size(), 1U << 30));
        }
        const unsigned in_before = bz.avail_in;
        const unsigned out_before = bz.avail_out;
        const int ret = BZ2_bzDecompress(&bz);
        consumed += in_before - bz.avail_in;
        const std::uint64_t out = out_before - bz.avail_out;
        if (skipping) {
            skip_left -= out;
        } else {
            sink.commit(static_cast<std::size_t>(out));
            produced += out;
        }
        if (ret != BZ_OK && ret != BZ_STREAM_END) {
            return base::make_error(base::ErrorCode::corrupt_data,
                                    "invalid bzip2 data (libbz2 error " + std::to_string(ret) + ")",
                                    detail::at_byte(path, offset + consumed));
        }
        if ((ret == BZ_STREAM_END || (input_ended && out == 0)) && produced < layout.bytes) {
            return base::make_error(base::ErrorCode::truncated,
                                    "expected " + std::to_string(layout.bytes) +
                                            " bytes of decompressed data, got " +
                                            std::to_string(produced),
                                    detail::at_byte(path, offset));
        }
    }
    return base::Ok{};
}

// Two hexadecimal digits a byte, in either case, whitespace anywhere between them; "byte skip"
// counts bytes of the file before the text, as teem reads it (and as for ASCII).
base::Status read_hex(std::FILE* file, const std::filesystem::path& path, const Layout& layout,
                      std::int64_t byte_skip, std::uint64_t offset, detail::SampleSink& sink) {
    offset += static_cast<std::uint64_t>(byte_skip);
    if (auto status = detail::seek_to(file, path, offset); !status) {
        return status.error();
    }
    const auto digit = [](int c) {
        if (c >= '0' && c <= '9') {
            return c - '0';
        }
        if (c >= 'a' && c <= 'f') {
            return c - 'a' + 10;
        }
        if (c >= 'A' && c <= 'F') {
            return c - 'A' + 10;
        }
        return -1;
    };
    std::vector<char> input(std::size_t{1} << 16);
    std::uint64_t consumed = 0;
    int high = -1;  // the first digit of a byte, once read
    while (!sink.full()) {
        const std::size_t got = std::fread(input.data(), 1, input.size(), file);
        if (got == 0) {
            if (std::ferror(file)) {
                return base::make_error(base::ErrorCode::read_failed,
                                        std::string("read error: ") + std::strerror(errno),
                                        detail::at_byte(path, offset + consumed));
            }
            return base::make_error(base::ErrorCode::truncated,
                                    "expected " + std::to_string(layout.bytes) +
                                            " bytes of hex data, got " +
                                            std::to_string(sink.received()),
                                    detail::at_byte(path, offset + consumed));
        }
        for (std::size_t i = 0; i < got && !sink.full(); ++i, ++consumed) {
            const char c = input[i];
            if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
                continue;
            }
            const int value = digit(static_cast<unsigned char>(c));
            if (value < 0) {
                char code[8];
                std::snprintf(code, sizeof code, "0x%02x", static_cast<unsigned char>(c));
                return base::make_error(base::ErrorCode::bad_data,
                                        std::string("byte ") + code + " is no hexadecimal digit",
                                        detail::at_byte(path, offset + consumed));
            }
            if (high < 0) {
                high = value;
                continue;
            }
            const auto byte = static_cast<std::byte>(high * 16 + value);
            high = -1;
            sink.window()[0] = byte;
            sink.commit(1);
        }
    }
    return base::Ok{};
}

base::Status read_gzip(std::FILE* file, const std::filesystem::path& path, const Layout& layout,
                       std::int64_t byte_skip, std::uint64_t offset, detail::SampleSink& sink) {
    // For compressed encodings NRRD applies "byte skip" to the decompressed data.
    auto inflated =
            detail::inflate_file(file, path, offset, static_cast<std::uint64_t>(byte_skip), sink);
    if (!inflated) {
        return inflated.error();
    }
    if (inflated->produced < layout.bytes) {
        return base::make_error(base::ErrorCode::truncated,
                                "expected " + std::to_string(layout.bytes) +
                                        " bytes of decompressed data, got " +
                                        std::to_string(inflated->produced),
                                detail::at_byte(path, offset));
    }
    if (!inflated->complete) {
        return base::make_error(base::ErrorCode::truncated,
                                "the gzip data is cut short before its end marker",
                                detail::at_byte(path, offset));
    }
    return base::Ok{};
}

// ASCII samples are stored in the type a Volume keeps for them, so the result is already in
// stored form (not in the file's sample type). The text is read in chunks, one number at a time:
// a load holds the volume and 64 KiB of text, whatever the file's size.
base::Result<std::vector<std::byte>> read_ascii(std::FILE* file, const std::filesystem::path& path,
                                                const Layout& layout, std::int64_t byte_skip,
                                                std::uint64_t offset) {
    offset += static_cast<std::uint64_t>(byte_skip);
    if (auto status = detail::seek_to(file, path, offset); !status) {
        return status.error();
    }
    // Longer than any number written in decimal; a longer token is no value of any type.
    constexpr std::size_t max_token = 128;
    const VoxelType stored = detail::stored_type(layout.type);
    std::vector<std::byte> samples(layout.voxels * bytes_per_voxel(stored));
    const auto is_separator = [](char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',';
    };
    std::uint64_t count = 0;
    std::string token;
    std::uint64_t token_start = 0;
    const auto store = [&]() -> base::Status {
        const auto value = parse_number<double>(token);
        const double low = stored == VoxelType::int16 ? -32768.0 : 0.0;
        const double high = stored == VoxelType::uint8   ? 255.0
                            : stored == VoxelType::int16 ? 32767.0
                                                         : 65535.0;
        if (!value || (stored != VoxelType::float32 &&
                       (*value != std::floor(*value) || *value < low || *value > high))) {
            return base::make_error(base::ErrorCode::bad_data,
                                    "'" + token.substr(0, max_token) + "' is not a " +
                                            detail::sample_name(layout.type) + " value",
                                    detail::at_byte(path, token_start));
        }
        switch (stored) {
            case VoxelType::uint8:
                samples[count] = static_cast<std::byte>(*value);
                break;
            case VoxelType::uint16: {
                const auto sample = static_cast<std::uint16_t>(*value);
                std::memcpy(samples.data() + count * 2, &sample, 2);
                break;
            }
            case VoxelType::int16: {
                const auto sample = static_cast<std::int16_t>(*value);
                std::memcpy(samples.data() + count * 2, &sample, 2);
                break;
            }
            case VoxelType::float32: {
                // Beyond float's range a cast is undefined; IEEE rounding gives ±infinity, which
                // make_volume counts as non-finite.
                constexpr float infinity = std::numeric_limits<float>::infinity();
                const float sample = std::abs(*value) > std::numeric_limits<float>::max()
                                             ? (*value > 0 ? infinity : -infinity)
                                             : static_cast<float>(*value);
                std::memcpy(samples.data() + count * 4, &sample, 4);
                break;
            }
        }
        ++count;
        token.clear();
        return base::Ok{};
    };
    std::array<char, 1 << 16> chunk{};
    std::uint64_t position = offset;
    bool ended = false;
    while (count < layout.voxels && !ended) {
        const std::size_t got = std::fread(chunk.data(), 1, chunk.size(), file);
        if (got < chunk.size()) {
            if (std::ferror(file)) {
                return base::make_error(base::ErrorCode::read_failed, "read error",
                                        detail::at_byte(path, position + got));
            }
            ended = true;
        }
        for (std::size_t k = 0; k < got && count < layout.voxels; ++k, ++position) {
            if (!is_separator(chunk[k])) {
                if (token.empty()) {
                    token_start = position;
                }
                if (token.size() == max_token) {
                    return base::make_error(
                            base::ErrorCode::bad_data,
                            "a value longer than " + std::to_string(max_token) + " characters",
                            detail::at_byte(path, token_start));
                }
                token.push_back(chunk[k]);
            } else if (!token.empty()) {
                if (auto status = store(); !status) {
                    return status.error();
                }
            }
        }
    }
    if (count < layout.voxels && !token.empty()) {
        if (auto status = store(); !status) {
            return status.error();
        }
    }
    if (count < layout.voxels) {
        return base::make_error(base::ErrorCode::truncated,
                                "expected " + std::to_string(layout.voxels) +
                                        " ASCII values, found " + std::to_string(count),
                                detail::at_byte(path, position));
    }
    return samples;
}

base::Result<Volume> load_nrrd_file(const std::filesystem::path& path, const LoadOptions& options) {
    auto file = detail::open_file(path);
    if (!file) {
        return file.error();
    }
    auto header = HeaderParser(file->get(), path).parse();
    if (!header) {
        return header.error();
    }
    auto layout = check_header(*header, path);
    if (!layout) {
        return layout.error();
    }
    auto source = data_path(*header, path);
    if (!source) {
        return source.error();
    }

    const detail::SampleLayout samples{
            .type = layout->type, .voxels = layout->voxels, .big_endian = layout->big_endian};
    std::string what = std::to_string(layout->dims.x) + "x" + std::to_string(layout->dims.y) + "x" +
                       std::to_string(layout->dims.z) + " " + detail::sample_name(layout->type);
    if (layout->volumes > 1) {
        base::log_info("volume", path.filename().string() + ": " + std::to_string(layout->volumes) +
                                         " volumes in the file; loading the first");
    }
    if (layout->components > 1) {
        base::log_info("volume", path.filename().string() + ": " +
                                         std::to_string(layout->components) +
                                         " values per voxel; loading the first");
        what += " (" + std::to_string(layout->components) + " values per voxel)";
    }
    if (!detail::is_kept(layout->type)) {
        what += std::string(" kept as ") + to_string(samples.stored());
    }
    if (auto status = detail::check_budget(samples.stored_bytes(), what, path, options); !status) {
        return status.error();
    }

    detail::File data_file;
    std::FILE* data = file->get();
    std::uint64_t offset = header->data_offset;
    if (header->data_file.value) {
        auto opened = detail::open_file(*source);
        if (!opened) {
            base::Error error = opened.error();
            error.message += " (named by 'data file' in " + path.filename().string() + ")";
            return error;
        }
        data_file = std::move(opened.value());
        data = data_file.get();
        offset = 0;
    } else if (auto status = detail::seek_to(data, path, offset); !status) {
        return status.error();
    }

    if (auto status = skip_lines(data, *source, header->line_skip.value.value_or(0), offset);
        !status) {
        return status.error();
    }
    const std::int64_t byte_skip = header->byte_skip.value.value_or(0);
    std::vector<std::byte> stored;
    if (layout->encoding == Encoding::ascii) {
        auto values = read_ascii(data, *source, *layout, byte_skip, offset);
        if (!values) {
            return values.error();
        }
        stored = std::move(values.value());
    } else {
        detail::SampleSink sink(samples);
        base::Status status = base::Ok{};
        if (layout->encoding == Encoding::raw) {
            auto start = raw_data_offset(*source, *layout, byte_skip, offset);
            status = start ? read_raw(data, *source, *layout, *start, sink)
                           : base::Status(start.error());
        } else if (layout->encoding == Encoding::gzip) {
            status = read_gzip(data, *source, *layout, byte_skip, offset, sink);
        } else if (layout->encoding == Encoding::hex) {
            status = read_hex(data, *source, *layout, byte_skip, offset, sink);
        } else {
            status = read_bzip2(data, *source, *layout, byte_skip, offset, sink);
        }
        if (!status) {
            return status.error();
        }
        stored = sink.take();
    }

    if (layout->components > 1) {
        // Each voxel's values lie together: its first is every components-th sample. Copied into
        // a buffer of its own size, so the volume holds what it counts.
        const std::size_t width = bytes_per_voxel(samples.stored());
        const std::uint64_t voxels = layout->voxels / layout->components;
        std::vector<std::byte> firsts(static_cast<std::size_t>(voxels * width));
        for (std::uint64_t v = 0; v < voxels; ++v) {
            std::memcpy(firsts.data() + v * width, stored.data() + v * layout->components * width,
                        width);
        }
        stored = std::move(firsts);
    }
    const std::string name =
            detail::strip_suffix(path, std::array<std::string_view, 2>{".nrrd", ".nhdr"});
    auto volume = make_volume(name, layout->dims, layout->geometry.spacing, samples.stored(),
                              std::move(stored));
    if (!volume) {
        base::Error error = volume.error();
        error.where = detail::at_file(path);
        return error;
    }
    if (auto placed = place_volume(*volume, layout->geometry, options); !placed) {
        base::Error error = placed.error();
        error.where = detail::at_file(path);
        return error;
    }
    volume->hounsfield = header->hounsfield;
    // Values per voxel count as volumes too: a label map must hold one of each.
    volume->volumes_in_file = layout->volumes * layout->components;
    return volume;
}

}  // namespace

base::Result<NrrdKeyValues> read_nrrd_key_values(const std::filesystem::path& path) {
    auto file = detail::open_file(path);
    if (!file) {
        return file.error();
    }
    auto header = HeaderParser(file->get(), path).parse();
    if (!header) {
        return header.error();
    }
    return std::move(header->key_values);
}

base::Result<Volume> load_nrrd(const std::filesystem::path& path, const LoadOptions& options) {
    return detail::guard_allocation(path, [&] { return load_nrrd_file(path, options); });
}

}  // namespace penumbra::volume
