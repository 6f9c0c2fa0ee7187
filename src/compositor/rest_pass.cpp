#include "compositor/rest_pass.hpp"

#include "compositor/device_buffers.hpp"
#include "compositor/surface_planes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <tuple>
#include <utility>

#include "decalcomp/error.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp {

RestMeshBuffers uploadRestMeshes(cl::Context& context, const std::vector<RestMesh>& meshes) {
    RestMeshBuffers out;
    if (meshes.empty()) return out;
    std::vector<cl_float4> vertices;
    std::vector<cl_int4> triangles;
    std::vector<cl_int> cells, cell_triangles;
    std::vector<cl_float4> uv_triangles;
    for (const RestMesh& mesh : meshes) {
        if (triangles.size() + mesh.triangles.size() >= (1u << 24))
            throw inputError(fmt::format("{}: more than 2^24 triangles in the scene's rest meshes", mesh.source));
        const int first_vertex = int(vertices.size() / 3), first_triangle = int(triangles.size());
        for (const RestVertex& v : mesh.vertices) {
            vertices.push_back({{v.position.x, v.position.y, v.position.z, v.uv.x}});
            vertices.push_back({{v.normal.x, v.normal.y, v.normal.z, v.uv.y}});
            vertices.push_back({{v.tangent.x, v.tangent.y, v.tangent.z, v.tangent.w}});
        }
        for (const glm::ivec3& t : mesh.triangles) {
            triangles.push_back({{t.x + first_vertex, t.y + first_vertex, t.z + first_vertex, 0}});
            // in float, as the kernel would compute them; 1 / det is 0 for a degenerate triangle
            const glm::vec2 a = mesh.vertices[std::size_t(t.x)].uv, e0 = mesh.vertices[std::size_t(t.y)].uv - a,
                            e1 = mesh.vertices[std::size_t(t.z)].uv - a;
            const float det = e0.x * e1.y - e0.y * e1.x;
            uv_triangles.push_back({{a.x, a.y, e0.x, e0.y}});
            uv_triangles.push_back({{e1.x, e1.y, std::abs(det) > 0.0f ? 1.0f / det : 0.0f, 0.0f}});
        }
        const UvGrid grid = mesh.grid.cell_start.size() >= 2 ? mesh.grid : buildUvGrid(mesh);
        cl_types::DcRestBinding g{};
        g.uv_origin[0] = grid.origin.x;
        g.uv_origin[1] = grid.origin.y;
        g.cells_per_uv[0] = grid.cells_per_uv.x;
        g.cells_per_uv[1] = grid.cells_per_uv.y;
        g.cells_x = grid.cells_x;
        g.cells_y = grid.cells_y;
        g.first_cell = int(cells.size());
        const int first_ref = int(cell_triangles.size());
        for (int start : grid.cell_start) cells.push_back(start + first_ref);
        for (int t : grid.triangles) cell_triangles.push_back(t + first_triangle);
        out.grids.push_back(g);
    }
    out.vertices = makeBuffer(context, vertices);
    out.triangles = makeBuffer(context, triangles);
    out.cells = makeBuffer(context, cells);
    out.cell_triangles = makeBuffer(context, cell_triangles);
    out.uv_triangles = makeBuffer(context, uv_triangles);
    return out;
}

RestBindings bindRestDecals(const std::vector<Decal>& decals, const RestMeshBuffers& meshes, bool uv_v_down,
                            std::vector<cl_types::DcDecal>& params) {
    RestBindings out;
    std::map<std::tuple<int, int, bool>, int> index;  // (mesh, mask, baked) -> binding
    for (std::size_t k = 0; k < decals.size(); ++k) {
        const Decal& decal = decals[k];
        params.at(k).rest_binding = -1;
        if (decal.space != DecalSpace::ObjectRest) continue;
        if (decal.rest_mesh < 0 || std::size_t(decal.rest_mesh) >= meshes.grids.size())
            throw inputError(fmt::format("decal '{}': rest mesh index {} out of range", decal.name, decal.rest_mesh));
        const auto key = std::make_tuple(decal.rest_mesh, decal.mask, decal.baked);
        auto [it, inserted] = index.emplace(key, int(out.bindings.size()));
        if (inserted) {
            cl_types::DcRestBinding b = meshes.grids[std::size_t(decal.rest_mesh)];
            b.mask = decal.mask;
            b.flip_v = uv_v_down ? 1 : 0;
            b.uv_only = decal.baked ? 1 : 0;  // bake mode reads UVs (kernels/rest_pose.h)
            out.bindings.push_back(b);
        }
        params[k].rest_binding = it->second;
        out.needs_frames |= !decal.baked && (decalAffects(decal, DecalTarget::Normal) || decal.angle_fade_deg[1] > 0.0);
    }
    return out;
}

