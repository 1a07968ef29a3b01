#include "penumbra/session/volume_store.hpp"

#include <penumbra/base/log.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <ctime>
#include <memory>
#include <optional>
#include <set>

#include <dirent.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace penumbra::session {
namespace {

using Clock = std::chrono::steady_clock;

// How deep a walk goes: an export keeps its images four or five folders down, and each level
// holds a descriptor open while the walk is in it.
constexpr int max_folder_depth = 16;

// How many skipped files one pass logs by name; the rest are counted in one line, so a folder of
// a hundred thousand stray files does not flood the log (or hold its lock) at every start.
constexpr std::size_t logged_skips_per_pass = 20;

// How long an open of a volume not listed yet waits for the first pass to list it.
constexpr std::chrono::seconds first_pass_wait{60};

// Why a link to a folder was not followed: always logged by name.
constexpr std::string_view leaving_link = "a link to a folder outside the data folder";

// The walk reads the disk and stats every file: it yields to rendering and the network threads,
// for the CPU and for the disk (the best-effort class's lowest level, so it is never starved
// outright). On Linux a thread's nice value and I/O priority are its own.
void lower_this_threads_priority() {
    const auto thread = static_cast<id_t>(::gettid());
    if (::setpriority(PRIO_PROCESS, thread, 19) != 0) {
        base::log_warning("volumes", "could not lower the scan thread's CPU priority");
    }
    constexpr int ioprio_who_process = 1;  // <linux/ioprio.h>
    constexpr int ioprio_class_best_effort = 2;
    constexpr int ioprio_class_shift = 13;
    constexpr int lowest_level = 7;
    if (::syscall(SYS_ioprio_set, ioprio_who_process, thread,
                  (ioprio_class_best_effort << ioprio_class_shift) | lowest_level) != 0) {
        base::log_warning("volumes", "could not lower the scan thread's I/O priority");
    }
}

// The CPU time the calling thread has used: a pass's time budget counts the work it does, not the
// time it waits for rendering, which its low priority lets go first (a pass starved by a busy
// server is slow, not over budget). A pass blocked on a slow disk is bounded by its entries.
std::chrono::nanoseconds thread_cpu_time() {
    timespec now{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return std::chrono::seconds(now.tv_sec) + std::chrono::nanoseconds(now.tv_nsec);
}

// Whether `path` is `root` or inside it; both resolved.
bool is_within(const std::filesystem::path& path, const std::filesystem::path& root) {
    if (root.empty() || path.empty()) {
        return false;  // a root or a target that could not be resolved allows nothing
    }
    const auto [root_end, path_at] =
            std::mismatch(root.begin(), root.end(), path.begin(), path.end());
    return root_end == root.end() || (std::next(root_end) == root.end() && root_end->empty());
}

// A folder's files that may be DICOM (DICOM file names are arbitrary, so only the content
// decides), with what says whether they changed.
struct FolderFiles {
    std::uintmax_t bytes = 0;  // of the candidates
    // The candidates' names, sizes and modification times: while it stays the same, so do
    // whether one is DICOM and the series their headers name.
    std::string signature;
    std::vector<std::filesystem::path> candidates;
};

// One stat per file, relative to the open folder: a rescan of a folder of a hundred thousand
// files pays for no path lookups from the root.
FolderFiles folder_files(const std::filesystem::path& folder) {
    FolderFiles files;
    const std::unique_ptr<DIR, int (*)(DIR*)> dir(::opendir(folder.c_str()), ::closedir);
    if (!dir) {
        return files;
    }
    while (const dirent* entry = ::readdir(dir.get())) {
        const std::string_view name = entry->d_name;
        // Links and folders are no series' files; hidden files, "." and ".." neither.
        if (name.starts_with('.') || (entry->d_type != DT_REG && entry->d_type != DT_UNKNOWN)) {
            continue;
        }

        struct stat info {};

        if (::fstatat(::dirfd(dir.get()), entry->d_name, &info, AT_SYMLINK_NOFOLLOW) != 0 ||
            !S_ISREG(info.st_mode)) {
            continue;
        }
        std::filesystem::path path = folder / name;
        if (volume::is_volume_file_name(path)) {
            continue;
        }
        const auto size = static_cast<std::uintmax_t>(info.st_size);
        files.bytes += size;
        files.signature += std::string(name) + '/' + std::to_string(size) + '/' +
                           std::to_string(info.st_mtim.tv_sec) + '.' +
                           std::to_string(info.st_mtim.tv_nsec) + '\n';
        files.candidates.push_back(std::move(path));
    }
    return files;
}

// The type of what the walk's entry names, a link's target's: from the folder's listing where it
// says, so that a walk over plain files stats none of them.
std::filesystem::file_type target_type(const std::filesystem::directory_entry& entry,
                                       std::error_code& ec) {
    if (entry.is_symlink(ec)) {
        return std::filesystem::status(entry.path(), ec).type();
    }
    if (entry.is_directory(ec)) {
        return std::filesystem::file_type::directory;
    }
    if (entry.is_regular_file(ec)) {
        return std::filesystem::file_type::regular;
    }
    return entry.symlink_status(ec).type();
}

// Why a file was not listed: what a volume's name ends with.
const std::string& not_a_volume_reason() {
    static const std::string reason = [] {
        std::string text = "not a volume (names ending";
        for (const std::string_view suffix : volume::volume_suffixes()) {
            text += " " + std::string(suffix);
        }
        return text + ", or DICOM files in a folder)";
    }();
    return reason;
}

// What a file's being a label map depends on: its size and time, and its folder's time (a names
// file put beside it changes that).
std::string label_stamp(const std::filesystem::path& path) {
    std::error_code ec;
    const auto time_of = [&](const std::filesystem::path& p) {
        return std::to_string(std::filesystem::last_write_time(p, ec).time_since_epoch().count());
    };
    return std::to_string(std::filesystem::file_size(path, ec)) + '/' + time_of(path) + '/' +
           time_of(path.parent_path());
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
        out.bounds = volume::patient_bounds(*volume);
    }
    return out;
}

base::Status check_data_folder(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec)) {
        return base::make_error(base::ErrorCode::not_found, "the data directory does not exist",
                                path.string());
    }
    return base::Ok{};
}

