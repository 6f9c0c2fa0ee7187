// The UV-space bake of a texture-space decal on the device (kernels/bake.cl, bake.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "compositor/device_buffers.hpp"
#include "compositor/kernel_params.hpp"
#include "compositor/rest_pass.hpp"
#include "decalcomp/bake.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

constexpr int kMaxBakeResolution = 16384;  // 2^28 texels per layer, 4 GiB of float4

using BakeKernel = cl::KernelFunctor<Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer, Buffer,
                                     Buffer, Buffer>;

Texture2D layerTexture(std::vector<glm::vec4> texels, int width, int height, const std::string& source) {
    Texture2D t;
    t.source = source;
    t.width = width;
    t.height = height;
    t.texels = std::move(texels);
    return t;
}

}  // namespace

BakedLayers bakeDecal(ComputeDevice& device, const DecalScene& scene, const Decal& decal) {
    if (decal.space != DecalSpace::ObjectRest || decal.rest_mesh < 0 || std::size_t(decal.rest_mesh) >= scene.meshes.size())
        throw inputError(fmt::format("decal '{}': only texture-space decals with a rest mesh can be baked", decal.name));
    if (decalAffects(decal, DecalTarget::Normal))
        throw inputError(fmt::format("decal '{}': bake mode does not carry normal maps; use \"mode\": \"exact\"",
                                     decal.name));
    const int size = decal.bake_resolution;
    if (size < 1 || size > kMaxBakeResolution)
        throw inputError(fmt::format("decal '{}': bake resolution {} is outside 1..{}", decal.name, size,
                                     kMaxBakeResolution));
    const RestMesh& mesh = scene.meshes[std::size_t(decal.rest_mesh)];
    const std::string source = fmt::format("{} (bake of decal '{}')", mesh.source, decal.name);
    BakedLayers out;
    out.width = out.height = size;
    const std::size_t texels = std::size_t(size) * std::size_t(size);
    try {
        cl::Context& context = device.context();
        // its own queue (the layers are read back here); profiled like the device's, for bake_kernel_ms
        cl::CommandQueue queue(context, device.info().device,
                               device.profiling() ? cl::QueueProperties::Profiling : cl::QueueProperties::None);
        const RestMeshBuffers meshes = uploadRestMeshes(context, {mesh, uvApron(mesh)});
        const PackedTextures packed = packTextures(scene.textures);
        DecalScene one;
        one.decals = {decal};
        const std::vector<cl_types::DcDecal> params = makeDecalParams(one, Camera{}, packed.first_entry);
        cl_types::DcBakeLayer layer{};
        layer.width = layer.height = size;
        layer.dilation = std::max(decal.bake_dilation, 0);
        const cl::Buffer layer_buffer = makeBuffer(context, std::vector<cl_types::DcBakeLayer>{layer});
        const cl::Buffer decal_buffer = makeBuffer(context, params);
        const cl::Buffer table = makeBuffer(context, packed.table), texel_buffer = makeBuffer(context, packed.texels);
        const cl::Buffer grids = makeBuffer(context, meshes.grids);
        std::array<cl::Buffer, 3> layers;
        for (cl::Buffer& b : layers) b = cl::Buffer(context, CL_MEM_WRITE_ONLY, texels * sizeof(cl_float4));
        BakeKernel kernel(device.program(), "dc_bake_layer");
        // 16 x 16 groups over the layer rounded up (the kernel skips texels beyond it)
        const cl::NDRange range(roundUp(std::size_t(size), 16), roundUp(std::size_t(size), 16)), group(16, 16);
        const cl::Event baked = kernel(cl::EnqueueArgs(queue, range, group), layer_buffer, decal_buffer, table,
                                       texel_buffer, grids, meshes.vertices, meshes.triangles, meshes.cells,
                                       meshes.cell_triangles, layers[0], layers[1], layers[2]);
        std::array<std::vector<glm::vec4>, 3> host;
        for (int k = 0; k < 3; ++k) {
            host[std::size_t(k)].resize(texels);
            queue.enqueueReadBuffer(layers[std::size_t(k)], CL_FALSE, 0, texels * sizeof(cl_float4),
                                    host[std::size_t(k)].data());
        }
        queue.finish();
        if (device.profiling())
            out.bake_kernel_ms = double(baked.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                        baked.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6;
        out.albedo = layerTexture(std::move(host[0]), size, size, source);
        if (decalAffects(decal, DecalTarget::Roughness) || decalAffects(decal, DecalTarget::Metallic) ||
            decalAffects(decal, DecalTarget::AmbientOcclusion))
            out.orm = layerTexture(std::move(host[1]), size, size, source);
        if (decalAffects(decal, DecalTarget::Emission))
            out.emission = layerTexture(std::move(host[2]), size, size, source);
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: baking decal '{}': {}: {}", device.info().name, decal.name, e.what(),
                                      clErrorName(e.err())));
    }
    return out;
}

}  // namespace decalcomp
