// DCMTK's getters, which answer with a status and an out-parameter, as optional values.

#include "dicom_tags.hpp"

#include "file_io.hpp"

#include <cmath>

#include <dcmtk/dcmdata/dctag.h>

namespace penumbra::volume::detail::dicom {
namespace {

std::string tag_label(const DcmTagKey& key) {
    DcmTag tag(key);  // getTagName() is not const: it looks the name up on first use
    return std::string(tag.getTagName()) + " " + key.toString().c_str();
}

}  // namespace

base::Error missing_tag(const DcmTagKey& key, const std::filesystem::path& path) {
    return base::make_error("bad_header", "missing or unreadable tag " + tag_label(key),
                            detail::at_file(path));
}

std::optional<double> get_double(DcmItem& item, const DcmTagKey& key, unsigned long pos) {
    Float64 value = 0.0;
    if (item.findAndGetFloat64(key, value, pos).good() && std::isfinite(value)) {
        return value;
    }
    return std::nullopt;
}

std::optional<std::int32_t> get_int(DcmItem& item, const DcmTagKey& key) {
    Sint32 value = 0;
    if (item.findAndGetSint32(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

std::optional<std::uint16_t> get_uint16(DcmItem& item, const DcmTagKey& key) {
    Uint16 value = 0;
    if (item.findAndGetUint16(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

std::string get_string(DcmItem& item, const DcmTagKey& key) {
    OFString value;
    if (item.findAndGetOFString(key, value).good()) {
        return value.c_str();
    }
    return {};
}

DcmItem* functional_group(DcmItem& dataset, std::uint32_t frame, const DcmTagKey& group) {
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

}  // namespace penumbra::volume::detail::dicom
