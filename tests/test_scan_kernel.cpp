// The device's prefix sum (kernels/scan.cl) that turns the binning's per-tile counts into list
// offsets, against std::exclusive_scan at lengths around its work-group size and beyond.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "compositor/kernels.hpp"
#include "shared_types.h"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

std::vector<cl_int> deviceScan(ComputeDevice& device, const std::vector<cl_int>& counts) {
    cl::Context& context = device.context();
    cl::CommandQueue& queue = device.queue();
    const std::size_t n = counts.size();
    cl::Buffer in(context, CL_MEM_READ_ONLY, std::max<std::size_t>(n, 1) * sizeof(cl_int));
    cl::Buffer out(context, CL_MEM_WRITE_ONLY, (n + 1) * sizeof(cl_int));
    if (n > 0) queue.enqueueWriteBuffer(in, CL_TRUE, 0, n * sizeof(cl_int), counts.data());
    CompositorKernels kernels(device.program());
    const cl::NDRange group(DC_SCAN_GROUP);
    kernels.scan(cl::EnqueueArgs(queue, group, group), in, cl_int(n), out);
    std::vector<cl_int> offsets(n + 1, -1);
    queue.enqueueReadBuffer(out, CL_TRUE, 0, (n + 1) * sizeof(cl_int), offsets.data());
    return offsets;
}

TEST(ScanKernel, EqualsExclusiveScanWithTheTotalAppended) {
    ComputeDevice& device = test::cpuDevice();
    std::mt19937 random(42);
    // lengths around the work-group size and its multiples; a 1080p and a 4K frame's tile counts
    for (const std::size_t n :
         {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(DC_SCAN_GROUP - 1), std::size_t(DC_SCAN_GROUP),
          std::size_t(DC_SCAN_GROUP + 1), std::size_t(2047), std::size_t(2048), std::size_t(2049), std::size_t(4097),
          std::size_t(8160), std::size_t(32400), std::size_t(100003)}) {
        std::vector<cl_int> counts(n);
        std::uniform_int_distribution<int> count(0, 40);
        for (cl_int& c : counts) c = random() % 3 == 0 ? 0 : count(random);  // many empty tiles
        std::vector<cl_int> expected(n + 1);
        std::exclusive_scan(counts.begin(), counts.end(), expected.begin(), cl_int(0));
        expected[n] = std::accumulate(counts.begin(), counts.end(), cl_int(0));
        EXPECT_EQ(deviceScan(device, counts), expected) << n << " counts";
    }
}

}  // namespace
}  // namespace decalcomp
