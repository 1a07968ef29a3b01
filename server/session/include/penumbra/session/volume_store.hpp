#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra::session {

struct VolumeEntry {
    // The file's path relative to the data directory; for a DICOM series, its folder's ("." for
    // DICOM files right in the data directory).
    std::string id;
    std::filesystem::path path;
    std::uintmax_t file_bytes = 0;                 // a DICOM folder: the bytes of its files
    std::shared_ptr<const volume::Volume> loaded;  // null until first opened
};

// The volumes a server offers: every supported file under one data directory, and every folder
// holding DICOM files (one series, one volume; its files are not listed apart). A volume is loaded
// once, on first use, and shared by every session that opens it; loaded volumes beyond the memory
// budget are dropped least recently used first (sessions holding one keep it alive). Ids are
// relative paths that never leave the data directory.
class VolumeStore {
public:
    // `load_options` bound what one load may take (volume::LoadOptions).
    VolumeStore(std::filesystem::path data_dir, std::size_t memory_budget,
                volume::LoadOptions load_options = {});

    // Re-scans the data directory.
    base::Status scan();

    [[nodiscard]] std::vector<VolumeEntry> list() const;

    // Loads (or returns the loaded) volume `id`. Unknown ids, ids reaching outside the data
    // directory and unreadable files are Errors ("unknown_volume", or the loader's code).
    base::Result<std::shared_ptr<const volume::Volume>> acquire(const std::string& id);

    [[nodiscard]] std::size_t loads() const;  // how many times a file was actually read

private:
    std::filesystem::path data_dir_;
    std::size_t memory_budget_;
    volume::LoadOptions load_options_;
    mutable std::mutex mutex_;
    std::mutex load_mutex_;
    std::vector<VolumeEntry> entries_;
    std::list<std::string> recent_;  // loaded ids, most recent first
    std::size_t loads_ = 0;
};

// Whether a file name is one the loaders read as a volume by itself (DICOM files are not: their
// folder is the volume).
bool is_volume_file(const std::filesystem::path& path);

}  // namespace penumbra::session
