#include "compositor/occlusion_maps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

#include "decalcomp/error.hpp"

namespace decalcomp {

OcclusionLayout layoutOcclusionMaps(const std::vector<Decal>& decals, std::vector<cl_types::DcDecal>& params) {
    OcclusionLayout layout;
    for (std::size_t k = 0; k < decals.size(); ++k) {
        cl_types::DcDecal& d = params.at(k);
        d.occlusion_map = -1;
        const Decal& decal = decals[k];
        if (!decal.occlusion.enabled) continue;
        if (decal.kind != DecalKind::Frustum && decal.kind != DecalKind::Cube)
            throw inputError(fmt::format("decal '{}': only frustum and cube decals have blast occlusion", decal.name));
        const OcclusionMapSize size = occlusionMapSize(decal);
        if (layout.texels + size.texels() > std::size_t(INT32_MAX))
            throw inputError("blast occlusion: more than 2^31 map texels in total");
        d.occlusion_map = int(layout.texels);
        d.occlusion_width = size.width;
        d.occlusion_height = size.height;
        d.occlusion_bias = float(decal.occlusion.bias);
        layout.texels += size.texels();
        layout.occluders.push_back(int(k));
    }
    return layout;
}

cl::Buffer buildOcclusionMaps(cl::Context& context, cl::CommandQueue& queue, CompositorKernels& kernels,
                              const OcclusionLayout& layout, const cl::Buffer& frame, const cl::Buffer& depth,
                              const cl::Buffer& position, const cl::Buffer& decals, int width, int height,
                              cl::Event* event) {
    const std::size_t texels = std::max<std::size_t>(layout.texels, 1);
    cl::Buffer maps(context, CL_MEM_READ_WRITE, texels * sizeof(cl_uint));
    if (layout.occluders.empty()) return maps;
    const cl_uint infinity_bits = 0x7f800000u;  // +inf: no point seen in the texel yet
    queue.enqueueFillBuffer(maps, infinity_bits, 0, texels * sizeof(cl_uint));
    cl::Buffer occluders(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, layout.occluders.size() * sizeof(cl_int),
                         const_cast<int*>(layout.occluders.data()));
    *event = kernels.occlusion_build(cl::EnqueueArgs(queue, cl::NDRange(std::size_t(width), std::size_t(height))),
                                     frame, depth, position, decals, occluders, cl_int(layout.occluders.size()), maps);
    return maps;
}

}  // namespace decalcomp
