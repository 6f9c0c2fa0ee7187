#pragma once
// Blast occlusion maps (docs/conventions.md "Blast occlusion"): where each occluding decal's map
// lies in one device buffer, and the kernel that fills them from the frame's points.
#include <vector>

#include "compositor/kernels.hpp"

#include "decalcomp/decal.hpp"
#include "decalcomp/device.hpp"
#include "shared_types.h"

namespace decalcomp {

struct OcclusionLayout {
    std::vector<int> occluders;  // indices of the decals with occlusion on
    std::size_t texels = 0;      // all maps together
};

// Sets each decal's occlusion_map/width/height/bias (-1 map for decals without occlusion).
OcclusionLayout layoutOcclusionMaps(const std::vector<Decal>& decals, std::vector<cl_types::DcDecal>& params);

// Fills the maps (+inf, then every valid pixel's distance per occluder) on the device and returns
// the buffer (one placeholder texel when no decal occludes). `event` times the build kernel.
cl::Buffer buildOcclusionMaps(cl::Context& context, cl::CommandQueue& queue, CompositorKernels& kernels,
                              const OcclusionLayout& layout, const cl::Buffer& frame, const cl::Buffer& depth,
                              const cl::Buffer& position, const cl::Buffer& decals, int width, int height,
                              cl::Event* event);

}  // namespace decalcomp
