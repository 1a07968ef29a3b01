#include "penumbra/session/volume_store.hpp"

#include <penumbra/base/log.hpp>

#include <algorithm>
#include <optional>
#include <set>

namespace penumbra::session {
namespace {

// The DICOM files of one folder make its series' volumes, so such a folder's series are listed,
// not its files.
struct DicomFiles {
    std::uintmax_t bytes = 0;  // of the folder's files
    // The names, sizes and modification times of the folder's files: while it stays the same,
    // so do the series the headers name.
    std::string signature;
};

// The folder's files when at least one is DICOM. DICOM file names are arbitrary, so the content
// decides; the search stops opening files at the first DICOM one.
std::optional<DicomFiles> dicom_files(const std::filesystem::path& folder) {
    std::error_code ec;
    bool found = false;
    DicomFiles files;
    for (auto it = std::filesystem::directory_iterator(
                 folder, std::filesystem::directory_options::skip_permission_denied, ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (!it->is_regular_file(ec) || it->is_symlink(ec) || name.starts_with('.') ||
            volume::is_volume_file_name(it->path())) {
            continue;
        }
        const std::uintmax_t size = it->file_size(ec);
        files.bytes += size;
        files.signature += name + '/' + std::to_string(size) + '/' +
                           std::to_string(it->last_write_time(ec).time_since_epoch().count()) +
                           '\n';
        found = found || volume::is_dicom_file(it->path());
    }
    return found ? std::optional(std::move(files)) : std::nullopt;
}

// Why a file was not listed: what a volume's name ends with.
std::string not_a_volume_reason() {
    std::string reason = "not a volume (names ending";
    for (const std::string_view suffix : volume::volume_suffixes()) {
        reason += " " + std::string(suffix);
    }
    return reason + ", or DICOM files in a folder)";
}

}  // namespace

VolumeSummary summarize(const std::string& id, const std::string& name,
                        const volume::Volume* volume) {
    VolumeSummary out;
    out.id = id;
    out.name = volume != nullptr ? volume->name : name;
    out.loaded = volume != nullptr;
    if (volume != nullptr) {
        out.dims = volume->dims;
        out.spacing = volume->spacing;
        out.voxel_type = volume::to_string(volume->type);
        out.min = volume->range.min;
        out.max = volume->range.max;
        out.hounsfield = volume->hounsfield;
    }
    return out;
}

VolumeStore::VolumeStore(std::filesystem::path data_dir, std::size_t memory_budget,
                         volume::LoadOptions load_options,
                         std::chrono::milliseconds rescan_interval, int loader_threads)
    : data_dir_(std::move(data_dir))
    , load_options_(std::move(load_options))
    , rescan_interval_(rescan_interval)
    , loaded_(memory_budget,
              {.on_evict =
                       [](const auto& entry) {
                           base::log_info("volumes", "dropped " + entry.key + " (memory budget)");
                       }})
    , loaders_(loader_threads) {
    rescanner_ = std::thread([this] { rescan_loop(); });
}

VolumeStore::~VolumeStore() {
    {
        const std::lock_guard lock(rescan_mutex_);
        stopping_ = true;
    }
    rescan_wake_.notify_all();
    rescanner_.join();
}

void VolumeStore::rescan_loop() {
    std::unique_lock lock(rescan_mutex_);
    while (true) {
        rescan_wake_.wait_for(lock, rescan_interval_,
                              [&] { return stopping_ || rescan_requested_; });
        if (stopping_) {
            return;
        }
        rescan_requested_ = false;
        lock.unlock();
        if (auto status = scan(); !status) {
            base::log_error("volumes", status.error().to_string());
        }
        lock.lock();
    }
}

base::Status VolumeStore::scan() {
    std::error_code ec;
    if (!std::filesystem::is_directory(data_dir_, ec)) {
        return base::make_error(base::ErrorCode::not_found, "the data directory does not exist",
                                data_dir_.string());
    }
    // Taken before the walk: a change during it asks for another scan.
    const auto mtime = std::filesystem::last_write_time(data_dir_, ec);
    std::vector<VolumeEntry> found;
    std::vector<std::string> skipped;
    std::set<std::filesystem::path> dicom_folders;
    // Ids are the paths as walked, below `top`: lexically, never through the links they pass.
    std::filesystem::path top = data_dir_;
    if (!top.has_filename() && top.has_parent_path()) {
        top = top.parent_path();  // "data/" walks as "data"
    }
    const auto relative = [&](const std::filesystem::path& path) {
        return path.lexically_relative(top).generic_string();
    };
    const auto skip = [&](const std::filesystem::path& path, const std::string& why) {
        skipped.push_back(relative(path) + ": " + why);
    };
    // A folder's DICOM files are one entry per series: under the folder's id where it holds one
    // series, else "folder#number" (or "#UID" where numbers repeat). A folder whose headers
    // cannot be read is listed whole, so that opening it tells why.
    const auto add_series_if_dicom = [&](const std::filesystem::path& folder) {
        const auto files = dicom_files(folder);
        if (!files) {
            return false;
        }
        VolumeEntry entry;
        entry.path = folder;
        entry.id = relative(folder);
        entry.name = entry.id;
        entry.file_bytes = files->bytes;
        dicom_folders.insert(folder);
        const auto series = dicom_series(folder, files->signature);
        if (!series && series.error().code == base::ErrorCode::no_dicom_images) {
            skip(folder,
                 "DICOM files without images (" + relative_paths(series.error().message) + ")");
            return true;
        }
        if (!series || series->size() == 1) {
            entry.dicom_series = series ? series->front().uid : std::string();
            found.push_back(std::move(entry));
            return true;
        }
        std::size_t all_images = 0;
        for (const volume::DicomSeries& one : *series) {
            all_images += one.images;
        }
        for (const volume::DicomSeries& one : *series) {
            const bool number_unique =
                    !one.number.empty() &&
                    std::count_if(series->begin(), series->end(), [&](const auto& other) {
                        return other.number == one.number;
                    }) == 1;
            VolumeEntry part = entry;
            part.id += "#" + (number_unique ? one.number : one.uid);
            part.name = one.label();
            part.dicom_series = one.uid;
            // Each series' share of the folder's bytes, by its number of files.
            part.file_bytes = entry.file_bytes * one.images / std::max<std::size_t>(1, all_images);
            found.push_back(std::move(part));
        }
        return true;
    };
    // Links the administrator put in the data folder are followed, to files and to folders; a
    // volume keeps the name of the link (clients name volumes by the listed id only, never by
    // path). A folder reached twice (a link loop, or two links to one folder) is walked once.
    std::set<std::filesystem::path> walked{std::filesystem::canonical(top, ec)};
    const bool top_is_series = add_series_if_dicom(top);
    for (auto it = std::filesystem::recursive_directory_iterator(
                 top,
                 std::filesystem::directory_options::skip_permission_denied |
                         std::filesystem::directory_options::follow_directory_symlink,
                 ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
        const std::filesystem::path& path = it->path();
        const std::string name = path.filename().string();
        if (name.starts_with('.')) {
            it.disable_recursion_pending();
            continue;
        }
        std::error_code status_error;
        const auto status = std::filesystem::status(path, status_error);
        if (status_error || !std::filesystem::exists(status)) {
            skip(path, it->is_symlink(ec) ? "a link to nothing (" + status_error.message() + ")"
                                          : "cannot be read (" + status_error.message() + ")");
            continue;
        }
        if (std::filesystem::is_directory(status)) {
            if (!walked.insert(std::filesystem::canonical(path, ec)).second) {
                skip(path, "a folder already listed through another path (a link loop?)");
                it.disable_recursion_pending();
                continue;
            }
            add_series_if_dicom(path);
            continue;
        }
        if (!std::filesystem::is_regular_file(status)) {
            skip(path, "not a regular file");
            continue;
        }
        if (!volume::is_volume_file_name(path)) {
            const bool in_series =
                    (path.parent_path() == top && top_is_series) ||
                    std::any_of(found.begin(), found.end(),
                                [&](const VolumeEntry& e) { return e.path == path.parent_path(); });
            // The data of a .hdr/.img pair, listed as its header.
            const bool pair_data =
                    path.extension() == ".img" &&
                    std::filesystem::exists(std::filesystem::path(path).replace_extension(".hdr"),
                                            ec);
            if (!in_series && !pair_data) {
                skip(path, not_a_volume_reason());
            }
            continue;
        }
        VolumeEntry entry;
        entry.path = path;
        entry.id = relative(path);
        entry.name = entry.id;
        entry.file_bytes = std::filesystem::file_size(path, ec);
        found.push_back(std::move(entry));
    }
    std::sort(found.begin(), found.end(),
              [](const VolumeEntry& a, const VolumeEntry& b) { return a.id < b.id; });
    const std::lock_guard lock(mutex_);
    // Volumes whose entries are gone leave the memory with them.
    loaded_.remove_if([&](const auto& held) {
        return std::none_of(found.begin(), found.end(),
                            [&](const VolumeEntry& e) { return e.id == held.key; });
    });
    // Each skipped file is logged once, not at every rescan.
    for (const std::string& line : skipped) {
        if (std::find(skipped_.begin(), skipped_.end(), line) == skipped_.end()) {
            base::log_warning("volumes", "skipped " + line);
        }
    }
    entries_ = std::move(found);
    {
        // Folders gone since the last scan leave the cache with them.
        const std::lock_guard dicom_lock(dicom_mutex_);
        std::erase_if(dicom_folders_,
                      [&](const auto& cached) { return !dicom_folders.contains(cached.first); });
    }
    skipped_ = std::move(skipped);
    scanned_mtime_ = mtime;
    return base::Ok{};
}

base::Result<std::vector<volume::DicomSeries>> VolumeStore::dicom_series(
        const std::filesystem::path& folder, const std::string& signature) {
    {
        const std::lock_guard lock(dicom_mutex_);
        const auto cached = dicom_folders_.find(folder);
        if (cached != dicom_folders_.end() && cached->second.signature == signature) {
            return cached->second.series;
        }
    }
    // Outside the lock: a folder of a thousand slices takes a moment to read.
    auto series = volume::list_dicom_series(folder, false);
    const std::lock_guard lock(dicom_mutex_);
    dicom_folders_[folder] = {signature, series};
    return series;
}

std::vector<std::string> VolumeStore::skipped() const {
    const std::lock_guard lock(mutex_);
    return skipped_;
}

std::vector<VolumeEntry> VolumeStore::list() const {
    std::error_code ec;
    const auto mtime = std::filesystem::last_write_time(data_dir_, ec);
    const std::lock_guard lock(mutex_);
    if (!ec && mtime != scanned_mtime_) {
        {
            const std::lock_guard rescan(rescan_mutex_);
            rescan_requested_ = true;
        }
        rescan_wake_.notify_all();
    }
    std::vector<VolumeEntry> entries = entries_;
    for (VolumeEntry& entry : entries) {
        if (const auto* held = loaded_.peek(entry.id)) {
            entry.loaded = *held;
        }
    }
    return entries;
}

std::size_t VolumeStore::histograms_computed() const {
    const std::lock_guard lock(mutex_);
    return histograms_computed_;
}

std::shared_ptr<const std::vector<std::uint64_t>> VolumeStore::histogram(
        const std::shared_ptr<const volume::Volume>& volume) {
    {
        const std::lock_guard lock(mutex_);
        const auto found = histograms_.find(volume.get());
        if (found != histograms_.end() && found->second.volume.lock() == volume) {
            return found->second.bins;
        }
    }
    // Outside the lock: a large volume takes most of a second.
    auto bins = std::make_shared<const std::vector<std::uint64_t>>(
            volume::compute_histogram(*volume, histogram_bins).bins);
    const std::lock_guard lock(mutex_);
    std::erase_if(histograms_, [](const auto& cached) { return cached.second.volume.expired(); });
    ++histograms_computed_;
    histograms_[volume.get()] = {volume, bins};
    return bins;
}

std::string VolumeStore::relative_paths(std::string text) const {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(data_dir_, ec);
    for (const std::filesystem::path& dir : {data_dir_, canonical}) {
        std::string prefix = dir.string();
        if (prefix.empty()) {
            continue;
        }
        if (prefix.back() != '/') {
            prefix += '/';
        }
        for (auto at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at)) {
            text.erase(at, prefix.size());
        }
    }
    return text;
}

void VolumeStore::acquire_async(std::string id, AcquireDone done) {
    loaders_.post([this, id = std::move(id), done = std::move(done)] { done(acquire(id)); });
}

std::size_t VolumeStore::loads() const {
    const std::lock_guard lock(mutex_);
    return loads_;
}

LoadedVolume VolumeStore::acquire(const std::string& id) {
    // Loads are serialised, so two sessions opening the same new volume read it once; the second
    // finds it loaded when it gets the lock.
    const std::lock_guard loading(load_mutex_);
    std::filesystem::path path;
    volume::LoadOptions options = load_options_;
    {
        const std::lock_guard lock(mutex_);
        // Only ids from the scan are accepted, so "../x" or "/etc/passwd" cannot name a file.
        const auto entry = std::find_if(entries_.begin(), entries_.end(),
                                        [&](const VolumeEntry& e) { return e.id == id; });
        if (entry == entries_.end()) {
            return base::make_error(base::ErrorCode::unknown_volume,
                                    "no volume '" + id + "' on this server", "/volume");
        }
        if (const auto* held = loaded_.find(id)) {
            return *held;
        }
        path = entry->path;
        // The series listed, from the folder's own files: its sub-folders are entries of their
        // own.
        options.dicom_series = entry->dicom_series;
        options.dicom_subfolders = false;
    }
    // Loading takes seconds for large files; listing and opening loaded volumes go on meanwhile.
    auto loaded = volume::load_volume(path, options);
    if (!loaded) {
        base::Error error = loaded.error();
        error.message = relative_paths(std::move(error.message));
        error.where = relative_paths(std::move(error.where));
        return error;
    }
    auto shared = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    histogram(shared);
    const std::lock_guard lock(mutex_);
    ++loads_;
    if (std::none_of(entries_.begin(), entries_.end(),
                     [&](const VolumeEntry& e) { return e.id == id; })) {
        return shared;  // rescanned away meanwhile; still usable by this caller
    }
    base::log_info("volumes", "loaded " + id);
    loaded_.insert(id, shared, shared->data.size());
    return shared;
}

}  // namespace penumbra::session
