#pragma once

// File access shared by the loaders: opening with a useful error, exact reads, and streaming gzip
// decompression into a buffer of known size. Private to the volume module.

#include <penumbra/base/result.hpp>

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <system_error>
#include <vector>

namespace penumbra::volume::detail {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};

using File = std::unique_ptr<std::FILE, FileCloser>;

// "where" strings for errors: the file alone, a byte offset in it, or a header line.
inline std::string at_file(const std::filesystem::path& path) {
    return path.string();
}

inline std::string at_byte(const std::filesystem::path& path, std::uint64_t offset) {
    return path.string() + ":byte " + std::to_string(offset);
}

inline std::string at_line(const std::filesystem::path& path, std::size_t line) {
    return path.string() + ":line " + std::to_string(line);
}

inline base::Result<std::uint64_t> regular_file_size(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        return base::make_error(base::ErrorCode::not_found, "file not found", at_file(path));
    }
    if (!std::filesystem::is_regular_file(status)) {
        return base::make_error(base::ErrorCode::read_failed, "not a regular file", at_file(path));
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) {
        return base::make_error(base::ErrorCode::read_failed,
                                "cannot read the file size: " + ec.message(), at_file(path));
    }
    return static_cast<std::uint64_t>(size);
}

inline base::Result<File> open_file(const std::filesystem::path& path) {
    if (auto size = regular_file_size(path); !size) {
        return size.error();
    }
    File file(std::fopen(path.c_str(), "rb"));
    if (!file) {
        return base::make_error(base::ErrorCode::read_failed,
                                std::string("cannot open the file: ") + std::strerror(errno),
                                at_file(path));
    }
    return file;
}

inline base::Status seek_to(std::FILE* file, const std::filesystem::path& path,
                            std::uint64_t offset) {
    if (offset > static_cast<std::uint64_t>(LONG_MAX) ||
        std::fseek(file, static_cast<long>(offset), SEEK_SET) != 0) {
        return base::make_error(base::ErrorCode::read_failed, "cannot seek in the file",
                                at_byte(path, offset));
    }
    return base::Ok{};
}

// Reads up to out.size() bytes; fewer only at the end of the file. `offset` is where the read
// starts, for the error message.
inline base::Result<std::size_t> read_some(std::FILE* file, const std::filesystem::path& path,
                                           std::uint64_t offset, std::span<std::byte> out) {
    const std::size_t got = std::fread(out.data(), 1, out.size(), file);
    if (got < out.size() && std::ferror(file)) {
        return base::make_error(base::ErrorCode::read_failed,
                                std::string("read error: ") + std::strerror(errno),
                                at_byte(path, offset + got));
    }
    return got;
}

struct Inflated {
    std::uint64_t produced = 0;  // bytes given to the target
    bool more = false;           // the stream holds data beyond skip + out.size()
    bool complete = false;       // the compressed stream reached its end marker
};

// Reads the file from its current position into `target` until the target is full or the file
// ends; returns the bytes read. A Target offers window() (where the next bytes go, empty when
// full) and commit(count) (SampleSink). `offset` is the current position, for errors.
template <class Target>
base::Result<std::uint64_t> read_into(std::FILE* file, const std::filesystem::path& path,
                                      std::uint64_t offset, Target& target) {
    std::uint64_t total = 0;
    for (std::span<std::byte> window = target.window(); !window.empty(); window = target.window()) {
        // Bounded reads keep a huge direct window from being one enormous fread.
        window = window.first(std::min<std::size_t>(window.size(), std::size_t{1} << 26));
        auto got = read_some(file, path, offset + total, window);
        if (!got) {
            return got.error();
        }
        target.commit(*got);
        total += *got;
        if (*got < window.size()) {
            break;
        }
    }
    return total;
}

