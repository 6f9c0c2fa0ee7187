#pragma once
// Work spread over OpenEXR's global thread pool, as OpenEXR's own readers and writers spread their
// chunks: the libdeflate codecs (exr_zip_encode, exr_zip_decode) share its threads, so
// `--threads` and Imf::setGlobalThreadCount bound them too.
#include <cstddef>
#include <functional>

namespace decalcomp::io {

// What a call does, for the CPU totals (codecCpuSeconds, exr_file.hpp).
enum class PoolWork { Decode, Encode };

// Runs work(i) for every i in [0, count) and returns once every call has ended; the first
// exception a call threw is rethrown here (the other calls still run). The calling thread takes
// indices too, so a caller whose pool tasks wait behind other callers' still progresses, and
// returns without waiting for tasks that found no index left.
void runOnExrPool(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work);

}  // namespace decalcomp::io
