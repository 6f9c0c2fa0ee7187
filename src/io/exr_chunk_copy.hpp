#pragma once
// Writing an ExrImage whose unchanged chunks are copied from its input file (internal).
#include <string>

#include "decalcomp/exr_chunks.hpp"
#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

// Writes `image` to `target` through OpenEXR's core API: each part's header attributes as the
// input file (image.path) has them, each chunk nobody changed copied compressed from the input,
// each changed chunk encoded from the image's samples with the part's own compression
// (exr_chunk_encode.hpp). Throws
// Error(Output) naming `name`, what `target` will become (Error(Input) naming the input when it
// cannot be read again).
ChunkWriteStats writeCopyingUnchangedChunks(const ExrImage& image, const std::string& target, const std::string& name);

}  // namespace decalcomp::io
