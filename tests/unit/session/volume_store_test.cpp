#include "dicom_writer.hpp"

#include <penumbra/session/volume_store.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <future>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

namespace fs = std::filesystem;

class VolumeStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "penumbra-store-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        data_ = pattern;
    }

    void TearDown() override {
        std::error_code ec;
        fs::remove_all(data_, ec);
    }

    void write_text(const fs::path& path, const std::string& text) {
        fs::create_directories(path.parent_path());
        std::ofstream(path) << text;
    }

    void write_series(const fs::path& folder, glm::uvec3 dims) {
        volume::fixtures::SeriesSpec spec;
        spec.dims = dims;
        volume::fixtures::write_series(folder, spec,
                                       std::vector<std::uint16_t>(dims.x * dims.y * dims.z, 7));
    }

    std::vector<std::string> ids(const VolumeStore& store) {
        std::vector<std::string> result;
        for (const auto& entry : store.list()) {
            result.push_back(entry.id);
        }
        return result;
    }

    fs::path data_;
};

TEST_F(VolumeStoreTest, ADicomFolderIsOneVolumeAndItsFilesAreNotListed) {
    write_series(data_ / "patients" / "ct_head", {4, 4, 3});
    write_text(data_ / "patients" / "ct_head" / "README.txt", "exported");
    write_series(data_ / "mr", {4, 4, 2});
    write_text(data_ / "mr" / "t1.nrrd", "a NIfTI or NRRD next to the series is its own volume");
    write_text(data_ / "notes" / "plan.txt", "not a volume");
    write_text(data_ / "heads" / "a_2x2x2_uint8.raw", "12345678");

    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"heads/a_2x2x2_uint8.raw", "mr", "mr/t1.nrrd",
                                                    "patients/ct_head"}));
    for (const auto& entry : store.list()) {
        if (entry.id == "patients/ct_head") {
            std::uintmax_t bytes = 0;
            for (const auto& file : fs::directory_iterator(data_ / "patients" / "ct_head")) {
                bytes += file.file_size();
            }
            EXPECT_EQ(entry.file_bytes, bytes);
        }
    }

    auto loaded = store.acquire("patients/ct_head");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ((*loaded)->dims, glm::uvec3(4, 4, 3));
    EXPECT_EQ((*loaded)->value(1, 2, 2), 7.0);
}

// A folder of two series (a localizer beside the scan) lists each under a stable id of the
// folder and its series number, named by description and number; each id opens its own series.
// A series in a sub-folder is its own entry, and the folder's own load does not take it in.
TEST_F(VolumeStoreTest, AFolderOfSeveralSeriesListsEachSeries) {
    volume::fixtures::SeriesSpec scan;
    scan.dims = {4, 4, 3};
    scan.series_number = "2";
    scan.series_description = "T1 axial";
    volume::fixtures::write_series(data_ / "study", scan, std::vector<std::uint16_t>(48, 7));
    volume::fixtures::SeriesSpec localizer;
    localizer.dims = {4, 4, 1};
    localizer.series_uid = volume::fixtures::make_uid();
    localizer.series_number = "1";
    localizer.series_description = "Localizer";
    volume::fixtures::write_slice(data_ / "study" / "localizer.dcm", localizer, 0,
                                  std::vector<std::uint16_t>(16, 3), 1);
    write_series(data_ / "study" / "later", {4, 4, 2});

    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"study#1", "study#2", "study/later"}));
    const auto listed = store.list();
    EXPECT_EQ(listed[0].name, "Localizer (series 1)");
    EXPECT_EQ(listed[1].name, "T1 axial (series 2)");
    EXPECT_EQ(listed[2].name, "study/later");

    auto t1 = store.acquire("study#2");
    ASSERT_TRUE(t1.ok()) << t1.error().to_string();
    EXPECT_EQ((*t1)->dims, glm::uvec3(4, 4, 3));
    EXPECT_EQ((*t1)->value(1, 1, 1), 7.0);
    EXPECT_EQ((*t1)->name, "T1 axial (series 2)");
    auto scout = store.acquire("study#1");
    ASSERT_TRUE(scout.ok()) << scout.error().to_string();
    EXPECT_EQ((*scout)->dims, glm::uvec3(4, 4, 1));
    EXPECT_EQ((*scout)->value(1, 1, 0), 3.0);
    auto later = store.acquire("study/later");
    ASSERT_TRUE(later.ok()) << later.error().to_string();
    EXPECT_EQ((*later)->dims, glm::uvec3(4, 4, 2));
    EXPECT_FALSE(store.acquire("study").ok());
}

