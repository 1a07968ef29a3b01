#pragma once

// Fixture files for the loader tests: a fresh folder per test and small writers. A failure to
// write a fixture throws, which GoogleTest reports as a failed test.

#include <cstddef>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::volume::fixtures {

// A new, empty folder under the system temp folder, removed with everything in it at the end of
// the test.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

    [[nodiscard]] std::filesystem::path operator/(std::string_view name) const {
        return path_ / name;
    }

private:
    std::filesystem::path path_;
};

void write_bytes(const std::filesystem::path& path, std::span<const std::byte> bytes);

void write_text(const std::filesystem::path& path, std::string_view text);

// Writes `bytes` gzip-compressed through zlib's gzopen/gzwrite, as gzip(1) would.
void write_gzip_file(const std::filesystem::path& path, std::span<const std::byte> bytes);

// The gzip (RFC 1952) compression of `bytes`, for data attached behind a NRRD header.
std::vector<std::byte> gzip_bytes(std::span<const std::byte> bytes);

template <class T>
std::vector<std::byte> as_bytes(const std::vector<T>& values) {
    std::vector<std::byte> bytes(values.size() * sizeof(T));
    if (!values.empty()) {
        std::memcpy(bytes.data(), values.data(), bytes.size());
    }
    return bytes;
}

std::vector<std::byte> text_bytes(std::string_view text);

std::vector<std::byte> concat(std::span<const std::byte> a, std::span<const std::byte> b);

}  // namespace penumbra::volume::fixtures
