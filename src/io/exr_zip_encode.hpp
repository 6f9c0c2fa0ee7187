#pragma once
// ZIP and ZIPS chunks of scanline parts, deflated by libdeflate (internal).
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

// Whether encodeZipChunks can encode `part`: a scanline part compressed with ZIP or ZIPS whose
// channels are all full-resolution and all held in `part.channels`.
bool canEncodeZip(const ExrPart& part);

// The stored bytes of chunks [first, last] of such a part, as OpenEXR's C++ writer stores them:
// each chunk's rows (per line, each channel's samples in the header's channel order), its bytes
// split into even and odd halves and stored as differences to the byte before, then deflated with
// a zlib header; a chunk that would not shrink is stored raw. libdeflate deflates at about twice
// zlib's speed to the same size (docs/benchmarks.md, stop 44). The chunks are compressed in
// parallel on OpenEXR's global thread pool, as its own writer does. Throws Error(Output) naming
// `path`.
std::vector<std::string> encodeZipChunks(const ExrPart& part, int first, int last, const std::string& path);

}  // namespace decalcomp::io
