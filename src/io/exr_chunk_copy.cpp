// The chunk-copying EXR writer: untouched chunks go from input to output still compressed, so
// they cost no codec time and, with lossy codecs (B44, DWA), lose nothing a second time.
#include "io/exr_chunk_copy.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "decalcomp/error.hpp"
#include "io/exr_chunk_encode.hpp"
#include "io/exr_core.hpp"

namespace decalcomp::io {

namespace {

// One chunk's place as the core API names it (a scanline block's first line, or a tile), and
// its pixels.
struct ChunkSpot {
    bool tiled;
    int y, tile_x, tile_y;
    Imath::Box2i pixels;
};

ChunkSpot spotOf(const ChunkLayout& layout, int chunk) {
    const Imath::Box2i pixels = layout.box(chunk);
    if (layout.tiled) return {true, 0, layout.tileX(chunk), layout.tileY(chunk), pixels};
    return {false, pixels.min.y, 0, 0, pixels};
}

// Attribute or channel names past 31 bytes need the file's long-names flag, as the input had it.
bool hasLongNames(const CoreContext& in, int parts) {
    for (int p = 0; p < parts; ++p) {
        int32_t count = 0;
        in.require(exr_get_attribute_count(in.context(), p, &count), p, "attributes");
        for (int32_t a = 0; a < count; ++a) {
            const exr_attribute_t* attribute = nullptr;
            in.require(exr_get_attribute_by_index(in.context(), p, EXR_ATTR_LIST_FILE_ORDER, a, &attribute), p,
                       "attributes");
            if (attribute->name_length > 31) return true;
        }
        const exr_attr_chlist_t* channels = nullptr;
        in.require(exr_get_channels(in.context(), p, &channels), p, "channels");
        for (int c = 0; c < channels->num_channels; ++c)
            if (channels->entries[c].name.length > 31) return true;
    }
    return false;
}

void declareParts(const CoreContext& in, const CoreContext& out, int parts,
                  const std::map<std::string, std::string>& added_attributes) {
    if (hasLongNames(in, parts)) out.require(exr_set_longname_support(out.context(), 1), 0, "long names");
    for (int p = 0; p < parts; ++p) {
        const char* name = nullptr;
        if (exr_get_name(in.context(), p, &name) != EXR_ERR_SUCCESS) name = nullptr;  // single-part files may have none
        exr_storage_t storage{};
        in.require(exr_get_storage(in.context(), p, &storage), p, "type");
        int index = 0;
        out.require(exr_add_part(out.context(), name, storage, &index), p, "part");
        // Set first: copying fills in only the attributes not set yet, so these replace the input's.
        for (const auto& [attribute, value] : added_attributes)
            out.require(exr_attr_set_string(out.context(), index, attribute.c_str(), value.c_str()), p, attribute.c_str());
        out.require(exr_copy_unset_attributes(out.context(), index, in.context(), p), p, "attributes");
    }
    out.require(exr_write_header(out.context()), 0, "header");
}

void copyChunk(const CoreContext& in, const CoreContext& out, int part, const ChunkSpot& spot,
               std::vector<std::uint8_t>& packed) {
    exr_chunk_info_t info{};
    in.require(spot.tiled ? exr_read_tile_chunk_info(in.context(), part, spot.tile_x, spot.tile_y, 0, 0, &info)
                          : exr_read_scanline_chunk_info(in.context(), part, spot.y, &info),
               part, "chunk table");
    packed.resize(std::size_t(info.packed_size));
    in.require(exr_read_chunk(in.context(), part, &info, packed.data()), part, "chunk");
    out.require(spot.tiled ? exr_write_tile_chunk(out.context(), part, spot.tile_x, spot.tile_y, 0, 0, packed.data(),
                                                  info.packed_size)
                           : exr_write_scanline_chunk(out.context(), part, spot.y, packed.data(), info.packed_size),
                part, "chunk");
}

std::size_t pixelsIn(const Imath::Box2i& box) {
    return std::size_t(box.max.x - box.min.x + 1) * std::size_t(box.max.y - box.min.y + 1);
}

bool hasSubsampledChannel(const ExrPart& part) {
    for (const ExrChannel& channel : part.channels)
        if (channel.x_sampling != 1 || channel.y_sampling != 1) return true;
    return false;
}

void writePart(const CoreContext& in, const CoreContext& out, const ExrPart& part, int index,
               ChunkWriteStats& stats) {
    const ChunkLayout& layout = part.chunks;
    int32_t stored = 0;
    in.require(exr_get_chunk_count(in.context(), index, &stored), index, "chunkCount");
    if (stored != layout.count())
        throw outputError(fmt::format("{}: part {}: the input {} has {} chunks where {} were read; was it replaced "
                                      "while this ran?",
                                      out.path(), index, in.path(), stored, layout.count()));
    // A part with subsampled channels is encoded whole: a chunk's own window could break their
    // sampling alignment.
    const bool whole = hasSubsampledChannel(part) && part.anyChanged();
    const auto changed = [&](int chunk) {
        return whole || (std::size_t(chunk) < part.changed.size() && part.changed[std::size_t(chunk)]);
    };
    std::vector<std::uint8_t> packed;
    for (int chunk = 0; chunk < layout.count();) {
        const ChunkSpot spot = spotOf(layout, chunk);
        if (!changed(chunk)) {
            copyChunk(in, out, index, spot, packed);
            ++stats.copied;
            ++chunk;
            continue;
        }
        // A run of changed chunks (within one row of tiles) is encoded at once.
        int last = chunk;
        while (last + 1 < layout.count() && changed(last + 1) && (!layout.tiled || layout.tileY(last + 1) == spot.tile_y))
            ++last;
        for (int c = chunk; c <= last; ++c)
            if (!part.isDecoded(c))
                throw outputError(fmt::format("{}: part {}: chunk {} changed but was never read (internal error)",
                                              out.path(), index, c));
        const std::vector<std::string> encoded = encodeChunks(part, chunk, last, out.path());
        for (int c = chunk; c <= last; ++c) {
            const ChunkSpot at = spotOf(layout, c);
            const std::string& bytes = encoded[std::size_t(c - chunk)];
            out.require(at.tiled ? exr_write_tile_chunk(out.context(), index, at.tile_x, at.tile_y, 0, 0, bytes.data(),
                                                        bytes.size())
                                 : exr_write_scanline_chunk(out.context(), index, at.y, bytes.data(), bytes.size()),
                        index, "chunk");
            ++stats.reencoded;
            stats.pixels_reencoded += pixelsIn(at.pixels);
        }
        chunk = last + 1;
    }
}

}  // namespace

ChunkWriteStats writeCopyingUnchangedChunks(const ExrImage& image, const std::string& target, const std::string& name) {
    const CoreContext in(image.path, CoreContext::Mode::Read);
    CoreContext out(target, CoreContext::Mode::Write, name);
    int parts = 0;
    in.require(exr_get_count(in.context(), &parts), 0, "parts");
    if (parts != int(image.parts.size()))
        throw outputError(
            fmt::format("{}: the input {} has {} parts where {} were read; was it replaced while this "
                        "ran?",
                        name, image.path, parts, image.parts.size()));
    declareParts(in, out, parts, image.added_attributes);
    ChunkWriteStats stats;
    for (int p = 0; p < parts; ++p) writePart(in, out, image.parts[std::size_t(p)], p, stats);
    out.finish();
    return stats;
}

}  // namespace decalcomp::io
