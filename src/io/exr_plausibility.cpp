// Plausibility of an EXR's size claims, read through OpenEXR's core API: it reads the header and
// the chunk table without allocating pixel memory, so a hostile header fails in microseconds.
#include "io/exr_plausibility.hpp"

#include <OpenEXR/openexr.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>

#include "decalcomp/error.hpp"
#include "decalcomp/memory_limit.hpp"
#include "io/exr_core.hpp"

namespace decalcomp::io {

namespace {

// The most a chunk can expand: its decoded bytes over its stored bytes. Deflate tops out near
// 1032:1 (ZIP, ZIPS; PXR24 adds 4:3 for 24-bit floats); PIZ's Huffman runs about 255 values per
// code; DWA's DC and lossless planes go through deflate after RLE. Generous on purpose: the bound
// only refuses headers that no encoder could have written.
std::uint64_t maxExpansion(exr_compression_t compression) {
    switch (compression) {
        case EXR_COMPRESSION_NONE: return 1;
        case EXR_COMPRESSION_RLE: return 128;
        case EXR_COMPRESSION_B44:
        case EXR_COMPRESSION_B44A: return 32;
        case EXR_COMPRESSION_ZIPS:
        case EXR_COMPRESSION_ZIP:
        case EXR_COMPRESSION_PIZ:
        case EXR_COMPRESSION_PXR24: return 2048;
        default: return 65536;
    }
}
constexpr std::uint64_t kChunkSlack = 256;  // codec headers of tiny chunks
constexpr std::uint64_t kMaxChannels = 4096;  // per part; renderers write dozens, AOV-heavy files hundreds
constexpr std::size_t kMaxHeaderBytes = std::size_t(64) << 20;

// Header and chunk table only: no pixel memory.
struct CoreReader : CoreContext {
    explicit CoreReader(const std::string& path) : CoreContext(path, Mode::Read) {}
};

struct PartSize {
    std::uint64_t width = 0, height = 0;
    std::uint64_t bytes = 0;  // every channel's samples, as decoded
};

std::uint64_t bytesPerSample(exr_pixel_type_t type) { return type == EXR_PIXEL_HALF ? 2 : 4; }

PartSize partSize(const CoreReader& reader, int part, const std::string& path) {
    exr_attr_box2i_t window{};
    reader.require(exr_get_data_window(reader.context(), part, &window), part, "dataWindow");
    const std::int64_t width = std::int64_t(window.max.x) - window.min.x + 1;
    const std::int64_t height = std::int64_t(window.max.y) - window.min.y + 1;
    // Pixel indices must fit in int for OpenEXR's and our own arithmetic.
    if (width <= 0 || height <= 0 || width > INT32_MAX || height > INT32_MAX)
        throw inputError(fmt::format("{}: part {}: dataWindow: ({},{})-({},{}) is not a valid window; the header is "
                                     "corrupt",
                                     path, part, window.min.x, window.min.y, window.max.x, window.max.y));
    const exr_attr_chlist_t* channels = nullptr;
    reader.require(exr_get_channels(reader.context(), part, &channels), part, "channels");
    PartSize size{std::uint64_t(width), std::uint64_t(height), 0};
    for (int c = 0; c < channels->num_channels; ++c) {
        const exr_attr_chlist_entry_t& channel = channels->entries[c];
        const auto bytes = decodedChannelBytes(size.width, size.height, channel.x_sampling, channel.y_sampling,
                                               bytesPerSample(channel.pixel_type));
        if (!bytes || size.bytes + *bytes < size.bytes)
            throw inputError(fmt::format("{}: part {}: dataWindow: {}x{} with {} channels overflows; the header is "
                                         "corrupt",
                                         path, part, width, height, channels->num_channels));
        size.bytes += *bytes;
    }
    return size;
}

// Every chunk must be where the table says, lead with its own coordinates and hold enough
// stored bytes for what it decodes to.
void requireChunk(const std::string& where, int index, const exr_chunk_info_t& chunk, exr_compression_t compression) {
    const std::uint64_t bound = chunk.packed_size * maxExpansion(compression) + kChunkSlack;
    if (chunk.packed_size == 0 || chunk.unpacked_size > bound)
        throw inputError(fmt::format("{}: chunk {}: {} stored bytes cannot decode to {}; the header claims more pixels "
                                     "than the file holds (corrupt or edited header)",
                                     where, index, chunk.packed_size, readableBytes(chunk.unpacked_size)));
}

// "FILE: part P: dataWindow (x0,y0)-(x1,y1) with N channels": what a chunk failure puts in doubt.
std::string claimText(const CoreReader& reader, int part, const exr_attr_box2i_t& window, const std::string& path) {
    const exr_attr_chlist_t* channels = nullptr;
    const int count = exr_get_channels(reader.context(), part, &channels) == EXR_ERR_SUCCESS ? channels->num_channels : 0;
    return fmt::format("{}: part {}: dataWindow ({},{})-({},{}) with {} channels", path, part, window.min.x,
                       window.min.y, window.max.x, window.max.y, count);
}

void requirePlausibleChunks(const CoreReader& reader, int part, const std::string& path) {
    exr_storage_t storage{};
    reader.require(exr_get_storage(reader.context(), part, &storage), part, "type");
    if (storage == EXR_STORAGE_DEEP_SCANLINE || storage == EXR_STORAGE_DEEP_TILED) return;  // refused later
    exr_compression_t compression{};
    reader.require(exr_get_compression(reader.context(), part, &compression), part, "compression");
    exr_attr_box2i_t window{};
    reader.require(exr_get_data_window(reader.context(), part, &window), part, "dataWindow");
    const std::string where = claimText(reader, part, window, path);
    const auto missing = [&](int index, exr_result_t result) {
        return inputError(fmt::format("{}: chunk {}: {}; the file is truncated, or its header claims more pixels than "
                                      "it holds",
                                      where, index, reader.reason(result)));
    };
    int index = 0;
    if (storage == EXR_STORAGE_SCANLINE) {
        std::int32_t lines = 0;
        reader.require(exr_get_scanlines_per_chunk(reader.context(), part, &lines), part, "compression");
        for (std::int64_t y = window.min.y; y <= window.max.y; y += lines, ++index) {
            exr_chunk_info_t chunk{};
            const exr_result_t result = exr_read_scanline_chunk_info(reader.context(), part, int(y), &chunk);
            if (result != EXR_ERR_SUCCESS) throw missing(index, result);
            requireChunk(where, index, chunk, compression);
        }
        return;
    }
    // Tiled: level 0 only (multi-level parts are refused when read).
    std::int32_t tile_w = 0, tile_h = 0, level_w = 0, level_h = 0;
    reader.require(exr_get_tile_sizes(reader.context(), part, 0, 0, &tile_w, &tile_h), part, "tiles");
    reader.require(exr_get_level_sizes(reader.context(), part, 0, 0, &level_w, &level_h), part, "tiles");
    if (tile_w <= 0 || tile_h <= 0)
        throw inputError(fmt::format("{}: part {}: tiles: {}x{} tiles are not valid", path, part, tile_w, tile_h));
    for (std::int32_t ty = 0; ty < (level_h + tile_h - 1) / tile_h; ++ty)
        for (std::int32_t tx = 0; tx < (level_w + tile_w - 1) / tile_w; ++tx, ++index) {
            exr_chunk_info_t chunk{};
            const exr_result_t result = exr_read_tile_chunk_info(reader.context(), part, tx, ty, 0, 0, &chunk);
            if (result != EXR_ERR_SUCCESS) throw missing(index, result);
            requireChunk(where, index, chunk, compression);
        }
}

// OpenEXR's core inserts channels into a sorted list one by one, so a header listing 10^5 channels
// takes it tens of seconds; the 'channels' attributes are counted here, from the raw header bytes,
// before OpenEXR parses them. nullopt while `header` ends before the headers do.
std::optional<std::uint64_t> largestChannelList(const std::string& header) {
    if (header.size() < 8) return std::nullopt;
    std::int32_t version = 0;
    std::memcpy(&version, &header[4], 4);
    const bool multi_part = (version & 0x1000) != 0;
    std::size_t at = 8;
    std::uint64_t largest = 0;
    bool header_start = true;
    while (at < header.size()) {
        if (header[at] == '\0') {  // the end of a part's header; an empty one ends a multi-part list
            ++at;
            if (!multi_part || header_start) return largest;
            header_start = true;
            continue;
        }
        header_start = false;
        const std::size_t name_end = header.find('\0', at);
        const std::size_t type_end = name_end == std::string::npos ? name_end : header.find('\0', name_end + 1);
        if (type_end == std::string::npos || type_end + 5 > header.size()) return std::nullopt;
        const std::string name = header.substr(at, name_end - at);
        const std::string type = header.substr(name_end + 1, type_end - name_end - 1);
        std::int32_t size = 0;
        std::memcpy(&size, &header[type_end + 1], 4);
        at = type_end + 5;
        if (size < 0) return largest;  // OpenEXR refuses it with its own message
        if (at + std::size_t(size) > header.size()) return std::nullopt;
        if (name == "channels" && type == "chlist") {
            // Entries: name, NUL, then 16 bytes (type, pLinear, reserved, x and y sampling).
            std::uint64_t count = 0;
            for (std::size_t p = at; p < at + std::size_t(size) && header[p] != '\0'; ++count) {
                const std::size_t end = header.find('\0', p);
                if (end == std::string::npos) break;
                p = end + 1 + 16;
            }
            largest = std::max(largest, count);
        }
        at += std::size_t(size);
    }
    return std::nullopt;
}

// Reads the file's start, growing until the headers are in (headers are usually a few KB).
std::uint64_t largestChannelListOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string header;
    for (std::size_t want = std::size_t(64) << 10;; want *= 8) {
        want = std::min(want, kMaxHeaderBytes);
        const std::size_t have = header.size();
        header.resize(want);
        in.read(header.data() + have, std::streamsize(want - have));
        header.resize(have + std::size_t(in.gcount()));
        if (const auto count = largestChannelList(header)) return *count;
        if (!in || want == kMaxHeaderBytes) return 0;  // short or odd: OpenEXR's own checks decide
    }
}

}  // namespace