// Decompresses the gzip (or zlib) stream that starts at the file's current position, drops the
// first `skip` bytes of output and fills `target` (see read_into). It decompresses at most one
// byte past what the target takes, so a small file that expands to terabytes (a gzip bomb) costs
// neither memory nor much time. As with gzip(1), concatenated gzip members are read as one stream
// and other bytes after the stream are ignored. `start_offset` is the stream's offset in the
// file, for errors.
template <class Target>
base::Result<Inflated> inflate_file(std::FILE* file, const std::filesystem::path& path,
                                    std::uint64_t start_offset, std::uint64_t skip,
                                    Target& target) {
    z_stream zs{};
    constexpr int gzip_or_zlib_header = 15 + 32;
    if (inflateInit2(&zs, gzip_or_zlib_header) != Z_OK) {
        return base::make_error(base::ErrorCode::read_failed, "zlib could not start a decompressor",
                                at_file(path));
    }

    struct EndInflate {
        z_stream* zs;

        ~EndInflate() { inflateEnd(zs); }
    } end_inflate{&zs};

    std::vector<unsigned char> input(std::size_t{1} << 16);
    std::array<unsigned char, 1 << 14> scratch{};
    std::uint64_t consumed = 0;  // compressed bytes consumed, over all members
    std::uint64_t skip_left = skip;
    Inflated result;
    bool input_ended = false;

    // Keeps at least `wanted` compressed bytes available unless the file has ended.
    const auto refill = [&](uInt wanted) -> base::Status {
        if (zs.avail_in >= wanted || input_ended) {
            return base::Ok{};
        }
        if (zs.avail_in > 0) {
            std::memmove(input.data(), zs.next_in, zs.avail_in);
        }
        const std::size_t room = input.size() - zs.avail_in;
        const std::size_t got = std::fread(input.data() + zs.avail_in, 1, room, file);
        if (got < room && std::ferror(file)) {
            return base::make_error(base::ErrorCode::read_failed,
                                    std::string("read error: ") + std::strerror(errno),
                                    at_byte(path, start_offset + consumed + zs.avail_in));
        }
        input_ended = got == 0;
        zs.next_in = input.data();
        zs.avail_in += static_cast<uInt>(got);
        return base::Ok{};
    };

    for (;;) {
        if (auto status = refill(1); !status) {
            return status.error();
        }
        if (zs.avail_in == 0) {
            return result;  // the compressed data ended before the stream's end marker
        }
        const bool skipping = skip_left > 0;
        const std::span<std::byte> window = skipping ? std::span<std::byte>() : target.window();
        const bool probing = !skipping && window.empty();
        if (skipping) {
            zs.next_out = scratch.data();
            zs.avail_out = static_cast<uInt>(std::min<std::uint64_t>(scratch.size(), skip_left));
        } else if (probing) {
            zs.next_out = scratch.data();
            zs.avail_out = 1;
        } else {
            zs.next_out = reinterpret_cast<unsigned char*>(window.data());
            zs.avail_out = static_cast<uInt>(std::min<std::uint64_t>(window.size(), UINT_MAX));
        }
        const uInt avail_in_before = zs.avail_in;
        const uInt avail_out_before = zs.avail_out;
        const int ret = inflate(&zs, Z_NO_FLUSH);
        consumed += avail_in_before - zs.avail_in;
        const std::uint64_t produced = avail_out_before - zs.avail_out;
        if (skipping) {
            skip_left -= produced;
        } else if (probing) {
            if (produced > 0) {
                result.more = true;
                result.complete = true;  // not known, and irrelevant: the data is too long
                return result;
            }
        } else {
            target.commit(static_cast<std::size_t>(produced));
            result.produced += produced;
        }

        if (ret == Z_STREAM_END) {
            if (auto status = refill(2); !status) {
                return status.error();
            }
            constexpr unsigned char gzip_magic[2] = {0x1f, 0x8b};
            if (zs.avail_in >= 2 && zs.next_in[0] == gzip_magic[0] &&
                zs.next_in[1] == gzip_magic[1]) {
                inflateReset(&zs);
                continue;
            }
            result.complete = true;
            return result;
        }
        if (ret != Z_OK && ret != Z_BUF_ERROR) {
            const std::string reason = zs.msg != nullptr ? zs.msg : "zlib error";
            return base::make_error(base::ErrorCode::corrupt_data,
                                    "invalid compressed data (" + reason + ")",
                                    at_byte(path, start_offset + consumed));
        }
    }
}

}  // namespace penumbra::volume::detail
