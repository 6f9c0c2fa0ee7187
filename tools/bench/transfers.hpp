#pragma once
// The floors the compositor is judged against, measured on the device in the same run: host <->
// device copies of a frame's planes (pageable and pinned host memory), and the device's own copy
// rate, for buffers and for images (docs/benchmarks.md "Transfer floor").
#include <cstddef>

#include "decalcomp/device.hpp"

namespace decalcomp::bench {

struct TransferRates {
    double upload_pageable_gbs = 0, download_pageable_gbs = 0;  // host <-> device, GB/s
    double upload_pinned_gbs = 0, download_pinned_gbs = 0;
    double buffer_copy_gbs = 0;  // device buffer -> buffer, bytes read + written per second
    double image_copy_gbs = 0;   // device RGBA float image -> image, the same
    double image_upload_gbs = 0; // pinned host -> RGBA float image
};

// Medians over `repeat` copies of `bytes` (an RGBA float plane of bytes / 16 pixels for images).
TransferRates measureTransfers(ComputeDevice& device, std::size_t bytes, int repeat);

}  // namespace decalcomp::bench