// A folder's series are read from its headers once and kept while its files stay the same; a
// series added to it shows at the next scan.
TEST_F(VolumeStoreTest, ASeriesAddedToAFolderIsListedAtTheNextScan) {
    volume::fixtures::SeriesSpec first;
    first.dims = {4, 4, 2};
    first.series_number = "1";
    volume::fixtures::write_series(data_ / "study", first, std::vector<std::uint16_t>(32, 1));
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"study"}));
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"study"}));

    volume::fixtures::SeriesSpec second;
    second.dims = {4, 4, 1};
    second.series_uid = volume::fixtures::make_uid();
    second.series_number = "2";
    volume::fixtures::write_slice(data_ / "study" / "added.dcm", second, 0,
                                  std::vector<std::uint16_t>(16, 2), 1);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"study#1", "study#2"}));
    auto added = store.acquire("study#2");
    ASSERT_TRUE(added.ok()) << added.error().to_string();
    EXPECT_EQ((*added)->dims, glm::uvec3(4, 4, 1));
}

// The listing tells label maps from scans by what the files say (an atlas's label intent), and a
// names file put beside a scan makes it one at the next scan; the file refused as a label map
// until then is drawn after.
TEST_F(VolumeStoreTest, LabelMapsAreListedAsSuchAndANamesFileBesideOneIsSeenAtTheNextScan) {
    const fs::path templates = "/usr/share/mricron/templates";
    fs::copy_file(templates / "aal.nii.gz", data_ / "aal.nii.gz");
    fs::copy_file(templates / "brodmann.nii.gz", data_ / "brodmann.nii.gz");
    VolumeStore store(data_, std::size_t{1} << 28);
    ASSERT_TRUE(store.scan().ok());
    const auto label_maps = [&] {
        std::map<std::string, bool> out;
        for (const VolumeEntry& entry : store.list()) {
            out[entry.id] = entry.label_map;
            EXPECT_EQ(entry.summary().label_map, entry.label_map);
        }
        return out;
    };
    EXPECT_EQ(label_maps(),
              (std::map<std::string, bool>{{"aal.nii.gz", true}, {"brodmann.nii.gz", true}}));

    fs::copy_file(templates / "ch2.nii.gz", data_ / "ch2.nii.gz");
    ASSERT_TRUE(store.scan().ok());
    EXPECT_FALSE(label_maps().at("ch2.nii.gz"));
    const auto refused = store.acquire_labels("ch2.nii.gz");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("not a label map"), std::string::npos);
    std::ofstream(data_ / "ch2.nii.txt") << "7 Dark\n8 Darker\n";  // ch2's lowest values
    ASSERT_TRUE(store.scan().ok());
    EXPECT_TRUE(label_maps().at("ch2.nii.gz"));
    const auto drawn = store.acquire_labels("ch2.nii.gz");
    ASSERT_TRUE(drawn.ok()) << drawn.error().to_string();
    EXPECT_EQ((*drawn)->labels.front().name, "Dark");
}

// A CD export: the DICOMDIR at the root is no volume; the series four folders down is.
TEST_F(VolumeStoreTest, AnExportRootListsItsSeriesNotItsDicomdir) {
    const fs::path root = data_ / "cdrom";
    volume::fixtures::SeriesSpec spec;
    spec.dims = {4, 4, 2};
    const auto files = volume::fixtures::write_series(root / "DICOM" / "PAT1" / "STU1" / "SER1",
                                                      spec, std::vector<std::uint16_t>(32, 5));
    std::vector<fs::path> renamed;
    for (std::size_t i = 0; i < files.size(); ++i) {
        renamed.push_back(files[i].parent_path() / ("IM" + std::to_string(i)));
        fs::rename(files[i], renamed.back());
    }
    volume::fixtures::write_dicomdir(root, renamed);
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"cdrom/DICOM/PAT1/STU1/SER1"}));
    auto loaded = store.acquire("cdrom/DICOM/PAT1/STU1/SER1");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ((*loaded)->dims, glm::uvec3(4, 4, 2));
}

