#pragma once
// Checks an EXR's header against its own file before any pixel memory is allocated.
#include <string>

namespace decalcomp::io {

// Throws Error(Input) naming the file, the part and the field when a part's data window,
// channels or chunk table cannot be real: a window that overflows, pixel data that would decode
// to more than the memory limit (memory_limit.hpp), or chunks that are missing, point outside
// the file or unpack to more than their codec can produce from their stored bytes (a header
// edited or corrupted to claim a bigger image than the file holds).
void requirePlausibleExr(const std::string& path);

}  // namespace decalcomp::io
