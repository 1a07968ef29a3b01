#pragma once

// Reading tag values out of a DCMTK data set, for every part of the DICOM loader: DCMTK answers
// each read with a status and an out-parameter, and an absent or unreadable tag must read as no
// value (never as zero) the same way everywhere. Private to the volume module, which keeps DCMTK
// to itself.

#include "file_io.hpp"

#include <penumbra/base/result.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcitem.h>
#include <dcmtk/dcmdata/dctag.h>

namespace penumbra::volume::detail::dicom {

inline constexpr std::string_view log_component = "volume";

// "Rows (0028,0010)".
inline std::string tag_label(const DcmTagKey& key) {
    DcmTag tag(key);  // getTagName() is not const: it looks the name up on first use
    return std::string(tag.getTagName()) + " " + key.toString().c_str();
}

// "missing or unreadable tag Rows (0028,0010)", for a tag the file cannot do without.
inline base::Error missing_tag(const DcmTagKey& key, const std::filesystem::path& path) {
    return base::make_error(base::ErrorCode::bad_header,
                            "missing or unreadable tag " + tag_label(key), detail::at_file(path));
}

// Value `pos` of a numeric tag; a non-finite one reads as absent.
inline std::optional<double> get_double(DcmItem& item, const DcmTagKey& key,
                                        unsigned long pos = 0) {
    Float64 value = 0.0;
    if (item.findAndGetFloat64(key, value, pos).good() && std::isfinite(value)) {
        return value;
    }
    return std::nullopt;
}

// The first N values of a numeric tag, or nothing where any is absent.
template <std::size_t N>
std::optional<std::array<double, N>> get_doubles(DcmItem& item, const DcmTagKey& key) {
    std::array<double, N> values{};
    for (std::size_t i = 0; i < N; ++i) {
        const auto value = get_double(item, key, i);
        if (!value) {
            return std::nullopt;
        }
        values[i] = *value;
    }
    return values;
}

inline std::optional<std::int32_t> get_int(DcmItem& item, const DcmTagKey& key) {
    Sint32 value = 0;
    if (item.findAndGetSint32(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

inline std::optional<std::uint16_t> get_uint16(DcmItem& item, const DcmTagKey& key) {
    Uint16 value = 0;
    if (item.findAndGetUint16(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

// Empty where the tag is absent.
inline std::string get_string(DcmItem& item, const DcmTagKey& key) {
    OFString value;
    if (item.findAndGetOFString(key, value).good()) {
        return value.c_str();
    }
    return {};
}

// The item of functional group `group` (e.g. PlanePositionSequence) that applies to `frame` of
// an enhanced multi-frame image: the frame's own, else the shared one; null in other images.
inline DcmItem* functional_group(DcmItem& dataset, std::uint32_t frame, const DcmTagKey& group) {
    DcmItem* groups = nullptr;
    DcmItem* item = nullptr;
    if (dataset.findAndGetSequenceItem(DCM_PerFrameFunctionalGroupsSequence, groups,
                                       static_cast<signed long>(frame))
                .good() &&
        groups->findAndGetSequenceItem(group, item).good()) {
        return item;
    }
    if (dataset.findAndGetSequenceItem(DCM_SharedFunctionalGroupsSequence, groups).good() &&
        groups->findAndGetSequenceItem(group, item).good()) {
        return item;
    }
    return nullptr;
}

// A tag of one frame: from its functional group where the image has them, else from the top
// level, where classic single-frame images keep it.
template <class Get>
auto frame_value(DcmItem& dataset, std::uint32_t frame, const DcmTagKey& group, Get get)
        -> decltype(get(dataset)) {
    if (DcmItem* item = functional_group(dataset, frame, group)) {
        if (auto value = get(*item)) {
            return value;
        }
    }
    return get(dataset);
}

}  // namespace penumbra::volume::detail::dicom