// The suffixes are volume's, compared ignoring case as load_volume compares them: every file
// `penumbra render` opens is offered.
TEST_F(VolumeStoreTest, VolumeFileNamesInAnyCaseAreListed) {
    write_text(data_ / "HEAD.NII.GZ", "a NIfTI file");
    write_text(data_ / "Brain.Nrrd", "a NRRD file");
    write_text(data_ / "scan_2x2x2_uint8.RAW", "12345678");
    write_text(data_ / "NOTES.TXT", "not a volume");
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store),
              (std::vector<std::string>{"Brain.Nrrd", "HEAD.NII.GZ", "scan_2x2x2_uint8.RAW"}));
}

TEST_F(VolumeStoreTest, DicomFilesRightInTheDataFolderAreTheVolumeDot) {
    write_series(data_, {4, 4, 2});
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"."}));
    auto loaded = store.acquire(".");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ((*loaded)->dims, glm::uvec3(4, 4, 2));
}

// The administrator links volumes kept elsewhere into the data folder: links to files are
// listed under the link's name and open through it, wherever they lead; a link to a folder
// outside is followed only into a root the administrator allowed.
TEST_F(VolumeStoreTest, LinksInTheDataFolderAreFollowedAndNamedByTheLink) {
    const fs::path outside = data_.parent_path() / (data_.filename().string() + "-outside");
    write_series(outside / "series", {4, 4, 2});
    write_text(outside / "heads" / "a_2x2x2_uint8.raw", "12345678");
    fs::create_directory_symlink(outside / "series", data_ / "ct");
    fs::create_symlink(outside / "heads" / "a_2x2x2_uint8.raw", data_ / "b_2x2x2_uint8.raw");
    fs::create_directory_symlink(data_, data_ / "loop");  // walked once, not forever
    fs::create_symlink(data_ / "nothing.nrrd", data_ / "broken.nrrd");
    {
        VolumeStore store(data_, std::size_t{1} << 20);
        ASSERT_TRUE(store.scan().ok());
        EXPECT_EQ(ids(store), (std::vector<std::string>{"b_2x2x2_uint8.raw"}));
        auto raw = store.acquire("b_2x2x2_uint8.raw");
        ASSERT_TRUE(raw.ok()) << raw.error().to_string();
        EXPECT_EQ((*raw)->value(1, 1, 1), static_cast<double>('8'));
        EXPECT_EQ(store.acquire("ct").error().code, base::ErrorCode::unknown_volume);
        const std::vector<std::string> skipped = store.skipped();
        EXPECT_TRUE(std::any_of(skipped.begin(), skipped.end(), [](const std::string& line) {
            return line.starts_with("ct: a link to a folder outside the data folder");
        })) << "the link that leaves is named once, with why";
    }
    ScanOptions allowed;
    allowed.link_roots = {outside};
    VolumeStore store(data_, std::size_t{1} << 20, {}, allowed);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"b_2x2x2_uint8.raw", "ct"}));
    auto series = store.acquire("ct");
    ASSERT_TRUE(series.ok()) << series.error().to_string();
    EXPECT_EQ((*series)->dims, glm::uvec3(4, 4, 2));
    // Only listed ids open: the link's target by its own path does not.
    EXPECT_FALSE(store.acquire((outside / "heads" / "a_2x2x2_uint8.raw").string()).ok());
    EXPECT_FALSE(
            store.acquire("../" + outside.filename().string() + "/heads/a_2x2x2_uint8.raw").ok());
    fs::remove_all(outside);
}

// A link that was allowed when the folder was scanned and is then pointed elsewhere opens
// nothing: the load checks where it leads now.
TEST_F(VolumeStoreTest, AFolderLinkRepointedAfterTheScanDoesNotOpen) {
    const fs::path pacs = data_.parent_path() / (data_.filename().string() + "-pacs");
    const fs::path elsewhere = data_.parent_path() / (data_.filename().string() + "-elsewhere");
    write_series(pacs / "series", {4, 4, 2});
    write_series(elsewhere / "series", {4, 4, 3});
    fs::create_directory_symlink(pacs / "series", data_ / "ct");
    ScanOptions allowed;
    allowed.link_roots = {pacs};
    VolumeStore store(data_, std::size_t{1} << 20, {}, allowed);
    store.wait_for_first_pass();  // no pass of the store's own after the link is re-pointed
    ASSERT_EQ(ids(store), std::vector<std::string>{"ct"});
    fs::remove(data_ / "ct");
    fs::create_directory_symlink(elsewhere / "series", data_ / "ct");
    auto opened = store.acquire("ct");
    ASSERT_FALSE(opened.ok());
    EXPECT_EQ(opened.error().code, base::ErrorCode::unknown_volume);
    fs::remove_all(pacs);
    fs::remove_all(elsewhere);
}

