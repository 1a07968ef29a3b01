#pragma once

#include <penumbra/base/lru_cache.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/session/worker_pool.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

namespace penumbra::session {

// What those who open a volume are told of it: its id and name and, once it is loaded, its grid,
// voxel type and values.
struct VolumeSummary {
    std::string id;
    std::string name;
    bool loaded = false;
    glm::uvec3 dims{0};
    glm::dvec3 spacing{1.0};
    std::string voxel_type;  // as the loaders name it ("uint8", "int16"...)
    double min = 0.0;        // the values' range, in real units
    double max = 0.0;
    bool hounsfield = false;       // the values are Hounsfield units (a CT)
    volume::PatientBounds bounds;  // where it lies in patient space: what a crop box cuts
    // As the listing found it: the file says it is a label map (volume::declares_labels), what
    // add_labels draws; unknown outside a listing (a session's own volume).
    std::optional<bool> label_map;
};

// `volume` null: not loaded yet, called `name`; else the volume's own name and facts.
VolumeSummary summarize(const std::string& id, const std::string& name,
                        const volume::Volume* volume);

// A volume the store loaded, shared by every session on it; or why it could not be loaded.
using LoadedVolume = base::Result<std::shared_ptr<const volume::Volume>>;
// A listed file loaded as a label map (volume::load_label_map), shared likewise.
using LoadedLabels = base::Result<std::shared_ptr<const volume::LabelMap>>;

struct VolumeEntry {
    // The file's path relative to the data directory; for a DICOM series, its folder's ("." for
    // DICOM files right in the data directory), followed by "#" and the series' number (or its
    // UID where numbers repeat) when the folder holds several series: "study/ct#3".
    std::string id;
    // What users see before the volume is loaded: the id, or for one of several DICOM series its
    // description and number ("T1 axial (series 3)").
    std::string name;
    std::filesystem::path path;
    std::string dicom_series;                      // the SeriesInstanceUID a DICOM entry opens
    std::uintmax_t file_bytes = 0;                 // a DICOM folder: the bytes of its files
    std::shared_ptr<const volume::Volume> loaded;  // null until first opened
    bool label_map = false;                        // the file says it is a label map

