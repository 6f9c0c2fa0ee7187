#include "transfers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <vector>

namespace decalcomp::bench {

namespace {

double medianSeconds(int repeat, const std::function<void()>& run) {
    run();  // warm-up
    std::vector<double> times;
    for (int i = 0; i < repeat; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        run();
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

double rate(double bytes, double seconds) { return seconds > 0 ? bytes / seconds * 1e-9 : 0.0; }

}  // namespace

TransferRates measureTransfers(ComputeDevice& device, std::size_t bytes, int repeat) {
    cl::Context& context = device.context();
    cl::CommandQueue& queue = device.queue();
    TransferRates r;
    cl::Buffer a(context, CL_MEM_READ_WRITE, bytes), b(context, CL_MEM_READ_WRITE, bytes);
    std::vector<unsigned char> pageable(bytes, 1);
    r.upload_pageable_gbs = rate(double(bytes), medianSeconds(repeat, [&] {
                                     queue.enqueueWriteBuffer(a, CL_TRUE, 0, bytes, pageable.data());
                                 }));
    r.download_pageable_gbs = rate(double(bytes), medianSeconds(repeat, [&] {
                                       queue.enqueueReadBuffer(a, CL_TRUE, 0, bytes, pageable.data());
                                   }));
    cl::Buffer pinned(context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, bytes);
    void* host = queue.enqueueMapBuffer(pinned, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, bytes);
    std::fill_n(static_cast<unsigned char*>(host), bytes, 1);
    r.upload_pinned_gbs = rate(double(bytes), medianSeconds(repeat, [&] {
                                   queue.enqueueWriteBuffer(a, CL_TRUE, 0, bytes, host);
                               }));
    r.download_pinned_gbs = rate(double(bytes), medianSeconds(repeat, [&] {
                                     queue.enqueueReadBuffer(a, CL_TRUE, 0, bytes, host);
                                 }));
    r.buffer_copy_gbs = rate(2.0 * double(bytes), medianSeconds(repeat, [&] {
                                 queue.enqueueCopyBuffer(a, b, 0, 0, bytes);
                                 queue.finish();
                             }));
    // Images: a square-ish RGBA float image of the same size.
    const std::size_t pixels = bytes / 16;
    const std::size_t width = std::max<std::size_t>(1, std::size_t(std::sqrt(double(pixels))));
    const std::size_t height = std::max<std::size_t>(1, pixels / width);
    const std::size_t image_bytes = width * height * 16;
    const cl::ImageFormat format(CL_RGBA, CL_FLOAT);
    cl::Image2D ia(context, CL_MEM_READ_WRITE, format, width, height), ib(context, CL_MEM_READ_WRITE, format, width, height);
    const std::array<cl::size_type, 3> origin{0, 0, 0}, region{width, height, 1};
    r.image_upload_gbs = rate(double(image_bytes), medianSeconds(repeat, [&] {
                                  queue.enqueueWriteImage(ia, CL_TRUE, origin, region, 0, 0, host);
                              }));
    r.image_copy_gbs = rate(2.0 * double(image_bytes), medianSeconds(repeat, [&] {
                                queue.enqueueCopyImage(ia, ib, origin, origin, region);
                                queue.finish();
                            }));
    queue.enqueueUnmapMemObject(pinned, host);
    queue.finish();
    return r;
}

}  // namespace decalcomp::bench