// The first pass runs on the store's own thread from construction: a caller that opens a volume
// before it has been listed waits for that pass instead of hearing "unknown".
TEST_F(VolumeStoreTest, TheFirstPassRunsByItselfAndAnOpenWaitsForIt) {
    write_text(data_ / "a_2x2x2_uint8.raw", "12345678");
    VolumeStore store(data_, std::size_t{1} << 20);
    auto raw = store.acquire("a_2x2x2_uint8.raw");
    ASSERT_TRUE(raw.ok()) << raw.error().to_string();
    const ScanProgress progress = store.progress();
    EXPECT_TRUE(progress.first_pass_done);
    EXPECT_FALSE(progress.cut_short);
    EXPECT_EQ(store.acquire("b_2x2x2_uint8.raw").error().code, base::ErrorCode::unknown_volume);
}

// A tree deeper than any export is not walked to its bottom (each level holds a descriptor).
TEST_F(VolumeStoreTest, AWalkStopsSixteenFoldersDown) {
    fs::path deep = data_;
    for (int level = 0; level < 20; ++level) {
        deep /= "d";
        if (level == 10) {
            write_text(deep / "a_2x2x2_uint8.raw", "12345678");
        }
    }
    write_text(deep / "b_2x2x2_uint8.raw", "12345678");
    VolumeStore store(data_, std::size_t{1} << 20);
    store.wait_for_first_pass();
    const std::vector<std::string> listed = ids(store);
    ASSERT_EQ(listed.size(), 1U);
    EXPECT_TRUE(listed[0].ends_with("/a_2x2x2_uint8.raw"));
    const std::vector<std::string> skipped = store.skipped();
    EXPECT_TRUE(std::any_of(skipped.begin(), skipped.end(), [](const std::string& line) {
        return line.find("deeper than 16 folders") != std::string::npos;
    }));
}

// A pass stops at its budget of entries, lists what it found, and says why.
TEST_F(VolumeStoreTest, APassStopsAtItsBudgetAndSaysSo) {
    for (int i = 0; i < 50; ++i) {
        write_text(data_ / "stray" / ("note" + std::to_string(i) + ".txt"), "not a volume");
    }
    write_text(data_ / "a_2x2x2_uint8.raw", "12345678");
    ScanOptions small;
    small.max_entries = 10;
    metrics::Registry registry;
    small.metrics = &registry;
    VolumeStore store(data_, std::size_t{1} << 20, {}, small);
    store.wait_for_first_pass();
    const ScanProgress progress = store.progress();
    ASSERT_TRUE(progress.cut_short);
    EXPECT_NE(progress.cut_short->find("more than 10 files and folders"), std::string::npos)
            << *progress.cut_short;
    const std::string text = registry.prometheus_text();
    EXPECT_NE(text.find("penumbra_volume_scans_cut_short_total 1"), std::string::npos) << text;
    EXPECT_NE(text.find("penumbra_volume_scan_entries 11"), std::string::npos) << text;
}

// `--data DIR` showing no volume says why: every file passed over is reported with its reason.
TEST_F(VolumeStoreTest, EverySkippedFileIsReportedWithWhy) {
    write_text(data_ / "notes" / "plan.txt", "not a volume");
    write_text(data_ / "head.nii.bak", "not a volume name either");
    fs::create_symlink(data_ / "gone.nrrd", data_ / "broken.nrrd");
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_TRUE(store.list().empty());
    const std::vector<std::string> skipped = store.skipped();
    ASSERT_EQ(skipped.size(), 3U);
    const auto reason = [&](const std::string& id) {
        for (const std::string& line : skipped) {
            if (line.starts_with(id + ": ")) {
                return line.substr(id.size() + 2);
            }
        }
        return std::string("(not reported)");
    };
    EXPECT_NE(reason("notes/plan.txt").find("not a volume"), std::string::npos);
    EXPECT_NE(reason("head.nii.bak").find(" .nii.gz"), std::string::npos);
    EXPECT_NE(reason("broken.nrrd").find("a link to nothing"), std::string::npos);
}

