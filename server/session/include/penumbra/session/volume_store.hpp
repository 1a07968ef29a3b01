#pragma once

#include <penumbra/base/lru_cache.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/session/worker_pool.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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
    bool hounsfield = false;  // the values are Hounsfield units (a CT)
};

// `volume` null: not loaded yet, called `name`; else the volume's own name and facts.
VolumeSummary summarize(const std::string& id, const std::string& name,
                        const volume::Volume* volume);

// A volume the store loaded, shared by every session on it; or why it could not be loaded.
using LoadedVolume = base::Result<std::shared_ptr<const volume::Volume>>;

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

    [[nodiscard]] VolumeSummary summary() const { return summarize(id, name, loaded.get()); }
};

// The volumes a server offers: every supported file under one data directory, and every series of
// DICOM images in a folder (one series, one volume; its files are not listed apart; a folder of
// several series lists each). Links in the data
// directory are followed (the administrator put them there); a volume is named by its path in the
// data directory, the link's, whatever the link points to. A volume is loaded
// once, on first use, and shared by every session that opens it; loaded volumes beyond the memory
// budget are dropped least recently used first (sessions holding one keep it alive). Ids are
// relative paths within the data directory; only listed ids are opened.
//
// Nothing here that reads files needs to run on the caller's thread: loads run on the store's
// loader threads (acquire_async), the folder is rescanned by a thread of its own, and list()
// answers from the last scan. A volume's histogram is computed once, when it is loaded.
class VolumeStore {
public:
    // How many bins a volume's histogram has (the transfer-function editor's backdrop).
    static constexpr int histogram_bins = 256;
    // How old the listed scan may get unless told otherwise.
    static constexpr std::chrono::milliseconds default_rescan_interval{10'000};

    // `load_options` bound what one load may take (volume::LoadOptions). `rescan_interval`: how
    // old the listed scan may get; a change of the data directory's modification time (a file
    // added or removed at its top) asks for a rescan sooner.
    VolumeStore(std::filesystem::path data_dir, std::size_t memory_budget,
                volume::LoadOptions load_options = {},
                std::chrono::milliseconds rescan_interval = default_rescan_interval,
                int loader_threads = 2);

    VolumeStore(const VolumeStore&) = delete;
    VolumeStore& operator=(const VolumeStore&) = delete;
    ~VolumeStore();

    // Scans the data directory now, on the caller's thread (at start-up).
    base::Status scan();

    // The volumes of the last scan.
    [[nodiscard]] std::vector<VolumeEntry> list() const;

    // What the last scan passed over, each as "relative/path: why" (not a volume file, a broken
    // link, a folder reached twice); each is also logged once, when first seen.
    [[nodiscard]] std::vector<std::string> skipped() const;

    // Loads (or returns the loaded) volume `id`. Unknown ids, ids reaching outside the data
    // directory and unreadable files are Errors ("unknown_volume", or the loader's code), whose
    // paths are relative to the data directory.
    LoadedVolume acquire(const std::string& id);

    using AcquireDone = std::function<void(LoadedVolume)>;

    // acquire() on a loader thread; `done` is called there.
    void acquire_async(std::string id, AcquireDone done);

    // The histogram of a volume this store loaded, computed once per volume.
    std::shared_ptr<const std::vector<std::uint64_t>> histogram(
            const std::shared_ptr<const volume::Volume>& volume);

    // `text` with every path inside the data directory written relative to it, for messages that
    // leave the server.
    [[nodiscard]] std::string relative_paths(std::string text) const;

    [[nodiscard]] std::size_t loads() const;  // how many times a file was actually read
    [[nodiscard]] std::size_t histograms_computed() const;

private:
    void rescan_loop();

    std::filesystem::path data_dir_;
    volume::LoadOptions load_options_;
    std::chrono::milliseconds rescan_interval_;
    mutable std::mutex mutex_;
    std::mutex load_mutex_;
    std::vector<VolumeEntry> entries_;
    std::vector<std::string> skipped_;
    // The loaded volumes by id, within the memory budget; VolumeEntry::loaded as list() fills it.
    base::LruCache<std::string, std::shared_ptr<const volume::Volume>> loaded_;
    std::size_t loads_ = 0;

    struct CachedHistogram {
        std::weak_ptr<const volume::Volume> volume;
        std::shared_ptr<const std::vector<std::uint64_t>> bins;
    };

    std::map<const volume::Volume*, CachedHistogram> histograms_;
    std::size_t histograms_computed_ = 0;

    // The series of each DICOM folder, read from its files' headers: kept while the folder's
    // files keep their names, sizes and times, so a rescan does not reread them.
    struct DicomFolder {
        std::string signature;
        base::Result<std::vector<volume::DicomSeries>> series = std::vector<volume::DicomSeries>{};
    };

    base::Result<std::vector<volume::DicomSeries>> dicom_series(const std::filesystem::path& folder,
                                                                const std::string& signature);
    std::mutex dicom_mutex_;
    std::map<std::filesystem::path, DicomFolder> dicom_folders_;

    std::filesystem::file_time_type scanned_mtime_{};
    mutable std::mutex rescan_mutex_;
    mutable std::condition_variable rescan_wake_;
    mutable bool rescan_requested_ = false;
    bool stopping_ = false;
    std::thread rescanner_;
    WorkerPool loaders_;  // last: destroyed (joined) first
};

}  // namespace penumbra::session