void checkRestPassInputs(const RestBindings& rest, const GBuffer& frame) {
    if (rest.bindings.empty()) return;
    const auto uv = frame.planes.find(Attribute::UV);
    if (uv == frame.planes.end() || uv->second.components != 2 || uv->second.samples.size() != frame.pixelCount() * 2)
        throw inputError("texture-space decals need the frame's UV pass (u, v per pixel)");
}

std::vector<cl::Event> enqueueRestPass(cl::Context& context, cl::CommandQueue& queue, CompositorKernels& kernels,
                     const RestMeshBuffers& meshes, const RestBindings& rest, const GBuffer& frame,
                     const cl::Buffer& frame_params, const cl::Buffer& depth, const cl::Buffer& position,
                     const cl::Buffer& surface1, const cl::Buffer& masks, bool unified, RestPassBuffers& buffers) {
    const std::size_t pixels = frame.pixelCount(), count = rest.bindings.size();
    // Frames without texture-space decals bind placeholders: the shading kernel never reads them.
    const std::size_t planes = count > 0 ? pixels : 0;
    reserve(context, buffers.bindings, count * sizeof(cl_types::DcRestBinding));
    buffers.uv.reserve(context, queue, std::max<std::size_t>(planes, 1) * sizeof(cl_float2), unified);
    reserve(context, buffers.points, count * planes * sizeof(cl_float4));
    reserve(context, buffers.frames, count * planes * sizeof(cl_float4));
    std::vector<cl::Event> events;
    if (count == 0) return events;
    checkRestPassInputs(rest, frame);
    const auto uv = frame.planes.find(Attribute::UV);
    queue.enqueueWriteBuffer(buffers.bindings, CL_FALSE, 0, count * sizeof(cl_types::DcRestBinding),
                             rest.bindings.data());
    parallelCopy(static_cast<float*>(buffers.uv.beginUpload(queue)), uv->second.samples.data(), {0, 2 * pixels});
    buffers.uv.uploadRange(queue, 0, pixels * sizeof(cl_float2));
    buffers.uv.finishUpload(queue);
    // Tile-sized groups over the frame rounded up (the kernels skip pixels beyond it): PoCL's own
    // choice for a whole frame keeps too many work-items' variables on one thread's stack.
    const cl::NDRange range(roundUp(std::size_t(frame.width), DC_TILE_SIZE), roundUp(std::size_t(frame.height), DC_TILE_SIZE));
    const cl::NDRange group(DC_TILE_SIZE, DC_TILE_SIZE);
    for (std::size_t b = 0; b < count; ++b)
        events.push_back(kernels.rest_lookup(cl::EnqueueArgs(queue, range, group), frame_params, buffers.bindings, cl_int(b),
                                             buffers.uv.device(), masks, meshes.vertices, meshes.triangles, meshes.cells,
                                             meshes.cell_triangles, meshes.uv_triangles, buffers.points,
                                             buffers.frames));
    if (!rest.needs_frames) return events;
    for (std::size_t b = 0; b < count; ++b)
        if (!rest.bindings[b].uv_only)
            events.push_back(kernels.rest_frame(cl::EnqueueArgs(queue, range, group), frame_params, cl_int(b), depth,
                                                position, surface1, meshes.vertices, meshes.triangles, buffers.points,
                                                buffers.frames));
    return events;
}

}  // namespace decalcomp