TEST_F(VolumeStoreTest, LoadsRunOnALoaderThreadAndEachVolumeGetsOneHistogram) {
    write_text(data_ / "a_2x2x2_uint8.raw", "12345678");
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    std::promise<std::thread::id> loaded_on;
    std::promise<base::Result<std::shared_ptr<const volume::Volume>>> loaded;
    store.acquire_async("a_2x2x2_uint8.raw", [&](auto result) {
        loaded_on.set_value(std::this_thread::get_id());
        loaded.set_value(std::move(result));
    });
    EXPECT_NE(loaded_on.get_future().get(), std::this_thread::get_id());
    auto volume = loaded.get_future().get();
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(store.histograms_computed(), 1U) << "computed with the load, off the caller";
    const auto first = store.histogram(*volume);
    ASSERT_EQ(first->size(), static_cast<std::size_t>(VolumeStore::histogram_bins));
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(store.histogram(*volume), first) << "the same bins, not a new computation";
    }
    EXPECT_EQ(store.histograms_computed(), 1U);
}

TEST_F(VolumeStoreTest, ListingAnswersFromTheLastScanAndAChangedFolderIsRescannedSoon) {
    write_text(data_ / "a_2x2x2_uint8.raw", "12345678");
    ScanOptions hourly;
    hourly.rescan_interval = std::chrono::hours(1);
    VolumeStore store(data_, std::size_t{1} << 20, {}, hourly);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), std::vector<std::string>{"a_2x2x2_uint8.raw"});
    // A file added at the top changes the folder's modification time; the listing that notices
    // it asks the store's own thread for a scan (not the caller's, and not the hour's timer).
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    write_text(data_ / "b_2x2x2_uint8.raw", "12345678");
    std::vector<std::string> listed = ids(store);
    for (int i = 0; i < 100 && listed.size() < 2; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        listed = ids(store);
    }
    EXPECT_EQ(listed, (std::vector<std::string>{"a_2x2x2_uint8.raw", "b_2x2x2_uint8.raw"}));
}

TEST_F(VolumeStoreTest, LoadedVolumesBeyondTheBudgetAreDroppedLeastRecentlyUsedFirst) {
    for (const char* name : {"a", "b", "c"}) {
        write_text(data_ / (std::string(name) + "_2x2x2_uint8.raw"), "12345678");
    }
    VolumeStore store(data_, 16);  // two of the 8-byte volumes
    ASSERT_TRUE(store.scan().ok());
    const auto loaded = [&] {
        std::vector<std::string> held;
        for (const auto& entry : store.list()) {
            if (entry.loaded) {
                held.push_back(entry.id.substr(0, 1));
            }
        }
        return held;
    };
    const auto acquire = [&](const std::string& name) {
        ASSERT_TRUE(store.acquire(name + "_2x2x2_uint8.raw").ok()) << name;
    };
    acquire("a");
    acquire("b");
    acquire("a");  // held: b is now the least recently used
    EXPECT_EQ(store.loads(), 2U);
    acquire("c");
    EXPECT_EQ(loaded(), (std::vector<std::string>{"a", "c"}));
    acquire("b");
    EXPECT_EQ(store.loads(), 4U);
    EXPECT_EQ(loaded(), (std::vector<std::string>{"b", "c"}));
    // A volume whose file is gone at the next scan leaves the budget with it: a fits beside b.
    fs::remove(data_ / "c_2x2x2_uint8.raw");
    ASSERT_TRUE(store.scan().ok());
    acquire("a");
    EXPECT_EQ(loaded(), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(store.loads(), 5U);
}

TEST_F(VolumeStoreTest, LoadErrorsNameFilesRelativeToTheDataFolder) {
    write_text(data_ / "heads" / "short_4x4x4_uint8.raw", "too short");
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    const auto failed = store.acquire("heads/short_4x4x4_uint8.raw");
    ASSERT_FALSE(failed.ok());
    const std::string said = failed.error().to_string();
    EXPECT_EQ(said.find(data_.string()), std::string::npos) << said;
    EXPECT_NE(said.find("heads/short_4x4x4_uint8.raw"), std::string::npos) << said;
}

}  // namespace
}  // namespace penumbra::session
