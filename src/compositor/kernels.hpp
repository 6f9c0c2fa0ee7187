#pragma once
// Typed launches of the compositor's kernels: each functor's argument list is the kernel's
// signature (kernels/*.cl), so a call with a missing or misplaced argument does not compile.
#include <CL/opencl.hpp>
#include <array>
#include <map>

#include "decalcomp/device.hpp"

namespace decalcomp {

using cl::Buffer;

struct CompositorKernels {
    // Every kernel of `program` (ComputeDevice::program); the shading kernels of filtered and
    // texture-space frames come later, from their own programs.
    explicit CompositorKernels(const cl::Program& program);

    // frame, depth plane, position plane, tile depth ranges: a work-group per tile (GPUs), or a
    // work-item per tile (CPUs, where barriers are slow)
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer> tile_bounds, tile_bounds_serial;
    // frame, decals, decal bounds
    cl::KernelFunctor<Buffer, Buffer, Buffer> decal_bounds;
    // frame, tile depth, coarse depth
    cl::KernelFunctor<Buffer, Buffer, Buffer> coarse_depth;
    // frame, decal bounds, coarse depth, masks
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer> coarse_mark;
    // frame, masks, chunk starts, coarse counts: a work-group or a work-item per coarse tile
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer> coarse_count, coarse_count_serial;
    // frame, masks, chunk starts, coarse offsets, coarse lists, coarse capacity
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer, Buffer, cl_int> coarse_fill;
    // frame, decals, decal bounds, tile depth, coarse offsets, coarse lists, coarse capacity, listed
    // flags, tile counts: a work-group or a work-item per tile
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, cl_int, Buffer, Buffer> bin_count,
        bin_count_serial;
    // frame, coarse offsets, coarse lists, coarse capacity, listed flags, tile offsets, tile lists,
    // list capacity
    cl::KernelFunctor<Buffer, Buffer, Buffer, cl_int, Buffer, Buffer, Buffer, cl_int> bin_fill;
    // counts, n, offsets (n + 1)
    cl::KernelFunctor<Buffer, cl_int, Buffer> scan;
    // frame, depth plane, position plane, decals, occluder indices, occluder count, maps
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer, Buffer, cl_int, Buffer> occlusion_build;
    // frame, bindings, binding, uv plane, mask weights, vertices, triangles, cells, cell triangles,
    // uv triangles, rest points, rest frames (kernels/rest_pose.cl)
    cl::KernelFunctor<Buffer, Buffer, cl_int, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer>
        rest_lookup;
    // frame, binding, depth, position, surface group 1, vertices, triangles, rest points, rest frames
    cl::KernelFunctor<Buffer, cl_int, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer> rest_frame;
    // frame, depth plane, position plane, clean depths (filtered frames, kernels/clean_depth.h)
    cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer> clean_depths;
    // frame, depth, position, surface groups 0-2 (in place), groups 0-1 as uploaded and clean depths
    // (filtered frames), decals, texture table, texels,
    // tile offsets, tile lists, decal bounds, binned, list capacity, mask weights, occlusion maps,
    // beauty, light, rest points, rest frames
    using Shade = cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer,
                                    Buffer, Buffer, Buffer, Buffer, Buffer, cl_int, cl_int, Buffer, Buffer, Buffer,
                                    Buffer, Buffer, Buffer>;
    // The shading kernel of a variant (DC_VARIANT_ALBEDO_ONLY | DC_VARIANT_FLAT | DC_VARIANT_POINT
    // bits): with DC_VARIANT_POINT, the point program's; without, `dc_shade` of
    // device.shadingProgram(variant, paths), built and taken the first time it is asked for.
    Shade& shading(int variant, const ShadingPaths& paths, ComputeDevice& device);

private:
    std::array<Shade, 4> point_shade_;  // by the variant's other bits
    std::map<int, Shade> shade_;        // by ShadingPaths::key
};

}  // namespace decalcomp
