#pragma once
// A device buffer with a host view for filling and reading it, kept across frames of one size.
// On a discrete device (a GPU) the view is pinned host memory and the data moves by DMA; on a
// device that shares host memory (PoCL's CPU device) the view is the buffer itself, mapped, and
// nothing is copied.
#include <CL/opencl.hpp>

#include <cstddef>

namespace decalcomp {

class StagedBuffer {
public:
    StagedBuffer() = default;
    ~StagedBuffer();  // gives the mapping back
    StagedBuffer(const StagedBuffer&) = delete;
    StagedBuffer& operator=(const StagedBuffer&) = delete;

    // Grows to at least `bytes` (never shrinks); contents are undefined after a growth.
    void reserve(cl::Context& context, cl::CommandQueue& queue, std::size_t bytes, bool unified);

    // The host view to fill. uploadRange() sends a filled range to the device without waiting
    // (discrete devices: the DMA of one range runs while the next is filled; the view must stay
    // untouched until the queue has passed the copy); finishUpload() ends the filling.
    void* beginUpload(cl::CommandQueue& queue);
    void uploadRange(cl::CommandQueue& queue, std::size_t offset, std::size_t bytes);
    void finishUpload(cl::CommandQueue& queue);
    // Enqueues the device-to-host copy of a range without waiting (discrete devices; `done` is
    // set to its event); the view holds it once the event completed.
    void enqueueDownload(cl::CommandQueue& queue, std::size_t offset, std::size_t bytes, cl::Event* done);
    bool unified() const { return unified_; }
    // The downloaded view, after the queue finished (maps the buffer on unified devices);
    // endDownload() gives it back to the device.
    const void* beginDownload(cl::CommandQueue& queue, std::size_t bytes);
    void endDownload(cl::CommandQueue& queue);

    cl::Buffer& device() { return device_; }
    std::size_t capacity() const { return capacity_; }

private:
    cl::Buffer device_, host_;
    cl::CommandQueue queue_;      // the queue that mapped view_
    void* view_ = nullptr;        // pinned host memory (discrete) or the current mapping (unified)
    std::size_t capacity_ = 0;
    bool unified_ = false;
};

}  // namespace decalcomp