std::optional<std::uint64_t> decodedChannelBytes(std::uint64_t width, std::uint64_t height, int x_sampling,
                                                 int y_sampling, std::uint64_t sample_bytes) {
    const auto sampled = [](std::uint64_t extent, int sampling) {
        return sampling > 0 ? (extent + std::uint64_t(sampling) - 1) / std::uint64_t(sampling) : extent;
    };
    const auto samples = checkedProduct(sampled(width, x_sampling), sampled(height, y_sampling));
    return samples ? checkedProduct(*samples, sample_bytes) : std::nullopt;
}

void requirePlausibleExr(const std::string& path) {
    const std::uint64_t channels = largestChannelListOf(path);
    if (channels > kMaxChannels)
        throw inputError(fmt::format("{}: channels: {} channels in one part, more than the {} decalcomp reads (a "
                                     "corrupt or hostile header)",
                                     path, channels, kMaxChannels));
    const CoreReader reader(path);
    int parts = 0;
    reader.require(exr_get_count(reader.context(), &parts), 0, "parts");
    std::uint64_t total = 0;
    for (int part = 0; part < parts; ++part) {
        const PartSize size = partSize(reader, part, path);
        total += size.bytes;
        requireWithinMemoryLimit(total, path, fmt::format("part {}: dataWindow {}x{}", part, size.width, size.height));
    }
    for (int part = 0; part < parts; ++part) requirePlausibleChunks(reader, part, path);
}

}  // namespace decalcomp::io
