#include "dicom_writer.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcddirif.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcpixel.h>
#include <dcmtk/dcmdata/dcpixseq.h>
#include <dcmtk/dcmdata/dcpxitem.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <openjpeg.h>

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

void save(DcmFileFormat& file, const SeriesSpec& spec, const std::filesystem::path& path,
          E_TransferSyntax syntax = EXS_Unknown) {
    if (spec.edit) {
        spec.edit(*file.getDataset());
    }
    if (syntax == EXS_Unknown) {
        syntax = spec.explicit_vr ? EXS_LittleEndianExplicit : EXS_LittleEndianImplicit;
    }
    check(file.saveFile(path.c_str(), syntax), path.string());
}

// One frame as a JPEG 2000 codestream (OpenJPEG; lossless unless `ratio` > 0).
std::vector<std::uint8_t> encode_jpeg2000(const std::uint16_t* words, const SeriesSpec& spec,
                                          double ratio, bool jp2) {
    opj_image_cmptparm_t component{};
    component.dx = component.dy = 1;
    component.w = spec.dims.x;
    component.h = spec.dims.y;
    component.prec = spec.bits_stored;
    component.sgnd = spec.is_signed ? 1 : 0;
    std::unique_ptr<opj_image_t, void (*)(opj_image_t*)> image(
            opj_image_create(1, &component, OPJ_CLRSPC_GRAY), opj_image_destroy);
    if (!image) {
        throw std::runtime_error("writing a DICOM fixture: opj_image_create failed");
    }
    image->x1 = spec.dims.x;
    image->y1 = spec.dims.y;
    const std::size_t pixels = std::size_t{spec.dims.x} * spec.dims.y;
    for (std::size_t i = 0; i < pixels; ++i) {
        image->comps[0].data[i] = spec.is_signed ? static_cast<std::int16_t>(words[i]) : words[i];
    }
    opj_cparameters_t parameters;
    opj_set_default_encoder_parameters(&parameters);
    parameters.tcp_numlayers = 1;
    parameters.cp_disto_alloc = 1;
    parameters.tcp_rates[0] = static_cast<float>(ratio);  // 0: lossless
    parameters.irreversible = ratio > 0.0 ? 1 : 0;
    // Each resolution halves the image: a small one has fewer than OpenJPEG's default six.
    while (parameters.numresolution > 1 &&
           (1u << (parameters.numresolution - 1)) > std::min(spec.dims.x, spec.dims.y)) {
        --parameters.numresolution;
    }
    std::unique_ptr<opj_codec_t, void (*)(opj_codec_t*)> codec(
            opj_create_compress(jp2 ? OPJ_CODEC_JP2 : OPJ_CODEC_J2K), opj_destroy_codec);

    // The encoder may seek back to fill in a length: a buffer with a write position.
    struct Output {
        std::vector<std::uint8_t> bytes;
        std::size_t position = 0;
    } output;

    std::unique_ptr<opj_stream_t, void (*)(opj_stream_t*)> stream(
            opj_stream_create(1 << 16, OPJ_FALSE), opj_stream_destroy);
    opj_stream_set_user_data(stream.get(), &output, nullptr);
    opj_stream_set_write_function(stream.get(), [](void* data, OPJ_SIZE_T size, void* user) {
        auto& out = *static_cast<Output*>(user);
        out.bytes.resize(std::max(out.bytes.size(), out.position + size));
        std::memcpy(out.bytes.data() + out.position, data, size);
        out.position += size;
        return size;
    });
    opj_stream_set_skip_function(stream.get(), [](OPJ_OFF_T count, void* user) -> OPJ_OFF_T {
        auto& out = *static_cast<Output*>(user);
        out.position += static_cast<std::size_t>(count);
        out.bytes.resize(std::max(out.bytes.size(), out.position));
        return count;
    });
    opj_stream_set_seek_function(stream.get(), [](OPJ_OFF_T position, void* user) -> OPJ_BOOL {
        auto& out = *static_cast<Output*>(user);
        out.position = static_cast<std::size_t>(position);
        out.bytes.resize(std::max(out.bytes.size(), out.position));
        return OPJ_TRUE;
    });
    if (opj_setup_encoder(codec.get(), &parameters, image.get()) == OPJ_FALSE ||
        opj_start_compress(codec.get(), image.get(), stream.get()) == OPJ_FALSE ||
        opj_encode(codec.get(), stream.get()) == OPJ_FALSE ||
        opj_end_compress(codec.get(), stream.get()) == OPJ_FALSE) {
        throw std::runtime_error("writing a DICOM fixture: OpenJPEG could not encode a frame");
    }
    return output.bytes;
}

// The frames as encapsulated JPEG 2000 pixel data, each split over `fragments` fragments.
void put_jpeg2000_pixels(DcmDataset& dataset, const SeriesSpec& spec,
                         const std::vector<std::uint16_t>& words,
                         const std::vector<std::uint32_t>& slices) {
    const std::size_t slice_words = std::size_t{spec.dims.x} * spec.dims.y;
    auto* sequence = new DcmPixelSequence(DCM_PixelSequenceTag);
    sequence->insert(new DcmPixelItem(DCM_PixelItemTag));  // an empty offset table
    for (const std::uint32_t z : slices) {
        const auto codestream = encode_jpeg2000(words.data() + z * slice_words, spec,
                                                spec.jpeg2000_ratio, spec.jpeg2000_jp2);
        const std::size_t parts = static_cast<std::size_t>(spec.jpeg2000_fragments);
        const std::size_t part = (codestream.size() / parts + 1) & ~std::size_t{1};  // even
        for (std::size_t begin = 0; begin < codestream.size(); begin += part) {
            const std::size_t size = std::min(part, codestream.size() - begin);
            std::vector<Uint8> fragment(codestream.begin() + begin,
                                        codestream.begin() + begin + size);
            if (fragment.size() % 2 != 0) {
                fragment.push_back(0);  // fragments have even lengths
            }
            auto* item = new DcmPixelItem(DCM_PixelItemTag);
            check(item->putUint8Array(fragment.data(), fragment.size()), "a JPEG 2000 fragment");
            sequence->insert(item);
        }
    }
    auto* pixels = new DcmPixelData(DCM_PixelData);
    pixels->putOriginalRepresentation(
            spec.jpeg2000_ratio > 0.0 ? EXS_JPEG2000 : EXS_JPEG2000LosslessOnly, nullptr, sequence);
    check(dataset.insert(pixels, true), "PixelData");
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
    if (spec.jpeg2000_fragments > 0) {
        put_jpeg2000_pixels(dataset, spec, words, frame_order);
        save(file, spec, path, spec.jpeg2000_ratio > 0.0 ? EXS_JPEG2000 : EXS_JPEG2000LosslessOnly);
    } else {
        put_pixels(dataset, spec, words, frame_order);
        save(file, spec, path);
    }
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
