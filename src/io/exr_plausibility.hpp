#pragma once
// Checks an EXR's header against its own file before any pixel memory is allocated.
#include <cstdint>
#include <optional>
#include <string>

namespace decalcomp::io {

// Throws Error(Input) naming the file, the part and the field when a part's data window,
// channels or chunk table cannot be real: a window that overflows, pixel data that would decode
// to more than the memory limit (memory_limit.hpp), or chunks that are missing, point outside
// the file or unpack to more than their codec can produce from their stored bytes (a header
// edited or corrupted to claim a bigger image than the file holds).
void requirePlausibleExr(const std::string& path);

// The bytes one channel of a width x height data window decodes to, with its x and y sampling
// (<= 0 counts as 1) and bytes per sample; nullopt when that overflows 64 bits. The core-API
// check above and the C++ reader's allocation check (exr_file.cpp) both size channels with it.
std::optional<std::uint64_t> decodedChannelBytes(std::uint64_t width, std::uint64_t height, int x_sampling,
                                                 int y_sampling, std::uint64_t sample_bytes);

}  // namespace decalcomp::io
