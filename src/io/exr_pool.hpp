#pragma once
// Work spread over OpenEXR's global thread pool, as OpenEXR's own readers and writers spread their
// chunks: the libdeflate codecs (exr_zip_encode, exr_zip_decode) share its threads, so
// `--threads` and Imf::setGlobalThreadCount bound them too.
#include <cstddef>
#include <functional>

namespace decalcomp::io {

// Runs work(i) for every i in [0, count) on the pool and returns once every call has ended; the
// first exception a call threw is rethrown here (the other calls still run).
void runOnExrPool(std::size_t count, const std::function<void(std::size_t)>& work);

}  // namespace decalcomp::io
