// In a folder, only DICOM Part 10 files (the "DICM" marker after the 128-byte preamble) are read;
// other files (README.txt, .DS_Store, thumbnails) and DICOM objects without pixel data (DICOMDIR,
// reports) are skipped and counted in the log, and images of another kind (colour secondary
// captures, float or odd bit depths, mosaics that cannot be unpacked) are skipped with a warning
// naming each, so the series beside them opens; a folder of nothing else is that image's error.
// Damaged files (cut short, unreadable headers) are skipped too, each named in a note on the
// volume; a slice of the series lost with one is a gap, which refuses the series (the spacing
// check, or the damaged file's own position where DCMTK read that far).
// Sub-folders are searched too (unless LoadOptions says not), at most max_folder_depth levels and
// max_folder_files files deep: a DICOMDIR export root keeps its images in
// DICOM/<patient>/<study>/<series>/ and a study folder has one folder per series. The DICOMDIR
// itself is not needed: every image file names its own series.

#include "dicom_files.hpp"

#include "dicom_tags.hpp"
#include "file_io.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace penumbra::volume {
namespace detail::dicom {
namespace {

// How deep and how wide a folder's search for image files goes: a DICOMDIR export keeps its
// images four levels below the root (DICOM/<patient>/<study>/<series>/), and no volume has more
// files than it may have frames; the bounds keep a mistaken `--volume /` from walking a disk.
constexpr int max_folder_depth = 5;
constexpr std::uint64_t max_folder_files = max_frames;

// The files below the folder (in sub-folders too when `subfolders`) that carry the DICOM Part 10
// marker, in path order so that logs and fallbacks are reproducible. Hidden files and folders
// and links to folders are passed over.
base::Result<std::vector<std::filesystem::path>> dicom_files_in(
        const std::filesystem::path& folder, bool subfolders,
        std::vector<std::filesystem::path>& not_dicom) {
    std::error_code ec;
    std::vector<std::filesystem::path> files;
    std::uint64_t seen = 0;
    for (auto it = std::filesystem::recursive_directory_iterator(
                 folder, std::filesystem::directory_options::skip_permission_denied, ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (it->is_directory(ec)) {
            if (!subfolders || name.starts_with('.') || it.depth() + 1 >= max_folder_depth) {
                it.disable_recursion_pending();
            }
            continue;
        }
        if (!it->is_regular_file(ec) || name.starts_with('.')) {
            continue;
        }
        if (++seen > max_folder_files) {
            return base::make_error(base::ErrorCode::too_large,
                                    "the folder holds more than " +
                                            std::to_string(max_folder_files) +
                                            " files (sub-folders included); open the series' "
                                            "own folder",
                                    detail::at_file(folder));
        }
        if (is_dicom_file(it->path())) {
            files.push_back(it->path());
        } else {
            not_dicom.push_back(it->path());
        }
    }
    if (ec) {
        return base::make_error(base::ErrorCode::read_failed,
                                "cannot list the folder: " + ec.message(), detail::at_file(folder));
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

std::vector<std::string> FolderImages::notes() const {
    std::vector<std::string> lines;
    for (const Damaged& file : damaged) {
        lines.push_back("skipped " + file.error.where + " (" +
                        std::string(base::name_of(file.error.code)) + ": " + file.error.message +
                        "); whatever slices it holds are not in the volume");
    }
    if (!not_dicom.empty()) {
        // A few names say what the files are; an export's thousand thumbnails need no list.
        constexpr std::size_t named = 5;
        std::string names;
        for (std::size_t i = 0; i < std::min(named, not_dicom.size()); ++i) {
            names += (i == 0 ? "" : ", ") + not_dicom[i].filename().string();
        }
        if (not_dicom.size() > named) {
            names += ", ...";
        }
        lines.push_back("skipped " + std::to_string(not_dicom.size()) +
                        " file(s) that are not DICOM (no DICM marker): " + names);
    }
    return lines;
}

std::string FolderImages::damaged_suffix() const {
    if (damaged.empty()) {
        return {};
    }
    std::string names;
    for (const Damaged& file : damaged) {
        names += (names.empty() ? "" : ", ") + file.error.where;
    }
    return " (skipped as damaged: " + names + ")";
}

base::Result<FolderImages> read_folder(const std::filesystem::path& folder, bool subfolders,
                                       bool keep_files) {
    FolderImages found;
    auto files = dicom_files_in(folder, subfolders, found.not_dicom);
    if (!files) {
        return files.error();
    }
    for (const auto& path : *files) {
        Image image;
        auto opened = open_image(path, image);
        // An image of another kind (an RGB secondary capture, a screenshot of a dose report) is
        // not a slice of any series here: skipped with a warning, so the series beside it opens.
        if (!opened && opened.error().code == base::ErrorCode::unsupported_type) {
            base::log_warning(log_component,
                              "skipped " + opened.error().where + ": " + opened.error().message);
            if (!found.other_kind) {
                found.other_kind = opened.error();
            }
            continue;
        }
        // A file carrying the DICOM marker that cannot be read (a copy cut short, a damaged
        // header) is no reason to refuse its neighbours: skipped and noted, and a slice it held
        // inside the series shows as the gap the spacing check refuses.
        if (!opened) {
            base::log_warning(log_component, "skipped " + opened.error().to_string());
            // DCMTK keeps what it parsed before the damage: a file cut short in its pixel data
            // still says where its slice lies, which tells a gap inside the series from a
            // slice missing at an end.
            FolderImages::Damaged damaged{opened.error(), {}, {}};
            if (image.file && image.file->getDataset() != nullptr) {
                DcmDataset& dataset = *image.file->getDataset();
                damaged.series_uid = get_string(dataset, DCM_SeriesInstanceUID);
                damaged.position = get_doubles<3>(dataset, DCM_ImagePositionPatient);
            }
            found.damaged.push_back(std::move(damaged));
            continue;
        }
        if (*opened == Opened::not_an_image) {
            ++found.not_images;
            continue;
        }
        if (!keep_files) {
            image.file.reset();
        }
        found.images.push_back(std::move(image));
    }
    if (found.images.empty() && !found.damaged.empty()) {
        return found.damaged.front().error;
    }
    if (found.images.empty() && found.other_kind) {
        return *found.other_kind;
    }
    if (found.images.empty() && found.not_dicom.empty() && found.not_images == 0) {
        return base::make_error(base::ErrorCode::no_dicom_images, "the folder holds no files",
                                detail::at_file(folder));
    }
    if (found.images.empty()) {
        return base::make_error(base::ErrorCode::no_dicom_images,
                                "the folder holds no DICOM image files (" +
                                        std::to_string(found.not_dicom.size()) + " other files, " +
                                        std::to_string(found.not_images) +
                                        " DICOM files without pixel data)",
                                detail::at_file(folder));
    }
    return found;
}

}  // namespace detail::dicom

bool is_dicom_file(const std::filesystem::path& path) {
    // Opened without blocking and checked through the descriptor: a FIFO put in a file's place
    // after the folder was listed would otherwise hold the caller at open() forever.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        return false;
    }

    struct stat info {};

    std::array<char, 132> head{};
    const bool read = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) &&
                      ::pread(fd, head.data(), head.size(), 0) == static_cast<ssize_t>(head.size());
    ::close(fd);
    return read && std::string_view(head.data() + 128, 4) == "DICM";
}

}  // namespace penumbra::volume
