#pragma once
// The rest pass of texture-space decals (docs/texture-space.md, kernels/rest_pose.cl): the scene's
// rest meshes and their UV grids on the device (uploaded once per scene), and per frame one
// binding per distinct (mesh, object mask) pair, whose rest points and rotations the kernels fill.
#include <CL/opencl.hpp>

#include <vector>

#include "compositor/kernels.hpp"
#include "compositor/staged_buffer.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"
#include "shared_types.h"

namespace decalcomp {

// Every rest mesh of a scene in one set of buffers, indices made absolute.
struct RestMeshBuffers {
    std::vector<cl_types::DcRestBinding> grids;  // per mesh: its grid (mask and flip left to the binding)
    cl::Buffer vertices, triangles, cells, cell_triangles;
    // per triangle two float4: (uv0, uv1 - uv0), (uv2 - uv0, 1 / det, 0), for the lookup's barycentrics
    cl::Buffer uv_triangles;
    bool empty() const { return grids.empty(); }
};
// Builds each mesh's UV grid and uploads everything. Throws Error(Input) beyond 2^24 triangles.
RestMeshBuffers uploadRestMeshes(cl::Context& context, const std::vector<RestMesh>& meshes);

struct RestBindings {
    std::vector<cl_types::DcRestBinding> bindings;
    bool needs_frames = false;  // some texture-space decal turns normals (normal maps, angle fades)
};
// Sets each decal's rest_binding (-1 for world decals) and lists the bindings. `uv_v_down`: the
// frame's UV pass counts v from the top.
RestBindings bindRestDecals(const std::vector<Decal>& decals, const RestMeshBuffers& meshes, bool uv_v_down,
                            std::vector<cl_types::DcDecal>& params);

// Throws Error(Input) when texture-space decals meet a frame without a (u, v) UV pass. The
// compositor checks before it enqueues anything, so a refused frame leaves no transfer in flight.
void checkRestPassInputs(const RestBindings& rest, const GBuffer& frame);

// Device memory of one frame's rest pass, grown on demand.
struct RestPassBuffers {
    cl::Buffer bindings, points, frames;
    StagedBuffer uv;  // the UV pass, through pinned memory on a GPU (mapped on PoCL)
};
// Enqueues the rest pass (after the frame's planes and masks are on their way): uploads the UV
// plane, then per binding the lookup and, when needed, the rotations. Returns the kernels' events.
std::vector<cl::Event> enqueueRestPass(cl::Context& context, cl::CommandQueue& queue, CompositorKernels& kernels,
                     const RestMeshBuffers& meshes, const RestBindings& rest, const GBuffer& frame,
                     const cl::Buffer& frame_params, const cl::Buffer& depth, const cl::Buffer& position,
                     const cl::Buffer& surface1, const cl::Buffer& masks, bool unified, RestPassBuffers& buffers);

}  // namespace decalcomp