VolumeStore::VolumeStore(std::filesystem::path data_dir, std::size_t memory_budget,
                         volume::LoadOptions load_options, ScanOptions scan_options,
                         int loader_threads)
    : data_dir_(std::move(data_dir))
    , load_options_(std::move(load_options))
    , scan_options_(std::move(scan_options))
    , loaded_(memory_budget,
              {.on_evict =
                       [](const auto& entry) {
                           base::log_info("volumes", "dropped " + entry.key + " (memory budget)");
                       }})
    , labels_(memory_budget, {})
    , surfaces_(memory_budget, {})
    , loaders_(loader_threads) {
    if (metrics::Registry* registry = scan_options_.metrics) {
        scan_metrics_.emplace(ScanMetrics{
                .passes = registry->counter("penumbra_volume_scans_total",
                                            "passes over the data folder"),
                .cut_short = registry->counter(
                        "penumbra_volume_scans_cut_short_total",
                        "passes over the data folder stopped at their budget (files or time)"),
                .seconds = registry->gauge("penumbra_volume_scan_seconds",
                                           "how long the last pass over the data folder took"),
                .entries = registry->gauge("penumbra_volume_scan_entries",
                                           "files and folders the last pass saw")});
    }
    std::error_code ec;
    data_dir_real_ = std::filesystem::weakly_canonical(data_dir_, ec);
    for (const std::filesystem::path& root : scan_options_.link_roots) {
        std::filesystem::path real = std::filesystem::canonical(root, ec);
        if (ec) {
            base::log_error("volumes", "links may not lead to " + root.string() +
                                               ": it cannot be resolved (" + ec.message() + ")");
            continue;
        }
        link_roots_real_.push_back(std::move(real));
    }
    rescanner_ = std::thread([this] { rescan_loop(); });
}

VolumeStore::~VolumeStore() {
    // A pass under way stops at its next entry: shutting down does not wait for a long walk.
    stopping_scan_.store(true);
    {
        const std::lock_guard lock(rescan_mutex_);
        stopping_ = true;
    }
    rescan_wake_.notify_all();
    rescanner_.join();
}

