// Chunk layouts of EXR parts, from their headers.
#include "decalcomp/exr_chunks.hpp"

#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfTileDescription.h>
#include <fmt/format.h>

#include <algorithm>

namespace decalcomp {

namespace {

// OpenEXR's scanlines per chunk for each compression (ImfCompression.h documents the blocks).
int linesPerChunk(Imf::Compression compression) {
    switch (compression) {
        case Imf::ZIP_COMPRESSION:
        case Imf::PXR24_COMPRESSION: return 16;
        case Imf::PIZ_COMPRESSION:
        case Imf::B44_COMPRESSION:
        case Imf::B44A_COMPRESSION:
        case Imf::DWAA_COMPRESSION: return 32;
        case Imf::DWAB_COMPRESSION: return 256;
        default: return 1;  // NONE, RLE, ZIPS
    }
}

int ceilDiv(long long a, long long b) { return int((a + b - 1) / b); }

}  // namespace

int ChunkLayout::count() const {
    if (tiled) return tiles_x * tiles_y;
    return ceilDiv((long long)data_window.max.y - data_window.min.y + 1, lines_per_chunk);
}

int ChunkLayout::chunkAt(int x, int y) const {
    if (!tiled) return (y - data_window.min.y) / lines_per_chunk;
    return ((y - data_window.min.y) / tile_height) * tiles_x + (x - data_window.min.x) / tile_width;
}

Imath::Box2i ChunkLayout::box(int chunk) const {
    Imath::Box2i b = data_window;
    if (!tiled) {
        b.min.y = data_window.min.y + chunk * lines_per_chunk;
        b.max.y = std::min(data_window.max.y, b.min.y + lines_per_chunk - 1);
        return b;
    }
    b.min.x = data_window.min.x + tileX(chunk) * tile_width;
    b.min.y = data_window.min.y + tileY(chunk) * tile_height;
    b.max.x = std::min(data_window.max.x, b.min.x + tile_width - 1);
    b.max.y = std::min(data_window.max.y, b.min.y + tile_height - 1);
    return b;
}

void ChunkLayout::chunksIn(const Imath::Box2i& pixels, std::vector<std::uint8_t>& marks) const {
    marks.resize(std::size_t(count()), 0);
    const int x0 = std::max(pixels.min.x, data_window.min.x), x1 = std::min(pixels.max.x, data_window.max.x);
    const int y0 = std::max(pixels.min.y, data_window.min.y), y1 = std::min(pixels.max.y, data_window.max.y);
    if (x0 > x1 || y0 > y1) return;
    const int step_y = tiled ? tile_height : lines_per_chunk;
    const int step_x = tiled ? tile_width : (x1 - x0 + 1);
    // Corners of every chunk row and column the box crosses, plus its last row and column.
    for (int y = y0;; y = std::min(y1, y + step_y)) {
        for (int x = x0;; x = std::min(x1, x + step_x)) {
            marks[std::size_t(chunkAt(x, y))] = 1;
            if (x == x1) break;
        }
        if (y == y1) break;
    }
}

ChunkLayout chunkLayoutOf(const Imf::Header& header) {
    ChunkLayout layout;
    layout.data_window = header.dataWindow();
    layout.lines_per_chunk = linesPerChunk(header.compression());
    if (header.hasTileDescription()) {
        const Imf::TileDescription tiles = header.tileDescription();
        layout.tiled = true;
        layout.tile_width = int(tiles.xSize);
        layout.tile_height = int(tiles.ySize);
        layout.tiles_x = ceilDiv((long long)layout.data_window.max.x - layout.data_window.min.x + 1, layout.tile_width);
        layout.tiles_y = ceilDiv((long long)layout.data_window.max.y - layout.data_window.min.y + 1, layout.tile_height);
    }
    return layout;
}

std::string chunkSummary(const ChunkWriteStats& stats) {
    return fmt::format("{} copied, {} re-encoded ({} pixels)", stats.copied, stats.reencoded, stats.pixels_reencoded);
}

}  // namespace decalcomp
