// The build without OpenImageIO (PENUMBRA_WITH_OPENIMAGEIO=OFF): what needs it says so.

#include <string>

#include "penumbra/imageio/compare.hpp"
#include "penumbra/imageio/imageio.hpp"

namespace penumbra::imageio {
namespace {

base::Error unavailable(const std::string& what) {
    return base::make_error(base::ErrorCode::image_io_unavailable,
                            "this penumbra was built without OpenImageIO "
                            "(PENUMBRA_WITH_OPENIMAGEIO=OFF), so it cannot " +
                                    what,
                            "imageio");
}

}  // namespace

bool available() {
    return false;
}

base::Result<base::ImageRgba8> decode_image(std::span<const std::uint8_t> /*bytes*/) {
    return unavailable("decode images");
}

base::Result<base::ImageRgba8> read_image(const std::filesystem::path& path) {
    return unavailable("read " + path.string());
}

base::Result<std::vector<std::uint8_t>> encode_image_openimageio(const base::ImageRgba8& /*image*/,
                                                                 encode::ImageFormat /*format*/,
                                                                 int /*jpeg_quality*/) {
    return unavailable("encode through OpenImageIO");
}

base::Result<ImageDifference> compare_images(const base::ImageRgbaF& /*a*/,
                                             const base::ImageRgbaF& /*b*/) {
    return unavailable("compare images");
}

base::Result<base::ImageRgba8> stretched(const base::ImageRgba8& /*image*/, int /*width*/,
                                         int /*height*/) {
    return unavailable("resample images");
}

}  // namespace penumbra::imageio
