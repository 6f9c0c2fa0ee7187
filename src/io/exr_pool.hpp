#pragma once
// The chunk codecs' threads (exr_zip_encode, exr_zip_decode). As many as OpenEXR's global pool has,
// so `--threads` and Imf::setGlobalThreadCount bound them too, but scheduled chunk by chunk with
// decoding first: in a batch the reader's decode otherwise queues behind every worker's encode,
// and the whole pipeline waits for the frame it reads (docs/decisions.md).
#include <cstddef>
#include <functional>

namespace decalcomp::io {

// What a call does: its priority (decoding first) and its CPU total (codecCpuSeconds, exr_file.hpp).
enum class PoolWork { Decode, Encode };

// Runs work(i) for every i in [0, count) and returns once every call has ended; the first
// exception a call threw is rethrown here (the other calls still run). The calling thread takes
// indices too, so it progresses however busy the pool is. The pool's threads take the next index
// of the oldest decode call, else of the oldest encode call.
void runOnExrPool(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work);

}  // namespace decalcomp::io