    [[nodiscard]] VolumeSummary summary() const {
        VolumeSummary out = summarize(id, name, loaded.get());
        out.label_map = label_map;
        return out;
    }
};

// How the data folder is walked, and what one walk may cost.
struct ScanOptions {
    // How old the listed scan may get; a change of the data folder's modification time (a file
    // added or removed at its top) asks for a rescan sooner.
    std::chrono::milliseconds rescan_interval{10'000};
    // Folders outside the data folder that links in it may lead to (`--allow-links-to`). A link
    // to a folder anywhere else is skipped; links to files are followed wherever they lead.
    std::vector<std::filesystem::path> link_roots;
    // What one pass may cost: entries seen (files and folders) and the CPU time of its thread
    // (which yields to everything else, so a busy server makes a pass slower, not shorter). A
    // pass that reaches either stops there, lists what it found, and says so (log, /metrics,
    // list_volumes).
    int max_entries = 200'000;
    std::chrono::milliseconds max_time{30'000};
    // Where each pass is counted and timed (penumbra_volume_scan_*), when given.
    metrics::Registry* metrics = nullptr;
};

// Where the listing stands.
struct ScanProgress {
    // False until the first pass ends: list() holds what it has found so far.
    bool first_pass_done = false;
    bool scanning = false;  // a pass is under way
    // Why the last finished pass stopped at its budget, when it did: its list may miss volumes.
    std::optional<std::string> cut_short;
};

// `path` when it is a folder that exists, else the error that says which folder is missing.
base::Status check_data_folder(const std::filesystem::path& path);

// The volumes a server offers: every supported file under one data directory, and every series of
// DICOM images in a folder (one series, one volume; its files are not listed apart; a folder of
// several series lists each). A volume is named by its path in the data directory, a link's
// name where it passes one, whatever the link points to. Links to files are followed; links to
// folders only where the folder is inside the data directory or a root ScanOptions allows, so a
// link to "/" lists nothing and a folder reached twice (a link loop) is walked once. A volume is
// loaded once, on first use, and shared by every session that opens it; loaded volumes beyond
// the memory budget are dropped least recently used first (sessions holding one keep it alive).
// Ids are relative paths within the data directory; only listed ids are opened.
//
// Nothing here that reads files runs on the caller's thread: the folder is walked by a thread of
// its own, at the lowest CPU and I/O priority, from construction on (the first pass too: a server
// listens before its data folder is walked), and again every rescan interval; list() answers from
// the last pass, or during the first one with what it found so far. A rescan reopens no file whose
// folder kept its names, sizes and times. Loads run on the store's loader threads
// (acquire_async). A volume's histogram is computed once, when it is loaded.
class VolumeStore {
public:
    // How many bins a volume's histogram has (the transfer-function editor's backdrop).
    static constexpr int histogram_bins = 256;

    // `load_options` bound what one load may take (volume::LoadOptions).
    VolumeStore(std::filesystem::path data_dir, std::size_t memory_budget,
                volume::LoadOptions load_options = {}, ScanOptions scan_options = {},
                int loader_threads = 2);

    VolumeStore(const VolumeStore&) = delete;
    VolumeStore& operator=(const VolumeStore&) = delete;
    ~VolumeStore();

    // Walks the data directory now, on the caller's thread, after any pass under way.
    base::Status scan();

    // Waits until the first pass has ended (or the store stops before one).
    void wait_for_first_pass() const;

    [[nodiscard]] ScanProgress progress() const;

    // The volumes of the last scan.
    [[nodiscard]] std::vector<VolumeEntry> list() const;

    // What the last scan passed over, each as "relative/path: why" (not a volume file, a broken
    // link, a link to a folder outside, a folder reached twice); each is also logged once, when
    // first seen (a pass logs the first few and counts the rest).
    [[nodiscard]] std::vector<std::string> skipped() const;

    // Loads (or returns the loaded) volume `id`; an id not listed yet waits for the first pass
    // (a minute at most).
    // Unknown ids, ids reaching outside the data directory and unreadable files are Errors
    // ("unknown_volume", or the loader's code), whose paths are relative to the data directory.
    LoadedVolume acquire(const std::string& id);

    using AcquireDone = std::function<void(LoadedVolume)>;

    // acquire() on a loader thread; `done` is called there.
    void acquire_async(std::string id, AcquireDone done);

    // A listed file loaded as a label map (its names from the files beside it), as acquire loads
    // it as a volume, kept apart from the volumes under the same budget.
    LoadedLabels acquire_labels(const std::string& id);

    using AcquireLabelsDone = std::function<void(LoadedLabels)>;

    // acquire_labels() on a loader thread; `done` is called there.
    void acquire_labels_async(std::string id, AcquireLabelsDone done);

    // Runs `work` that reads a loaded volume at length (a pick's ray) on a loader thread, off the
    // threads that serve the network.
    void read_async(std::function<void()> work);

    // The histogram of a volume this store loaded, computed once per volume.
    std::shared_ptr<const std::vector<std::uint64_t>> histogram(
            const std::shared_ptr<const volume::Volume>& volume);

    // The surfaces of label map `map` with the labels `visible` shows (volume::label_surfaces),
    // what a session drawing the map alone draws: made once per map and visibility while they
    // stay within the memory budget (a class turning one atlas shares them), most of a second for
    // a large map, so on a loader thread (read_async).
    base::Result<std::shared_ptr<const volume::LabelSurfaces>> label_surfaces(
            const std::shared_ptr<const volume::LabelMap>& map, const std::vector<bool>& visible);

    // `text` with every path inside the data directory written relative to it, for messages that
    // leave the server.
    [[nodiscard]] std::string relative_paths(std::string text) const;

    [[nodiscard]] std::size_t loads() const;  // how many times a file was actually read
    [[nodiscard]] std::size_t histograms_computed() const;

private:
    // Loads the listed file `id` with `load` (path, LoadOptions) into `cache`, or returns what the
    // cache holds: what acquire and acquire_labels share.
    template <class Loaded, class Load>
    base::Result<std::shared_ptr<const Loaded>> load_listed(
            const std::string& id,
            base::LruCache<std::string, std::shared_ptr<const Loaded>>& cache, const Load& load);

    void rescan_loop();
    // Whether a walk may enter the folder whose resolved path is `real`.
    [[nodiscard]] bool may_walk(const std::filesystem::path& real) const;
    // Publishes `found`, what the first pass has listed so far.
    void publish_partial(std::vector<VolumeEntry> found);
    void count_pass(double seconds, std::uint64_t entries, bool cut_short);

    std::filesystem::path data_dir_;
    std::filesystem::path data_dir_real_;  // resolved at construction
    volume::LoadOptions load_options_;
    ScanOptions scan_options_;
    std::vector<std::filesystem::path> link_roots_real_;

    struct ScanMetrics {
        metrics::Counter& passes;
        metrics::Counter& cut_short;
        metrics::Gauge& seconds;
        metrics::Gauge& entries;
    };

    std::optional<ScanMetrics> scan_metrics_;  // when ScanOptions names a registry
    mutable std::mutex mutex_;
    std::mutex load_mutex_;
    std::mutex scan_mutex_;  // one pass at a time
    std::vector<VolumeEntry> entries_;
    std::vector<std::string> skipped_;
    std::unordered_set<std::string> skipped_logged_;  // each skipped file logged once
    ScanProgress progress_;
    mutable std::condition_variable first_pass_done_;
    // The loaded volumes by id, within the memory budget; VolumeEntry::loaded as list() fills it.
    base::LruCache<std::string, std::shared_ptr<const volume::Volume>> loaded_;
    base::LruCache<std::string, std::shared_ptr<const volume::LabelMap>> labels_;
    // Files refused as label maps, by id, with what that depended on (the file's size and time,
    // its folder's time) when refused.
    std::map<std::string, std::pair<std::string, base::Error>> refused_labels_;
    std::size_t loads_ = 0;

    struct CachedHistogram {
        std::weak_ptr<const volume::Volume> volume;
        std::shared_ptr<const std::vector<std::uint64_t>> bins;
    };

    std::map<const volume::Volume*, CachedHistogram> histograms_;
    std::size_t histograms_computed_ = 0;

    // The label surfaces made, by the map (held while they are) and its labels' visibility.
    using SurfacesKey = std::pair<std::shared_ptr<const volume::LabelMap>, std::vector<bool>>;
    base::LruCache<SurfacesKey, std::shared_ptr<const volume::LabelSurfaces>> surfaces_;

    // What the walk learnt of a folder from its files' contents, kept while the folder's files
    // keep their names, sizes and times (its signature), so a rescan opens none of them: whether
    // one is DICOM, and the series their headers name.
    struct FolderContents {
        std::string signature;
        bool has_dicom = false;
        std::optional<base::Result<std::vector<volume::DicomSeries>>> series;
    };

    // Whether `folder` holds DICOM files, from the cache while `signature` matches.
    bool holds_dicom(const std::filesystem::path& folder, const std::string& signature,
                     const std::vector<std::filesystem::path>& candidates);
    base::Result<std::vector<volume::DicomSeries>> dicom_series(const std::filesystem::path& folder,
                                                                const std::string& signature);
    std::mutex folders_mutex_;
    std::map<std::filesystem::path, FolderContents> folders_;

    // Whether the file in `path` says it is a label map (volume::declares_labels; false where its
    // header cannot be read: opening it tells why), from the cache while the file keeps its size
    // and time and its folder its time (a names file put beside it changes that).
    bool declares_labels(const std::filesystem::path& path);

    struct DeclaredLabels {
        std::string stamp;
        bool declares = false;
    };

    std::map<std::filesystem::path, DeclaredLabels> declared_labels_;  // by folders_mutex_

    std::filesystem::file_time_type scanned_mtime_{};
    mutable std::mutex rescan_mutex_;
    mutable std::condition_variable rescan_wake_;
    mutable bool rescan_requested_ = false;
    bool stopping_ = false;
    std::atomic<bool> stopping_scan_{false};
    std::thread rescanner_;
    WorkerPool loaders_;  // last: destroyed (joined) first
};

}  // namespace penumbra::session
