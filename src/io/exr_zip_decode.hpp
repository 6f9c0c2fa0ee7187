#pragma once
// ZIP and ZIPS chunks of scanline parts, inflated by libdeflate (internal).
#include <string>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

// Whether decodeZipChunks can read `part` (its header, channels and layout set, its samples
// allocated): a scanline part compressed with ZIP or ZIPS whose channels are all full resolution.
bool canDecodeZip(const ExrPart& part);

// Reads the chunks of file part `index` of `path` that `part.isDecoded` names into the channels'
// samples: each chunk's stored bytes through OpenEXR's core API (which checked the chunk table),
// inflated by libdeflate, the predictor undone and the rows put back in their channels; a chunk no
// smaller than its samples is taken as stored raw, as OpenEXR takes it. OpenEXR 3.1 inflates with
// zlib and then copies every sample on its own; this takes about a quarter of its time
// (docs/benchmarks.md, stop 45). The chunks are decoded in parallel on OpenEXR's global thread pool.
// Throws Error(Input) "PATH: part P: chunk at line Y: ..." for a chunk that does not decode to
// exactly its samples.
void decodeZipChunks(const std::string& path, int index, ExrPart& part);

}  // namespace decalcomp::io
