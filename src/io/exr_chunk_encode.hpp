#pragma once
// Encoding changed chunks (internal).
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

// The stored bytes of chunks [first, last] of `part`, encoded from its samples. ZIP and ZIPS
// scanline parts go through libdeflate (exr_zip_encode.hpp: the same layout, deflated twice as
// fast); every other part through OpenEXR's C++ writer into memory: its thread pool compresses them
// in parallel, it has every codec (3.1's core API cannot encode DWAA/DWAB), and each chunk comes
// out exactly as the whole-file writer would store it. Tiled parts: the chunks must lie in one row
// of tiles. Throws Error(Output) naming `path`.
std::vector<std::string> encodeChunks(const ExrPart& part, int first, int last, const std::string& path);

}  // namespace decalcomp::io
