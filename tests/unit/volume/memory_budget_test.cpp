// The memory a load may take: checked against what a file declares before anything is allocated,
// one copy of the volume while loading, and a failed allocation as an Error, never a crash.

#include "dicom_writer.hpp"
#include "fixture_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>
#include <nifti2_io.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace penumbra::volume {
namespace {

constexpr std::uint64_t mib = std::uint64_t{1} << 20;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// `load` is refused for its budget one byte below `needed` and loads with exactly `needed`.
void expect_budget(const std::function<base::Result<Volume>(const LoadOptions&)>& load,
                   std::uint64_t needed) {
    LoadOptions below;
    below.max_bytes = needed - 1;
    const auto refused = load(below);
    ASSERT_FALSE(refused.ok()) << "a budget one byte short must refuse the load";
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_large);
    EXPECT_TRUE(contains(refused.error().message, "load limit")) << refused.error().message;
    LoadOptions exact;
    exact.max_bytes = needed;
    const auto loaded = load(exact);
    EXPECT_TRUE(loaded.ok()) << loaded.error().to_string();
}

TEST(LoadBudget, RawCountsTheBytesOfTheTypeTheVolumeKeeps) {
    fixtures::TempDir dir;
    const std::vector<std::byte> samples(16 * 8 * 4 * 2, std::byte{1});
    fixtures::write_bytes(dir / "kept_16x8x4_uint16.raw", samples);
    expect_budget([&](const LoadOptions& o) { return load_raw(dir / "kept_16x8x4_uint16.raw", o); },
                  16 * 8 * 4 * 2);
    // int16 is kept as int16; float64 becomes float32: half the file's bytes.
    fixtures::write_bytes(dir / "kept_16x8x4_int16.raw", samples);
    expect_budget(
            [&](const LoadOptions& o) { return load_volume(dir / "kept_16x8x4_int16.raw", o); },
            16 * 8 * 4 * 2);
    const std::vector<std::byte> doubles(16 * 8 * 4 * 8, std::byte{0});
    fixtures::write_gzip_file(dir / "gz_16x8x4_float64.raw.gz", doubles);
    expect_budget(
            [&](const LoadOptions& o) { return load_raw(dir / "gz_16x8x4_float64.raw.gz", o); },
            16 * 8 * 4 * 4);
}

TEST(LoadBudget, NrrdCountsTheDeclaredSizeEvenWhenTheDataIsMissing) {
    fixtures::TempDir dir;
    const std::string header =
            "NRRD0004\ntype: double\ndimension: 3\nsizes: 8 8 8\nencoding: raw\nendian: "
            "little\n";
    fixtures::write_text(dir / "missing.nhdr", header + "data file: missing.raw\n");
    LoadOptions small;
    small.max_bytes = 8 * 8 * 8 * 4 - 1;
    const auto refused = load_nrrd(dir / "missing.nhdr", small);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_large)
            << "the budget is checked before the data file";

    const std::vector<std::byte> doubles(8 * 8 * 8 * 8, std::byte{0});
    fixtures::write_bytes(dir / "doubles.raw", doubles);
    fixtures::write_text(dir / "doubles.nhdr", header + "data file: doubles.raw\n");
    // float64 is kept as float32: half the file's bytes, converted chunk by chunk.
    expect_budget([&](const LoadOptions& o) { return load_nrrd(dir / "doubles.nhdr", o); },
                  8 * 8 * 8 * 4);
}

TEST(LoadBudget, NiftiCountsTheStoredBytes) {
    fixtures::TempDir dir;
    std::int64_t dims[8] = {3, 8, 4, 2, 1, 1, 1, 1};
    nifti_image* image = nifti_make_new_nim(dims, DT_INT32, 1);
    ASSERT_NE(image, nullptr);
    const auto path = dir / "int.nii.gz";
    ASSERT_EQ(nifti_set_filenames(image, path.c_str(), 0, 1), 0);
    nifti_image_write(image);
    nifti_image_free(image);
    expect_budget([&](const LoadOptions& o) { return load_nifti(path, o); }, 8 * 4 * 2 * 4);
}

TEST(LoadBudget, DicomCountsTheDecodedVolumeAndWhatItHoldsBeside) {
    fixtures::TempDir dir;
    fixtures::SeriesSpec spec;
    spec.dims = {8, 6, 3};
    std::vector<std::uint16_t> words(8 * 6 * 3, 7);
    fixtures::write_series(dir.path(), spec, words);
    LoadOptions tiny;
    tiny.max_bytes = 8 * 6 * 3 * 4;  // the float32 voxels alone: not enough
    const auto refused = load_volume(dir.path(), tiny);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_large);
    LoadOptions enough;
    enough.max_bytes = mib;
    const auto loaded = load_volume(dir.path(), enough);
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ(loaded->type, VoxelType::uint16);
}

TEST(LoadBudget, AvailableMemoryIsReadFromTheSystem) {
    const auto available = available_memory();
    ASSERT_TRUE(available.has_value()) << "/proc/meminfo has no MemAvailable";
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t total_kib = 0;
    ASSERT_TRUE(meminfo >> key >> total_kib && key == "MemTotal:");
    EXPECT_GT(*available, 0u);
    EXPECT_LE(*available, total_kib * 1024);
}

// --- Under an address-space limit (RLIMIT_AS), in a child process -------------------------------

#if defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_ADDRESS_SANITIZER 1
#endif
#endif

