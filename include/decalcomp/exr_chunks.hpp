#pragma once
// An EXR part as OpenEXR stores it: a list of independently compressed chunks (blocks of 1, 16,
// 32 or 256 scanlines, or tiles). A frame decodes only the chunks decals can reach and re-encodes
// only the chunks they changed; every other chunk is copied from the input, compressed, byte for
// byte (docs/decisions.md, "Chunk rewrite").
#include <Imath/ImathBox.h>
#include <OpenEXR/ImfHeader.h>

#include <cstdint>
#include <string>
#include <vector>

namespace decalcomp {

// Where each chunk of a part's level 0 lies, in absolute pixel coordinates.
struct ChunkLayout {
    Imath::Box2i data_window;
    bool tiled = false;
    int lines_per_chunk = 1;                   // scanline parts
    int tile_width = 0, tile_height = 0;       // tiled parts
    int tiles_x = 0, tiles_y = 0;

    int count() const;
    // The chunk holding pixel (x, y), which must lie in the data window.
    int chunkAt(int x, int y) const;
    // A chunk's pixels, clipped to the data window.
    Imath::Box2i box(int chunk) const;
    // Tile coordinates of a chunk of a tiled part (chunk = ty * tiles_x + tx).
    int tileX(int chunk) const { return chunk % tiles_x; }
    int tileY(int chunk) const { return chunk / tiles_x; }
    // Appends the chunks that overlap `pixels` (absolute coordinates; may reach outside the window).
    void chunksIn(const Imath::Box2i& pixels, std::vector<std::uint8_t>& marks) const;
};

// The layout OpenEXR uses for a header: its tile description, or its compression's scanlines
// per chunk (NONE, RLE, ZIPS 1; ZIP, PXR24 16; PIZ, B44, B44A, DWAA 32; DWAB 256).
ChunkLayout chunkLayoutOf(const Imf::Header& header);

// What writing a file did with its chunks, for the run's summary and --stats.
struct ChunkWriteStats {
    std::size_t copied = 0;       // chunks copied compressed from the input, byte for byte
    std::size_t reencoded = 0;    // chunks decoded, changed and encoded again
    std::size_t pixels_reencoded = 0;  // pixels in the re-encoded chunks
    ChunkWriteStats& operator+=(const ChunkWriteStats& other) {
        copied += other.copied, reencoded += other.reencoded, pixels_reencoded += other.pixels_reencoded;
        return *this;
    }
};

// "60 copied, 8 re-encoded (15360 pixels)", for summaries.
std::string chunkSummary(const ChunkWriteStats& stats);

}  // namespace decalcomp