void VolumeStore::rescan_loop() {
    lower_this_threads_priority();
    std::unique_lock lock(rescan_mutex_);
    // The first pass at once, then one each interval or when asked.
    for (bool first = true;; first = false) {
        if (!first) {
            rescan_wake_.wait_for(lock, scan_options_.rescan_interval,
                                  [&] { return stopping_ || rescan_requested_; });
        }
        if (stopping_) {
            // Stopped before a first pass: whoever waits for it has nothing more to wait for.
            // (list() takes mutex_ then rescan_mutex_: never the other way round.)
            lock.unlock();
            const std::lock_guard done(mutex_);
            progress_.first_pass_done = true;
            first_pass_done_.notify_all();
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

bool VolumeStore::may_walk(const std::filesystem::path& real) const {
    return is_within(real, data_dir_real_) ||
           std::any_of(link_roots_real_.begin(), link_roots_real_.end(),
                       [&](const std::filesystem::path& root) { return is_within(real, root); });
}

void VolumeStore::wait_for_first_pass() const {
    std::unique_lock lock(mutex_);
    first_pass_done_.wait(lock, [this] { return progress_.first_pass_done; });
}

ScanProgress VolumeStore::progress() const {
    const std::lock_guard lock(mutex_);
    return progress_;
}

void VolumeStore::publish_partial(std::vector<VolumeEntry> found) {
    std::sort(found.begin(), found.end(),
              [](const VolumeEntry& a, const VolumeEntry& b) { return a.id < b.id; });
    const std::lock_guard lock(mutex_);
    if (!progress_.first_pass_done) {
        entries_.swap(found);  // the last publication is freed after the lock is let go
    }
}

void VolumeStore::count_pass(double seconds, std::uint64_t entries, bool cut_short) {
    if (scan_metrics_) {
        scan_metrics_->passes.add();
        scan_metrics_->cut_short.add(cut_short ? 1 : 0);
        scan_metrics_->seconds.set(seconds);
        scan_metrics_->entries.set(static_cast<double>(entries));
    }
}

base::Status VolumeStore::scan() {
    const std::lock_guard one_pass(scan_mutex_);
    if (auto status = check_data_folder(data_dir_); !status) {
        const std::lock_guard lock(mutex_);
        progress_.first_pass_done = true;
        first_pass_done_.notify_all();
        return status;
    }
    {
        const std::lock_guard lock(mutex_);
        progress_.scanning = true;
    }
    const Clock::time_point started = Clock::now();
    const std::chrono::nanoseconds cpu_started = thread_cpu_time();
    const bool publishing = !progress().first_pass_done;
    std::error_code ec;
    // Taken before the walk: a change during it asks for another scan.
    const auto mtime = std::filesystem::last_write_time(data_dir_, ec);
    std::vector<VolumeEntry> found;
    std::vector<std::string> skipped;
    std::set<std::filesystem::path> checked_folders;  // as walked
    std::set<std::filesystem::path> listed_folders;   // those whose DICOM files are listed
    // Ids are the paths as walked, below `top`: lexically, never through the links they pass.
    std::filesystem::path top = data_dir_;
    if (!top.has_filename() && top.has_parent_path()) {
        top = top.parent_path();  // "data/" walks as "data"
    }
    // The walk's paths all begin with `top`: cutting it off is what lexically_relative would do,
    // without taking each path apart.
    const std::string top_text = top.generic_string();
    const auto relative = [&](const std::filesystem::path& path) {
        std::string text = path.generic_string();
        if (text.size() > top_text.size() + 1 && text.starts_with(top_text) &&
            text[top_text.size()] == '/') {
            return text.substr(top_text.size() + 1);
        }
        return path.lexically_relative(top).generic_string();
    };
    const auto skip = [&](const std::filesystem::path& path, const std::string& why) {
        skipped.push_back(relative(path) + ": " + why);
    };
    // The pass's budget: each entry seen counts, and the clock is read every few hundred.
    std::uint64_t seen = 0;
    std::optional<std::string> cut_short;
    const auto over_budget = [&] {
        ++seen;
        if (stopping_scan_.load(std::memory_order_relaxed)) {
            cut_short = "the server is stopping";
        } else if (seen > static_cast<std::uint64_t>(scan_options_.max_entries)) {
            cut_short = "the data folder holds more than " +
                        std::to_string(scan_options_.max_entries) +
                        " files and folders (--scan-max-entries)";
        } else if (seen % 256 == 0 && thread_cpu_time() - cpu_started > scan_options_.max_time) {
            std::array<char, 32> budget{};
            std::snprintf(budget.data(), budget.size(), "%g",
                          std::chrono::duration<double>(scan_options_.max_time).count());
            cut_short = "the pass used more than " + std::string(budget.data()) +
                        " s of CPU time (--scan-max-seconds)";
        }
        return cut_short.has_value();
    };
    // Until the first pass ends, what it has found is listed every quarter of a second.
    constexpr auto publish_every = std::chrono::milliseconds(250);
    Clock::time_point next_publish = started + publish_every;
    // A folder's DICOM files are one entry per series: under the folder's id where it holds one
    // series, else "folder#number" (or "#UID" where numbers repeat). A folder whose headers
    // cannot be read is listed whole, so that opening it tells why.
    const auto add_series_if_dicom = [&](const std::filesystem::path& folder) {
        checked_folders.insert(folder);
        FolderFiles files = folder_files(folder);
        if (!holds_dicom(folder, files.signature, files.candidates)) {
            return false;
        }
        VolumeEntry entry;
        entry.path = folder;
        entry.id = relative(folder);
        entry.name = entry.id;
        entry.file_bytes = files.bytes;
        const auto series = dicom_series(folder, files.signature);
        if (!series && series.error().code == base::ErrorCode::no_dicom_images) {
            skip(folder,
                 "DICOM files without images (" + relative_paths(series.error().message) + ")");
            return true;
        }
        listed_folders.insert(folder);
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
    // Links the administrator put in the data folder are followed to files wherever they lead
    // (a volume keeps the link's name: clients name volumes by the listed id only, never by
    // path), and to folders inside the data folder or an allowed root: a link to "/" must not
    // make the server walk, list and open the machine's files. A folder reached twice (a link
    // loop, or two links to one folder) is walked once.
    std::set<std::filesystem::path> walked{std::filesystem::canonical(top, ec)};
    const bool top_is_series = add_series_if_dicom(top);
    std::error_code walk_error;
    for (auto it = std::filesystem::recursive_directory_iterator(
                 top,
                 std::filesystem::directory_options::skip_permission_denied |
                         std::filesystem::directory_options::follow_directory_symlink,
                 walk_error);
         !walk_error && it != std::filesystem::recursive_directory_iterator();
         it.increment(walk_error)) {
        if (over_budget()) {
            break;
        }
        if (publishing && Clock::now() >= next_publish) {
            publish_partial(found);
            next_publish = Clock::now() + publish_every;
        }
        const std::filesystem::path& path = it->path();
        const std::string name = path.filename().string();
        if (name.starts_with('.')) {
            it.disable_recursion_pending();
            continue;
        }
        std::error_code status_error;
        const std::filesystem::file_type type = target_type(*it, status_error);
        if (status_error || type == std::filesystem::file_type::not_found) {
            skip(path, it->is_symlink(ec) ? "a link to nothing (" + status_error.message() + ")"
                                          : "cannot be read (" + status_error.message() + ")");
            continue;
        }
        if (type == std::filesystem::file_type::directory) {
            if (it.depth() + 1 >= max_folder_depth) {
                skip(path, "deeper than " + std::to_string(max_folder_depth) +
                                   " folders below the data folder");
                it.disable_recursion_pending();
                continue;
            }
            const std::filesystem::path real = std::filesystem::canonical(path, ec);
            if (!may_walk(real)) {
                skip(path, std::string(leaving_link) + " (" + real.string() +
                                   "); --allow-links-to lets links lead there");
                it.disable_recursion_pending();
                continue;
            }
            if (!walked.insert(real).second) {
                skip(path, "a folder already listed through another path (a link loop?)");
                it.disable_recursion_pending();
                continue;
            }
            add_series_if_dicom(path);
            continue;
        }
        if (type != std::filesystem::file_type::regular) {
            skip(path, "not a regular file");
            continue;
        }
        if (!volume::is_volume_file_name(path)) {
            const bool in_series = (path.parent_path() == top && top_is_series) ||
                                   listed_folders.contains(path.parent_path());
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
        entry.label_map = declares_labels(path);
        found.push_back(std::move(entry));
    }
    // A walk that fails (a folder removed under it, out of descriptors) lists what it found
    // and says that it is not all.
    if (walk_error && !cut_short) {
        cut_short = "the walk failed: " + walk_error.message();
    }
    std::sort(found.begin(), found.end(),
              [](const VolumeEntry& a, const VolumeEntry& b) { return a.id < b.id; });
    const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
    if (cut_short) {
        base::log_warning("volumes", "scan cut short after " + std::to_string(seen - 1) +
                                             " entries, listing " + std::to_string(found.size()) +
                                             " volume(s): " + *cut_short);
    }
    count_pass(seconds, seen, cut_short.has_value());
    // Each skipped file is logged once, not at every rescan; a link leaving the folder always by
    // name, other files up to a few a pass (then counted). What is no longer skipped is
    // forgotten, so the set holds this pass's lines only.
    std::size_t named = 0;
    std::size_t unnamed = 0;
    std::unordered_set<std::string> this_pass;
    this_pass.reserve(skipped.size());
    for (const std::string& line : skipped) {
        const bool seen_before = skipped_logged_.contains(line);
        this_pass.insert(line);
        if (seen_before) {
            continue;
        }
        if (line.find(leaving_link) != std::string::npos || named < logged_skips_per_pass) {
            base::log_warning("volumes", "skipped " + line);
            ++named;
        } else {
            ++unnamed;
        }
    }
    skipped_logged_.swap(this_pass);
    if (unnamed > 0) {
        base::log_warning("volumes",
                          "skipped " + std::to_string(unnamed) + " more file(s), not named");
    }
    {
        // Folders gone since the last scan leave the cache with them.
        const std::lock_guard folders_lock(folders_mutex_);
        std::erase_if(folders_,
                      [&](const auto& cached) { return !checked_folders.contains(cached.first); });
        std::unordered_set<std::string> listed_paths;
        for (const VolumeEntry& entry : found) {
            listed_paths.insert(entry.path.string());
        }
        std::erase_if(declared_labels_, [&](const auto& cached) {
            return !listed_paths.contains(cached.first.string());
        });
    }
    // What follows holds the lock that listing and opening take: nothing in it walks or frees a
    // list of files, since this thread's low priority would make them wait. The last pass's lists
    // are swapped out, and freed after the lock is let go.
    std::vector<VolumeEntry> last_entries;
    std::vector<std::string> last_skipped;
    const std::lock_guard lock(mutex_);
    // Volumes whose entries are gone leave the memory with them.
    loaded_.remove_if([&](const auto& held) {
        return std::none_of(found.begin(), found.end(),
                            [&](const VolumeEntry& e) { return e.id == held.key; });
    });
    last_entries.swap(entries_);
    entries_ = std::move(found);
    last_skipped.swap(skipped_);
    skipped_ = std::move(skipped);
    scanned_mtime_ = mtime;
    progress_.scanning = false;
    progress_.cut_short = cut_short;
    if (!progress_.first_pass_done) {
        progress_.first_pass_done = true;
        first_pass_done_.notify_all();
    }
    return base::Ok{};
}

bool VolumeStore::holds_dicom(const std::filesystem::path& folder, const std::string& signature,
                              const std::vector<std::filesystem::path>& candidates) {
    {
        const std::lock_guard lock(folders_mutex_);
        const auto cached = folders_.find(folder);
        if (cached != folders_.end() && cached->second.signature == signature) {
            return cached->second.has_dicom;
        }
    }
    // The search stops opening files at the first DICOM one.
    const bool has_dicom = std::any_of(candidates.begin(), candidates.end(), [](const auto& path) {
        return volume::is_dicom_file(path);
    });
    const std::lock_guard lock(folders_mutex_);
    folders_[folder] = {signature, has_dicom, std::nullopt};
    return has_dicom;
}

bool VolumeStore::declares_labels(const std::filesystem::path& path) {
    const std::string stamp = label_stamp(path);
    {
        const std::lock_guard lock(folders_mutex_);
        const auto cached = declared_labels_.find(path);
        if (cached != declared_labels_.end() && cached->second.stamp == stamp) {
            return cached->second.declares;
        }
    }
    const auto declared = volume::declares_labels(path);
    const bool declares = declared && *declared;
    const std::lock_guard lock(folders_mutex_);
    declared_labels_[path] = {stamp, declares};
    return declares;
}

base::Result<std::vector<volume::DicomSeries>> VolumeStore::dicom_series(
        const std::filesystem::path& folder, const std::string& signature) {
    {
        const std::lock_guard lock(folders_mutex_);
        const auto cached = folders_.find(folder);
        if (cached != folders_.end() && cached->second.signature == signature &&
            cached->second.series) {
            return *cached->second.series;
        }
    }
    // Outside the lock: a folder of a thousand slices takes a moment to read.
    auto series = volume::list_dicom_series(folder, false);
    const std::lock_guard lock(folders_mutex_);
    FolderContents& contents = folders_[folder];
    if (contents.signature == signature) {
        contents.series = series;
    }
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
    if (!ec && progress_.first_pass_done && mtime != scanned_mtime_) {
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

base::Result<std::shared_ptr<const volume::LabelSurfaces>> VolumeStore::label_surfaces(
        const std::shared_ptr<const volume::LabelMap>& map, const std::vector<bool>& visible) {
    SurfacesKey key{map, visible};
    {
        const std::lock_guard lock(mutex_);
        if (const auto* kept = surfaces_.find(key)) {
            return *kept;
        }
    }
    // Outside the lock, as a histogram is.
    auto made = volume::label_surfaces(*map, visible);
    if (!made) {
        return made.error();
    }
    auto surfaces = std::make_shared<const volume::LabelSurfaces>(std::move(made.value()));
    const std::size_t bytes =
            surfaces->indicator.data.size() + surfaces->labels.indices.data.size();
    const std::lock_guard lock(mutex_);
    surfaces_.insert(std::move(key), surfaces, bytes);
    return surfaces;
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

namespace {

std::size_t bytes_held(const volume::Volume& volume) {
    return volume.data.size();
}

std::size_t bytes_held(const volume::LabelMap& labels) {
    return labels.indices.data.size();
}

}  // namespace

template <class Loaded, class Load>
base::Result<std::shared_ptr<const Loaded>> VolumeStore::load_listed(
        const std::string& id, base::LruCache<std::string, std::shared_ptr<const Loaded>>& cache,
        const Load& load) {
    const auto listed = [&] {
        return std::find_if(entries_.begin(), entries_.end(),
                            [&](const VolumeEntry& e) { return e.id == id; });
    };
    {
        // A volume named in a link may be opened before the first pass has reached it: the open
        // waits for that pass (for a while), before it takes the loads' turn, so that loads of
        // listed volumes go on meanwhile.
        std::unique_lock lock(mutex_);
        if (listed() == entries_.end()) {
            first_pass_done_.wait_for(lock, first_pass_wait,
                                      [this] { return progress_.first_pass_done; });
        }
    }
    // Loads are serialised, so two sessions opening the same new volume read it once; the second
    // finds it loaded when it gets the lock.
    const std::lock_guard loading(load_mutex_);
    std::filesystem::path path;
    volume::LoadOptions options = load_options_;
    {
        const std::lock_guard lock(mutex_);
        // Only ids from the scan are accepted, so "../x" or "/etc/passwd" cannot name a file.
        const auto entry = listed();
        if (entry == entries_.end()) {
            return base::make_error(base::ErrorCode::unknown_volume,
                                    "no volume '" + id + "' on this server", "/volume");
        }
        if (const auto* held = cache.find(id)) {
            return *held;
        }
        path = entry->path;
        // A folder is read through the path the scan walked: the link it passed must still lead
        // where the scan allowed, not to wherever it was pointed since.
        std::error_code ec;
        if (std::filesystem::is_directory(path, ec) &&
            !may_walk(std::filesystem::canonical(path, ec))) {
            return base::make_error(base::ErrorCode::unknown_volume,
                                    "no volume '" + id + "' on this server", "/volume");
        }
        // The series listed, from the folder's own files: its sub-folders are entries of their
        // own.
        options.dicom_series = entry->dicom_series;
        options.dicom_subfolders = false;
    }
    // Loading takes seconds for large files; listing and opening loaded volumes go on meanwhile.
    auto loaded = load(path, options);
    if (!loaded) {
        base::Error error = loaded.error();
        error.message = relative_paths(std::move(error.message));
        error.where = relative_paths(std::move(error.where));
        return error;
    }
    auto shared = std::make_shared<const Loaded>(std::move(loaded.value()));
    const std::lock_guard lock(mutex_);
    ++loads_;
    if (std::none_of(entries_.begin(), entries_.end(),
                     [&](const VolumeEntry& e) { return e.id == id; })) {
        return shared;  // rescanned away meanwhile; still usable by this caller
    }
    base::log_info("volumes", "loaded " + id);
    cache.insert(id, shared, bytes_held(*shared));
    return shared;
}

LoadedVolume VolumeStore::acquire(const std::string& id) {
    auto loaded =
            load_listed<volume::Volume>(id, loaded_, [](const auto& path, const auto& options) {
                return volume::load_volume(path, options);
            });
    if (loaded) {
        histogram(*loaded);  // computed once per volume
    }
    return loaded;
}

LoadedLabels VolumeStore::acquire_labels(const std::string& id) {
    // A file refused as a label map is not read again while it stays as it was: a client asking
    // for it again and again costs a look at its time, not a load.
    std::optional<std::filesystem::path> listed_path;
    {
        const std::lock_guard lock(mutex_);
        const auto entry = std::find_if(entries_.begin(), entries_.end(),
                                        [&](const VolumeEntry& e) { return e.id == id; });
        if (entry != entries_.end()) {
            listed_path = entry->path;
        }
    }
    // Its files are looked at outside the lock that listing and opening take.
    const std::optional<std::string> stamp =
            listed_path ? std::optional<std::string>(label_stamp(*listed_path)) : std::nullopt;
    if (stamp) {
        const std::lock_guard lock(mutex_);
        const auto refused = refused_labels_.find(id);
        if (refused != refused_labels_.end() && refused->second.first == *stamp) {
            return refused->second.second;
        }
    }
    auto loaded = load_listed<volume::LabelMap>(
            id, labels_,
            [](const auto& path, const auto& options) -> base::Result<volume::LabelMap> {
                // A scan is no label map, though its integers would make one: a server draws
                // only files that say what they are, and reads no voxels of another.
                auto declared = volume::declares_labels(path);
                if (!declared) {
                    return declared.error();
                }
                if (!*declared) {
                    return base::make_error(
                            base::ErrorCode::invalid_volume,
                            "not a label map: neither marked as one (NIfTI's label intent) nor "
                            "named (MRIcron's .nii.txt beside it, a .seg.nrrd's segments)",
                            path.filename().string());
                }
                return volume::load_label_map(path, options);
            });
    // What the file holds is kept; a failure of the moment (memory, a read) is tried again.
    const auto lasting = [](base::ErrorCode code) {
        return code != base::ErrorCode::unknown_volume && code != base::ErrorCode::out_of_memory &&
               code != base::ErrorCode::io_error && code != base::ErrorCode::read_failed;
    };
    if (!loaded && stamp && lasting(loaded.error().code)) {
        const std::lock_guard lock(mutex_);
        refused_labels_.insert_or_assign(id, std::pair{*stamp, loaded.error()});
    }
    return loaded;
}

void VolumeStore::read_async(std::function<void()> work) {
    loaders_.post(std::move(work));
}

void VolumeStore::acquire_labels_async(std::string id, AcquireLabelsDone done) {
    loaders_.post([this, id = std::move(id), done = std::move(done)] { done(acquire_labels(id)); });
}

}  // namespace penumbra::session
