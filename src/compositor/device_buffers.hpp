#pragma once
// Small device-buffer helpers shared by the compositor's passes.
#include <CL/opencl.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace decalcomp {

inline std::size_t roundUp(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

// A device buffer of at least `bytes` (16 at least: OpenCL refuses empty ones), grown (never
// shrunk) as frames need.
inline void reserve(cl::Context& context, cl::Buffer& buffer, std::size_t bytes) {
    bytes = std::max<std::size_t>(bytes, 16);
    if (buffer() && buffer.getInfo<CL_MEM_SIZE>() >= bytes) return;
    buffer = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
}

// A read-only buffer holding `data` (one placeholder element when it is empty).
template <typename T>
cl::Buffer makeBuffer(cl::Context& context, const std::vector<T>& data) {
    if (data.empty()) return cl::Buffer(context, CL_MEM_READ_ONLY, sizeof(T));
    return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T),
                      const_cast<T*>(data.data()));
}

}  // namespace decalcomp