std::uint64_t address_space_in_use() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.starts_with("VmSize:")) {
            std::istringstream fields(line.substr(7));
            std::uint64_t kibibytes = 0;
            fields >> kibibytes;
            return kibibytes * 1024;
        }
    }
    return 0;
}

// What a child that ran `load` under an address-space limit of what it uses now + `headroom`
// reported: 0 loaded, 1 refused with an Error of `code`, 2 another Error; a crash (an uncaught
// std::bad_alloc aborts) shows as a signal.
struct ChildResult {
    bool exited = false;
    int status = -1;
    int signal = 0;
};

ChildResult run_limited(std::uint64_t headroom, const std::function<base::Result<Volume>()>& load,
                        std::optional<base::ErrorCode> code) {
    const pid_t child = fork();
    if (child == 0) {
        const std::uint64_t limit = address_space_in_use() + headroom;
        const rlimit cap{limit, limit};
        if (setrlimit(RLIMIT_AS, &cap) != 0) {
            _exit(3);
        }
        const auto result = load();
        _exit(result.ok() ? 0 : result.error().code == code ? 1 : 2);
    }
    ChildResult result;
    int status = 0;
    if (child < 0 || waitpid(child, &status, 0) != child) {
        return result;
    }
    result.exited = WIFEXITED(status);
    result.status = result.exited ? WEXITSTATUS(status) : -1;
    result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    return result;
}

class LoadUnderAddressLimit : public ::testing::Test {
protected:
    void SetUp() override {
#ifdef PENUMBRA_ADDRESS_SANITIZER
        GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: RLIMIT_AS cannot "
                        "be applied";
#endif
    }
};

// Finding: a file whose declared size passed max_voxels but needed more memory than the process
// could get was allocated in one go, and the uncaught std::bad_alloc aborted the server.
TEST_F(LoadUnderAddressLimit, AnAllocationThatFailsIsAnErrorNotACrash) {
    fixtures::TempDir dir;
    const auto path = dir / "huge_1024x1024x512_uint8.raw";
    std::filesystem::resize_file((fixtures::write_bytes(path, {}), path), 512 * mib);  // sparse
    const auto result = run_limited(
            128 * mib,
            [&] {
                LoadOptions options;
                options.within_available_memory = false;
                return load_raw(path, options);
            },
            base::ErrorCode::out_of_memory);
    EXPECT_TRUE(result.exited) << "the child died of signal " << result.signal;
    EXPECT_EQ(result.status, 1) << "expected an out_of_memory Error";
}

// Loading keeps about one copy of the volume: int16 samples (64 MiB) become float32 (128 MiB)
// chunk by chunk, so the load fits in 128 MiB + 24 MiB of address space; reading the file whole
// and converting it (64 + 128 MiB) does not.
TEST_F(LoadUnderAddressLimit, ConvertingLoadsHoldOneCopyOfTheVolume) {
    fixtures::TempDir dir;
    const auto raw = dir / "wide_512x512x128_int16.raw";
    std::filesystem::resize_file((fixtures::write_bytes(raw, {}), raw), 64 * mib);
    const auto loaded = run_limited(
            152 * mib, [&] { return load_raw(raw); }, std::nullopt);
    EXPECT_TRUE(loaded.exited) << "the child died of signal " << loaded.signal;
    EXPECT_EQ(loaded.status, 0) << "the load did not fit in one copy of the volume + 24 MiB";

    // The same through NIfTI: the header by the nifti library, the int16 voxels (sparse zeros)
    // after it; the library's own read would hold a second, 64 MiB copy.
    const auto nifti = dir / "wide.nii";
    std::int64_t dims[8] = {3, 512, 512, 128, 1, 1, 1, 1};
    nifti_image* image = nifti_make_new_nim(dims, DT_INT16, 0);
    ASSERT_NE(image, nullptr);
    ASSERT_EQ(nifti_set_filenames(image, nifti.c_str(), 0, 1), 0);
    znzFile header = nifti_image_write_hdr_img(image, 2, "wb");  // 2: the header only, kept open
    ASSERT_FALSE(znz_isnull(header));
    znzclose(header);
    const auto data_offset = static_cast<std::uintmax_t>(image->iname_offset);
    nifti_image_free(image);
    std::filesystem::resize_file(nifti, data_offset + 64 * mib);
    const auto from_nifti = run_limited(
            152 * mib, [&] { return load_nifti(nifti); }, std::nullopt);
    EXPECT_TRUE(from_nifti.exited) << "the child died of signal " << from_nifti.signal;
    EXPECT_EQ(from_nifti.status, 0) << "the NIfTI load did not fit in one copy + 24 MiB";

    // The same through NRRD with gzip data: 16 MiB of uint16 kept as they are.
    const std::vector<std::byte> zeros(16 * mib, std::byte{0});
    fixtures::write_bytes(dir / "kept.raw.gz", fixtures::gzip_bytes(zeros));
    fixtures::write_text(dir / "kept.nhdr",
                         "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 512 512 32\n"
                         "encoding: gzip\nendian: little\ndata file: kept.raw.gz\n");
    const auto nrrd = run_limited(
            16 * mib + 12 * mib, [&] { return load_nrrd(dir / "kept.nhdr"); }, std::nullopt);
    EXPECT_TRUE(nrrd.exited) << "the child died of signal " << nrrd.signal;
    EXPECT_EQ(nrrd.status, 0);
}

}  // namespace
}  // namespace penumbra::volume
