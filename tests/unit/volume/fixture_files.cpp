#include "fixture_files.hpp"

#include <zlib.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace penumbra::volume::fixtures {

TempDir::TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "penumbra-volume-XXXXXX");
    if (mkdtemp(pattern.data()) == nullptr) {
        throw std::runtime_error("cannot create a temp folder from " + pattern);
    }
    path_ = pattern;
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

void write_bytes(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        throw std::runtime_error("cannot write fixture " + path.string());
    }
}

void write_text(const std::filesystem::path& path, std::string_view text) {
    write_bytes(path, text_bytes(text));
}

void write_gzip_file(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    gzFile file = gzopen(path.c_str(), "wb");
    if (file == nullptr) {
        throw std::runtime_error("cannot open fixture " + path.string());
    }
    std::size_t written = 0;
    while (written < bytes.size()) {
        const auto chunk =
                static_cast<unsigned>(std::min<std::size_t>(bytes.size() - written, 1u << 20));
        if (gzwrite(file, bytes.data() + written, chunk) != static_cast<int>(chunk)) {
            gzclose(file);
            throw std::runtime_error("cannot write fixture " + path.string());
        }
        written += chunk;
    }
    if (gzclose(file) != Z_OK) {
        throw std::runtime_error("cannot close fixture " + path.string());
    }
}

std::vector<std::byte> gzip_bytes(std::span<const std::byte> bytes) {
    z_stream zs{};
    constexpr int gzip_format = 15 + 16;
    if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, gzip_format, 8, Z_DEFAULT_STRATEGY) !=
        Z_OK) {
        throw std::runtime_error("deflateInit2 failed");
    }
    std::vector<std::byte> out(deflateBound(&zs, static_cast<uLong>(bytes.size())) + 64);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(bytes.data()));
    zs.avail_in = static_cast<uInt>(bytes.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = static_cast<uInt>(out.size());
    const int ret = deflate(&zs, Z_FINISH);
    const std::size_t size = zs.total_out;
    deflateEnd(&zs);
    if (ret != Z_STREAM_END) {
        throw std::runtime_error("deflate failed");
    }
    out.resize(size);
    return out;
}

std::vector<std::byte> text_bytes(std::string_view text) {
    std::vector<std::byte> bytes(text.size());
    if (!text.empty()) {
        std::memcpy(bytes.data(), text.data(), text.size());
    }
    return bytes;
}

std::vector<std::byte> concat(std::span<const std::byte> a, std::span<const std::byte> b) {
    std::vector<std::byte> out(a.begin(), a.end());
    out.insert(out.end(), b.begin(), b.end());
    return out;
}

}  // namespace penumbra::volume::fixtures
