#include "dicom_writer.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>

#include <cstdio>
#include <stdexcept>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcddirif.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>

namespace penumbra::volume::fixtures {
namespace {

// DICOM decimal strings hold at most 16 characters.
std::string decimal(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", value);
    return text;
}

template <class... Values>
std::string decimals(Values... values) {
    std::string text;
    ((text += (text.empty() ? "" : "\\") + decimal(values)), ...);
    return text;
}

void check(const OFCondition& status, const std::string& what) {
    if (status.bad()) {
        throw std::runtime_error("writing a DICOM fixture: " + what + ": " + status.text());
    }
}

void put(DcmItem& item, const DcmTagKey& key, const std::string& value) {
    check(item.putAndInsertString(key, value.c_str()), DcmTag(key).getTagName());
}

void put(DcmItem& item, const DcmTagKey& key, std::uint16_t value) {
    check(item.putAndInsertUint16(key, value), DcmTag(key).getTagName());
}

std::string orientation_text(const SeriesSpec& spec) {
    const auto& o = spec.orientation;
    return decimals(o[0], o[1], o[2], o[3], o[4], o[5]);
}

std::string position_text(const SeriesSpec& spec, std::uint32_t z) {
    const glm::dvec3 p = slice_position(spec, z);
    return decimals(p.x, p.y, p.z);
}

// Everything but positions and pixel data.
void put_image_header(DcmDataset& dataset, const SeriesSpec& spec, std::int32_t instance) {
    put(dataset, DCM_SOPClassUID, std::string(UID_MRImageStorage));
    put(dataset, DCM_SOPInstanceUID, make_uid());
    put(dataset, DCM_StudyInstanceUID, std::string("1.2.276.0.7230010.3.1.2.1"));
    put(dataset, DCM_SeriesInstanceUID, spec.series_uid);
    put(dataset, DCM_Modality, std::string("MR"));
    if (!spec.series_number.empty()) {
        put(dataset, DCM_SeriesNumber, spec.series_number);
    }
    if (!spec.series_description.empty()) {
        put(dataset, DCM_SeriesDescription, spec.series_description);
    }
    put(dataset, DCM_PatientName, std::string("Colin27^Penumbra"));
    put(dataset, DCM_InstanceNumber, std::to_string(instance));
    put(dataset, DCM_SamplesPerPixel, std::uint16_t{1});
    put(dataset, DCM_PhotometricInterpretation, std::string("MONOCHROME2"));
    put(dataset, DCM_Rows, static_cast<std::uint16_t>(spec.dims.y));
    put(dataset, DCM_Columns, static_cast<std::uint16_t>(spec.dims.x));
    put(dataset, DCM_BitsAllocated, spec.bits_allocated);
    put(dataset, DCM_BitsStored, spec.bits_stored);
    put(dataset, DCM_HighBit, static_cast<std::uint16_t>(spec.bits_stored - 1));
    put(dataset, DCM_PixelRepresentation, static_cast<std::uint16_t>(spec.is_signed ? 1 : 0));
    if (spec.slope) {
        put(dataset, DCM_RescaleSlope, decimal(*spec.slope));
    }
    if (spec.intercept) {
        put(dataset, DCM_RescaleIntercept, decimal(*spec.intercept));
    }
}

void put_pixels(DcmDataset& dataset, const SeriesSpec& spec,
                const std::vector<std::uint16_t>& words, const std::vector<std::uint32_t>& slices) {
    const std::size_t slice_words = std::size_t{spec.dims.x} * spec.dims.y;
    for (const std::uint32_t z : slices) {
        if (words.size() < (std::size_t{z} + 1) * slice_words) {
            throw std::runtime_error("writing a DICOM fixture: fewer words than the dims need");
        }
    }
    if (spec.bits_allocated == 8) {
        std::vector<Uint8> bytes;
        for (const std::uint32_t z : slices) {
            for (std::size_t i = 0; i < slice_words; ++i) {
                bytes.push_back(static_cast<Uint8>(words[z * slice_words + i]));
            }
        }
        check(dataset.putAndInsertUint8Array(DCM_PixelData, bytes.data(), bytes.size()),
              "PixelData");
    } else {
        std::vector<Uint16> values;
        for (const std::uint32_t z : slices) {
            values.insert(values.end(), words.begin() + z * slice_words,
                          words.begin() + (z + 1) * slice_words);
        }
        check(dataset.putAndInsertUint16Array(DCM_PixelData, values.data(), values.size()),
              "PixelData");
    }
}

void save(DcmFileFormat& file, const SeriesSpec& spec, const std::filesystem::path& path) {
    if (spec.edit) {
        spec.edit(*file.getDataset());
    }
    check(file.saveFile(path.c_str(),
                        spec.explicit_vr ? EXS_LittleEndianExplicit : EXS_LittleEndianImplicit),
          path.string());
}

}  // namespace

std::string make_uid() {
    char uid[100];
    dcmGenerateUniqueIdentifier(uid, SITE_INSTANCE_UID_ROOT);
    return uid;
}

void write_dicomdir(const std::filesystem::path& root,
                    const std::vector<std::filesystem::path>& files) {
    const std::filesystem::path dicomdir = root / "DICOMDIR";
    DicomDirInterface writer;
    writer.enableInventMode(OFTrue);  // patient id, study id and dates the fixtures leave out
    check(writer.createNewDicomDir(DicomDirInterface::AP_GeneralPurpose, dicomdir.c_str()),
          "DICOMDIR");
    for (const auto& file : files) {
        check(writer.addDicomFile(file.lexically_relative(root).c_str(), root.c_str()),
              file.string());
    }
    check(writer.writeDicomDir(), "DICOMDIR");
}

glm::dvec3 slice_position(const SeriesSpec& spec, std::uint32_t z) {
    const auto& o = spec.orientation;
    const glm::dvec3 normal =
            glm::cross(glm::dvec3(o[0], o[1], o[2]), glm::dvec3(o[3], o[4], o[5]));
    return spec.origin + static_cast<double>(z) * spec.spacing.z * normal;
}

void write_slice(const std::filesystem::path& path, const SeriesSpec& spec, std::uint32_t z,
                 const std::vector<std::uint16_t>& words, std::int32_t instance_number) {
    DcmFileFormat file;
    DcmDataset& dataset = *file.getDataset();
    put_image_header(dataset, spec, instance_number);
    put(dataset, DCM_PixelSpacing, decimals(spec.spacing.y, spec.spacing.x));
    put(dataset, DCM_SliceThickness, decimal(spec.spacing.z));
    if (spec.positions) {
        put(dataset, DCM_ImagePositionPatient, position_text(spec, z));
        put(dataset, DCM_ImageOrientationPatient, orientation_text(spec));
    }
    put_pixels(dataset, spec, words, {z});
    save(file, spec, path);
}

std::vector<std::filesystem::path> write_series(const std::filesystem::path& folder,
                                                SeriesSpec spec,
                                                const std::vector<std::uint16_t>& words) {
    if (spec.series_uid.empty()) {
        spec.series_uid = make_uid();
    }
    std::filesystem::create_directories(folder);
    std::vector<std::filesystem::path> paths;
    for (std::uint32_t z = 0; z < spec.dims.z; ++z) {
        char name[32];
        std::snprintf(name, sizeof name, "slice_%03u.dcm", z);
        paths.push_back(folder / name);
        write_slice(paths.back(), spec, z, words, static_cast<std::int32_t>(z + 1));
    }
    return paths;
}

void write_multiframe(const std::filesystem::path& path, const SeriesSpec& original,
                      const std::vector<std::uint16_t>& words,
                      const std::vector<std::uint32_t>& frame_order) {
    SeriesSpec spec = original;
    if (spec.series_uid.empty()) {
        spec.series_uid = make_uid();
    }
    DcmFileFormat file;
    DcmDataset& dataset = *file.getDataset();
    put_image_header(dataset, spec, 1);
    put(dataset, DCM_SOPClassUID, std::string(UID_EnhancedMRImageStorage));
    put(dataset, DCM_NumberOfFrames, std::to_string(frame_order.size()));

    DcmItem* shared = nullptr;
    check(dataset.findOrCreateSequenceItem(DCM_SharedFunctionalGroupsSequence, shared, 0),
          "SharedFunctionalGroupsSequence");
    DcmItem* measures = nullptr;
    check(shared->findOrCreateSequenceItem(DCM_PixelMeasuresSequence, measures, 0),
          "PixelMeasuresSequence");
    put(*measures, DCM_PixelSpacing, decimals(spec.spacing.y, spec.spacing.x));
    put(*measures, DCM_SliceThickness, decimal(spec.spacing.z));
    DcmItem* orientation = nullptr;
    check(shared->findOrCreateSequenceItem(DCM_PlaneOrientationSequence, orientation, 0),
          "PlaneOrientationSequence");
    put(*orientation, DCM_ImageOrientationPatient, orientation_text(spec));

    for (std::size_t f = 0; f < frame_order.size(); ++f) {
        DcmItem* frame = nullptr;
        constexpr signed long append = -2;
        check(dataset.findOrCreateSequenceItem(DCM_PerFrameFunctionalGroupsSequence, frame, append),
              "PerFrameFunctionalGroupsSequence");
        DcmItem* position = nullptr;
        check(frame->findOrCreateSequenceItem(DCM_PlanePositionSequence, position, 0),
              "PlanePositionSequence");
        put(*position, DCM_ImagePositionPatient, position_text(spec, frame_order[f]));
    }
    put_pixels(dataset, spec, words, frame_order);
    save(file, spec, path);
}

std::vector<std::uint16_t> ch2_box(glm::uvec3 first, glm::uvec3 dims) {
    static const auto ch2 = load_nifti("/usr/share/mricron/templates/ch2.nii.gz");
    if (!ch2) {
        throw std::runtime_error("ch2 (Debian package mricron-data) is needed: " +
                                 ch2.error().to_string());
    }
    std::vector<std::uint16_t> words;
    words.reserve(std::size_t{dims.x} * dims.y * dims.z);
    for (std::uint32_t z = 0; z < dims.z; ++z) {
        for (std::uint32_t y = 0; y < dims.y; ++y) {
            for (std::uint32_t x = 0; x < dims.x; ++x) {
                words.push_back(static_cast<std::uint16_t>(
                        ch2->value(first.x + x, first.y + y, first.z + z)));
            }
        }
    }
    return words;
}

}  // namespace penumbra::volume::fixtures
