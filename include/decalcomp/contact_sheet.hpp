#pragma once
// A contact sheet of a sequence: one PNG with a thumbnail of every frame's composited albedo in
// frame order, left to right and top to bottom, so a person can scan a whole batch for a decal that
// slides, pops or is missing without opening each frame (docs/cli.md "batch --contact-sheet").
#include <map>
#include <string>
#include <vector>

#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// sRGB-encoded 8-bit RGB, rows top to bottom.
struct Thumbnail {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
};

// The frame's albedo (after compositing, when called after Frame::composite), filtered down so that
// its longer side is at most `long_side` pixels (never enlarged). Non-finite samples show black.
Thumbnail makeThumbnail(const GBuffer& gbuffer, int long_side);

// Collects thumbnails by their position in the sequence and writes the sheet. Positions without a
// thumbnail (frames skipped by --resume, or failed with --keep-going) are left as grey cells, so
// the grid keeps the sequence's order.
class ContactSheet {
public:
    explicit ContactSheet(int frames) : frames_(frames) {}
    void add(std::size_t position, Thumbnail thumbnail) { cells_[position] = std::move(thumbnail); }
    bool empty() const { return cells_.empty(); }
    // ceil(sqrt(frames)) columns, cells the size of the largest thumbnail with a 4-pixel gap.
    // Written to a temporary beside `path` and renamed into place; Error(Output) naming `path`.
    void write(const std::string& path) const;

private:
    int frames_ = 0;
    std::map<std::size_t, Thumbnail> cells_;
};

// Where a sharded batch's sheet goes: each shard writes its own, "sheet.png" -> "sheet.shard-2-of-8.png"
// (one shard: `path` itself).
std::string contactSheetPath(const std::string& path, int shard_index, int shard_count);

}  // namespace decalcomp
