#include "compositor/staged_buffer.hpp"

#include <algorithm>

namespace decalcomp {

StagedBuffer::~StagedBuffer() {
    if (!view_) return;
    try {
        queue_.enqueueUnmapMemObject(unified_ ? device_ : host_, view_);
        queue_.finish();
    } catch (const cl::Error&) {
        // the context is going away with the buffers; nothing left to give back
    }
}

void StagedBuffer::reserve(cl::Context& context, cl::CommandQueue& queue, std::size_t bytes, bool unified) {
    bytes = std::max<std::size_t>(bytes, 16);  // OpenCL refuses empty buffers
    if (bytes <= capacity_ && unified == unified_) return;
    if (view_) queue.enqueueUnmapMemObject(unified_ ? device_ : host_, view_);
    view_ = nullptr;
    queue_ = queue;
    unified_ = unified;
    capacity_ = bytes;
    if (unified) {
        device_ = cl::Buffer(context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, bytes);
        host_ = cl::Buffer();
    } else {
        device_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
        host_ = cl::Buffer(context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, bytes);
        // Mapped once and kept: the pinned pages serve every frame's copies.
        view_ = queue.enqueueMapBuffer(host_, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, bytes);
    }
}

void* StagedBuffer::beginUpload(cl::CommandQueue& queue) {
    if (!unified_) return view_;
    view_ = queue.enqueueMapBuffer(device_, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, capacity_);
    return view_;
}

void StagedBuffer::uploadRange(cl::CommandQueue& queue, std::size_t offset, std::size_t bytes) {
    if (!unified_ && bytes > 0)
        queue.enqueueWriteBuffer(device_, CL_FALSE, offset, bytes, static_cast<char*>(view_) + offset);
}

void StagedBuffer::finishUpload(cl::CommandQueue& queue) {
    if (!unified_ || !view_) return;
    queue.enqueueUnmapMemObject(device_, view_);
    view_ = nullptr;
}

void StagedBuffer::enqueueDownload(cl::CommandQueue& queue, std::size_t offset, std::size_t bytes, cl::Event* done) {
    if (!unified_ && bytes > 0)
        queue.enqueueReadBuffer(device_, CL_FALSE, offset, bytes, static_cast<char*>(view_) + offset, nullptr, done);
}

const void* StagedBuffer::beginDownload(cl::CommandQueue& queue, std::size_t bytes) {
    if (!unified_) return view_;
    view_ = queue.enqueueMapBuffer(device_, CL_TRUE, CL_MAP_READ, 0, bytes);
    return view_;
}

void StagedBuffer::endDownload(cl::CommandQueue& queue) {
    if (!unified_ || !view_) return;
    queue.enqueueUnmapMemObject(device_, view_);
    view_ = nullptr;
}

}  // namespace decalcomp
