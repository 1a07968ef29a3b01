#pragma once

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcxfer.h>

class DcmDataset;

namespace penumbra::volume::detail::dicom {

// DICOM's JPEG 2000 transfer syntaxes (Part 1 lossless and lossy, Part 2 multi-component), which
// Debian's DCMTK has no codec for: OpenJPEG decodes them.
[[nodiscard]] bool is_jpeg2000(E_TransferSyntax syntax);

// Decodes every frame of an image's encapsulated JPEG 2000 pixel data (a codestream per frame,
// or a JP2 file, over one or several fragments) into pixel words as the uncompressed data would
// hold them: `format.bits_allocated` bits each, little endian, frame after frame. The header's
// PixelRepresentation reads the codestream's bits, as GDCM and pydicom do (an unsigned codestream
// of a signed image, the "pixel representation mismatch" files, holds two's complement); where
// the codestream is signed or more precise than the header says, `format` is updated to hold it.
// Fails with a clear error for a codestream of another size or several components, and for data
// OpenJPEG cannot decode.
base::Result<std::vector<std::byte>> decode_jpeg2000(DcmDataset& dataset, std::uint32_t frames,
                                                     PixelFormat& format,
                                                     const std::filesystem::path& path);

}  // namespace penumbra::volume::detail::dicom
