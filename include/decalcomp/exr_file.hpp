#pragma once
// OpenEXR files kept whole: every part, header and channel, so a frame can be written back with
// the same layout, pixel types, compression and metadata, and only decal-affected channels change.
#include <OpenEXR/ImfHeader.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "decalcomp/exr_chunks.hpp"

namespace decalcomp {

enum class SampleType { Uint, Half, Float };

struct ExrChannel {
    std::string name;       // as stored in its part
    std::string qualified;  // name used for mapping: part name + "." + name in multi-part files
                            // when the name has no '.' of its own, else the name itself
    SampleType type = SampleType::Float;
    int x_sampling = 1, y_sampling = 1;
    std::vector<unsigned char> bytes;  // raw samples over the part's data window, rows top-down
};

struct ExrPart {
    Imf::Header header;  // kept as read: compression, windows, tiling, every attribute
    int width = 0, height = 0;  // data window size
    std::vector<ExrChannel> channels;
    ChunkLayout chunks;                   // where each stored chunk lies
    std::vector<std::uint8_t> changed;    // per chunk: some sample differs from the input's (markChanged)
    std::vector<std::uint8_t> decoded;    // per chunk: its samples were read; empty: every chunk was

    bool isDecoded(int chunk) const { return decoded.empty() || decoded[std::size_t(chunk)]; }
    bool isDecodedAt(int x, int y) const { return decoded.empty() || isDecoded(chunks.chunkAt(x, y)); }
    // Records that a sample at absolute pixel (x, y) now differs from the input.
    void markChanged(int x, int y) {
        changed.resize(std::size_t(chunks.count()), 0);
        changed[std::size_t(chunks.chunkAt(x, y))] = 1;
    }
    bool anyChanged() const;
};

// Which chunks to decode: nullopt reads every chunk; else, per file part, the pixel boxes
// (absolute coordinates) whose chunks are read. Chunks outside them keep zero samples, are marked
// not decoded and can only be written back as copies of the input's.
struct ExrReadRegion {
    bool everything = true;
    std::vector<Imath::Box2i> boxes;  // any part's chunks overlapping one of these are read
};

struct ExrImage {
    std::string path;
    std::vector<ExrPart> parts;
    // True when every sample change goes through ExrPart::markChanged (storeAttribute does) and the
    // headers are as read: a write then copies the unchanged chunks, compressed, from `path`.
    // readExr leaves it false (callers may edit bytes directly); Frame sets it, --add-channels
    // clears it (a new channel changes every chunk).
    bool copy_unchanged_chunks = false;
    // String attributes every part's header gets on write, replacing any of the same name (the
    // provenance, provenance.hpp). A file no chunk of which changed is still copied byte for byte.
    std::map<std::string, std::string> added_attributes;
};

// Reads scanline or tiled, single- or multi-part files. Deep parts are refused.
// Throws Error(Input) naming the file ("in.exr: not an OpenEXR file", "...: deep parts unsupported").
// `region` limits decoding to the chunks it covers (see ExrReadRegion).
ExrImage readExr(const std::string& path, const ExrReadRegion& region = {});
// Only the parts' headers (no pixels), with readExr's checks and errors.
std::vector<Imf::Header> readExrHeaders(const std::string& path);

// Writes all parts with their original headers to `path` through a temporary file in the same
// folder, renamed into place only when complete. Throws Error(Output) naming the file.
void writeExrAtomic(const ExrImage& image, const std::string& path);

// The two halves of writeExrAtomic, for several outputs that should appear together: writes the
// temporary beside `path` and returns its name (Error(Output) on failure, nothing left behind);
// commitExrTemporary renames it into place, discardExrTemporary removes it.
// With chunks_from_path, chunks nothing changed are copied compressed from the input: a file
// with no changed chunk is copied whole, byte for byte. `stats` (optional) counts the chunks.
std::string writeExrTemporary(const ExrImage& image, const std::string& path, ChunkWriteStats* stats = nullptr);
void commitExrTemporary(const std::string& temporary, const std::string& path);
void discardExrTemporary(const std::string& temporary) noexcept;

// CPU time the chunk codecs have taken in this process so far, summed over every thread that ran
// them (the codecs' pool and the callers): what `batch --timing` reports beside the stages' wall times.
struct CodecCpu {
    double decode_s = 0, encode_s = 0;
};
CodecCpu codecCpuSeconds();

}  // namespace decalcomp
