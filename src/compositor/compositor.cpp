#include "decalcomp/compositor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <numeric>

#include "compositor/kernel_params.hpp"
#include "compositor/occlusion_maps.hpp"
#include "compositor/surface_planes.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

constexpr int kBinGroupSize = 64;  // work-items per group in the binning kernels
constexpr int kCoarse = 4;         // DC_COARSE in kernels/binning.cl: tiles per coarse tile side

std::size_t roundUp(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

double eventMs(const cl::Event& e) {
    const auto start = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return double(end - start) * 1e-6;
}

// Exclusive prefix sum of `n` device counts, with the total appended. Done on the host: the
// total sizes the list buffer, so lists have no cap and never drop a decal.
std::vector<int> prefixSum(cl::CommandQueue& queue, const cl::Buffer& counts, std::size_t n) {
    std::vector<int> values(n, 0);
    queue.enqueueReadBuffer(counts, CL_TRUE, 0, n * sizeof(int), values.data());
    std::vector<int> offsets(n + 1, 0);
    std::int64_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        offsets[i] = int(total);
        total += values[i];
        if (total > INT32_MAX) throw deviceError("binning: more than 2^31 tile-decal pairs");
    }
    offsets[n] = int(total);
    return offsets;
}

// A buffer of at least one element: OpenCL refuses zero-sized buffers.
template <typename T>
cl::Buffer makeBuffer(cl::Context& context, cl_mem_flags flags, const std::vector<T>& data) {
    if (data.empty()) return cl::Buffer(context, flags, sizeof(T));
    return cl::Buffer(context, flags | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T), const_cast<T*>(data.data()));
}

// Pads a plane to the 1 or 4 channels an OpenCL image can hold.
std::vector<float> imagePixels(const Plane& plane, std::size_t pixels, int channels) {
    std::vector<float> out(pixels * channels, 0.0f);
    const int copy = std::min(channels, plane.components);
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < copy; ++c) out[i * channels + c] = plane.at(i, c);
    return out;
}

cl::Image2D makeImage(cl::Context& context, int width, int height, int channels, const std::vector<float>& pixels) {
    const cl::ImageFormat format(channels == 1 ? CL_R : CL_RGBA, CL_FLOAT);
    return cl::Image2D(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, format, std::size_t(width),
                       std::size_t(height), 0, const_cast<float*>(pixels.data()));
}

cl::Image2D placeholderImage(cl::Context& context, int channels) {
    return makeImage(context, 1, 1, channels, std::vector<float>(std::size_t(channels), 0.0f));
}

// All mask weight planes back to back, one float per pixel each.
std::vector<float> packMaskWeights(const GBuffer& frame, std::size_t count) {
    std::vector<float> out;
    out.reserve(count * frame.pixelCount());
    for (const Plane& plane : frame.mask_weights) {
        if (plane.components != 1 || plane.samples.size() != frame.pixelCount())
            throw inputError("decal masks: a weight plane does not match the frame size");
        out.insert(out.end(), plane.samples.begin(), plane.samples.end());
    }
    return out;
}

}  // namespace

std::vector<Attribute> compositedAttributes(const DecalScene& scene) {
    std::vector<Attribute> out = {Attribute::Albedo};
    const std::array<bool, kDecalTargets> targets = sceneTargets(scene);
    for (int t = 0; t < kDecalTargets; ++t)
        if (targets[std::size_t(t)] && DecalTarget(t) != DecalTarget::Albedo)
            out.push_back(targetAttribute(DecalTarget(t)));
    return out;
}

struct Compositor::State {
    cl::Kernel tile_bounds, decal_bounds, coarse_depth, coarse_mask, coarse_count, coarse_fill, bin_count, bin_fill,
        occlusion;
    // shading kernels by variant bits (DC_VARIANT_ALBEDO_ONLY | DC_VARIANT_FLAT)
    std::array<cl::Kernel, 4> shade;
    cl::Buffer texture_table, texels;
    std::size_t mask_count = 0;
    std::vector<int> texture_entries;           // scene texture index -> texture table entry
    std::array<bool, kDecalTargets> targets{};  // what the scene's decals change
    DecalScene scene;                           // decals only; textures live on the device
    // last frame's binning, kept for lastBinning()
    cl::Buffer tile_depth, tile_offsets, tile_decals;
    int tiles_x = 0, tiles_y = 0;
    std::int64_t bin_entries = 0;
    bool has_binning = false;
};

Compositor::Compositor(ComputeDevice& device) : device_(device), state_(std::make_unique<State>()) {
    cl::Program& program = device_.program();
    try {
        state_->tile_bounds = cl::Kernel(program, "dc_tile_bounds");
        state_->decal_bounds = cl::Kernel(program, "dc_decal_bounds");
        state_->coarse_depth = cl::Kernel(program, "dc_coarse_depth");
        state_->coarse_mask = cl::Kernel(program, "dc_coarse_mask");
        state_->coarse_count = cl::Kernel(program, "dc_coarse_count");
        state_->coarse_fill = cl::Kernel(program, "dc_coarse_fill");
        state_->bin_count = cl::Kernel(program, "dc_bin_count");
        state_->bin_fill = cl::Kernel(program, "dc_bin_fill");
        state_->shade[0] = cl::Kernel(program, "dc_shade");
        state_->shade[DC_VARIANT_FLAT] = cl::Kernel(program, "dc_shade_flat");
        state_->shade[DC_VARIANT_ALBEDO_ONLY] = cl::Kernel(program, "dc_shade_albedo");
        state_->shade[DC_VARIANT_ALBEDO_ONLY | DC_VARIANT_FLAT] = cl::Kernel(program, "dc_shade_albedo_flat");
        state_->occlusion = cl::Kernel(program, "dc_occlusion_build");
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: {}: {}", device_.info().name, e.what(), clErrorName(e.err())));
    }
    setScene(DecalScene{});
}

Compositor::~Compositor() = default;

void Compositor::setScene(const DecalScene& scene) {
    const PackedTextures packed = packTextures(scene.textures);
    try {
        state_->texture_table = makeBuffer(device_.context(), CL_MEM_READ_ONLY, packed.table);
        state_->texels = makeBuffer(device_.context(), CL_MEM_READ_ONLY, packed.texels);
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: uploading decal textures: {}", device_.info().name, clErrorName(e.err())));
    }
    state_->texture_entries = packed.first_entry;
    state_->mask_count = scene.masks.size();
    state_->scene.textures.clear();
    state_->scene.decals.clear();
    setDecals(scene.decals);
}

void Compositor::setDecals(const std::vector<Decal>& decals) {
    const int textures = int(state_->texture_entries.size());
    for (const Decal& d : decals) {
        for (int index : {d.albedo_texture, d.normal_texture, d.orm_texture, d.emission_texture})
            if (index >= textures)
                throw inputError(fmt::format("decal '{}': texture index {} out of range", d.name, index));
        if (d.mask >= int(state_->mask_count))
            throw inputError(fmt::format("decal '{}': mask index {} out of range", d.name, d.mask));
    }
    state_->scene.decals = decals;
    state_->targets = sceneTargets(state_->scene);
}

CompositeStats Compositor::composite(GBuffer& frame, const Camera& camera, const CompositeOptions& options) {
    if (!frame.has(Attribute::Albedo)) throw inputError("G-buffer has no albedo pass to decal");
    const bool uses_position = frame.depth_convention == DepthConvention::Position;
    if (uses_position && !frame.has(Attribute::Position))
        throw inputError("depth convention 'position' needs a position pass");
    if (!uses_position && !frame.has(Attribute::Depth)) throw inputError("G-buffer has no depth pass");
    if (frame.width <= 0 || frame.height <= 0 || frame.display_width <= 0 || frame.display_height <= 0)
        throw inputError("G-buffer has an empty data or display window");
    if (frame.mask_weights.size() != state_->mask_count)
        throw inputError(fmt::format("decal masks: the frame has {} weight planes, the scene {} masks",
                                     frame.mask_weights.size(), state_->mask_count));

    State& s = *state_;
    cl::Context& context = device_.context();
    cl::CommandQueue& queue = device_.queue();
    auto decals = makeDecalParams(s.scene, camera, s.texture_entries);
    const OcclusionLayout occlusion = layoutOcclusionMaps(s.scene.decals, decals);
    cl_types::DcFrame params = makeFrameParams(frame, camera, int(decals.size()));
    // Normals are read for angle fades, mip footprints, occlusion slopes and normal maps: skip
    // their upload otherwise.
    const bool needs_footprint = std::any_of(s.scene.decals.begin(), s.scene.decals.end(),
                                             [](const Decal& d) { return d.filter == TextureFilter::Mip; });
    const bool needs_normals = needs_footprint || !occlusion.occluders.empty() ||
                               std::any_of(s.scene.decals.begin(), s.scene.decals.end(),
                                           [](const Decal& d) { return d.angle_fade_deg[1] > 0.0; });
    const SurfacePlanes surface = packSurface(frame, camera, s.targets, needs_normals);
    params.attributes = surface.attributes;
    params.has_normal = (surface.attributes & (1 << DC_TARGET_NORMAL)) ? 1 : 0;
    params.reconstruct_normals = needs_normals && !params.has_normal ? 1 : 0;
    params.needs_footprint = needs_footprint ? 1 : 0;
    const std::size_t pixels = frame.pixelCount();
    const int tiles = params.tiles_x * params.tiles_y;

    CompositeStats stats;
    stats.decals = int(decals.size());
    stats.tiles = tiles;
    try {
        cl::Buffer frame_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(params),
                                const_cast<cl_types::DcFrame*>(&params));
        cl::Image2D depth = frame.has(Attribute::Depth)
                                ? makeImage(context, frame.width, frame.height, 1,
                                            imagePixels(frame.planes.at(Attribute::Depth), pixels, 1))
                                : placeholderImage(context, 1);
        cl::Image2D position = uses_position ? makeImage(context, frame.width, frame.height, 4,
                                                         imagePixels(frame.planes.at(Attribute::Position), pixels, 4))
                                             : placeholderImage(context, 4);
        std::array<cl::Image2D, kSurfaceGroups> surface_in;
        std::array<cl::Buffer, kSurfaceGroups> surface_out;
        for (int g = 0; g < kSurfaceGroups; ++g) {
            const bool used = surface.groupUsed(g);
            surface_in[std::size_t(g)] =
                used ? makeImage(context, frame.width, frame.height, 4, surface.groups[std::size_t(g)])
                     : placeholderImage(context, 4);
            surface_out[std::size_t(g)] =
                cl::Buffer(context, CL_MEM_WRITE_ONLY, (used ? pixels : 1) * sizeof(cl_float4));
        }
        cl::Buffer decal_buffer = makeBuffer(context, CL_MEM_READ_ONLY, decals);
        cl::Buffer mask_buffer = makeBuffer(context, CL_MEM_READ_ONLY, packMaskWeights(frame, s.mask_count));

        s.tile_depth = cl::Buffer(context, CL_MEM_READ_WRITE, std::size_t(tiles) * sizeof(cl_float2));
        s.tile_offsets = cl::Buffer(context, CL_MEM_READ_WRITE, std::size_t(tiles + 1) * sizeof(cl_int));
        std::vector<int> offsets(std::size_t(tiles) + 1, 0);

        if (options.binned && !decals.empty()) {
            cl::Event e_tiles, e_bounds, e_count, e_fill;
            s.tile_bounds.setArg(0, frame_buffer);
            s.tile_bounds.setArg(1, depth);
            s.tile_bounds.setArg(2, position);
            s.tile_bounds.setArg(3, s.tile_depth);
            queue.enqueueNDRangeKernel(
                s.tile_bounds, cl::NullRange,
                cl::NDRange(std::size_t(params.tiles_x) * DC_TILE_SIZE, std::size_t(params.tiles_y) * DC_TILE_SIZE),
                cl::NDRange(DC_TILE_SIZE, DC_TILE_SIZE), nullptr, &e_tiles);

            cl::Buffer bounds(context, CL_MEM_READ_WRITE, decals.size() * sizeof(cl_types::DcDecalBounds));
            s.decal_bounds.setArg(0, frame_buffer);
            s.decal_bounds.setArg(1, decal_buffer);
            s.decal_bounds.setArg(2, bounds);
            queue.enqueueNDRangeKernel(s.decal_bounds, cl::NullRange,
                                       cl::NDRange(roundUp(decals.size(), kBinGroupSize)), cl::NDRange(kBinGroupSize),
                                       nullptr, &e_bounds);

            // Level 1: coarse tiles against every decal.
            const int coarse_x = (params.tiles_x + kCoarse - 1) / kCoarse,
                      coarse_y = (params.tiles_y + kCoarse - 1) / kCoarse;
            const std::size_t coarse = std::size_t(coarse_x) * coarse_y;
            const cl::NDRange coarse_range(roundUp(coarse, kBinGroupSize));
            cl::Buffer coarse_depth(context, CL_MEM_READ_WRITE, coarse * sizeof(cl_float2));
            const std::size_t chunks = (decals.size() + 63) / 64;  // decals per mask word
            cl::Buffer coarse_counts(context, CL_MEM_READ_WRITE, coarse * sizeof(cl_int));
            cl::Buffer masks(context, CL_MEM_READ_WRITE, coarse * chunks * sizeof(cl_ulong));
            cl::Buffer chunk_starts(context, CL_MEM_READ_WRITE, coarse * chunks * sizeof(cl_int));
            const cl::NDRange pair_range(roundUp(coarse * chunks, kBinGroupSize));
            cl::Event e_cdepth, e_cmask, e_ccount, e_cfill;
            s.coarse_depth.setArg(0, frame_buffer);
            s.coarse_depth.setArg(1, s.tile_depth);
            s.coarse_depth.setArg(2, coarse_depth);
            queue.enqueueNDRangeKernel(s.coarse_depth, cl::NullRange, coarse_range, cl::NullRange, nullptr, &e_cdepth);
            s.coarse_mask.setArg(0, frame_buffer);
            s.coarse_mask.setArg(1, bounds);
            s.coarse_mask.setArg(2, coarse_depth);
            s.coarse_mask.setArg(3, masks);
            queue.enqueueNDRangeKernel(s.coarse_mask, cl::NullRange, pair_range, cl::NullRange, nullptr, &e_cmask);
            s.coarse_count.setArg(0, frame_buffer);
            s.coarse_count.setArg(1, masks);
            s.coarse_count.setArg(2, chunk_starts);
            s.coarse_count.setArg(3, coarse_counts);
            queue.enqueueNDRangeKernel(s.coarse_count, cl::NullRange, coarse_range, cl::NullRange, nullptr, &e_ccount);
            const std::vector<int> coarse_offsets = prefixSum(queue, coarse_counts, coarse);
            cl::Buffer coarse_offset_buffer = makeBuffer(context, CL_MEM_READ_ONLY, coarse_offsets);
            cl::Buffer coarse_lists(context, CL_MEM_READ_WRITE,
                                    std::size_t(std::max(coarse_offsets.back(), 1)) * sizeof(cl_int));
            s.coarse_fill.setArg(0, frame_buffer);
            s.coarse_fill.setArg(1, masks);
            s.coarse_fill.setArg(2, chunk_starts);
            s.coarse_fill.setArg(3, coarse_offset_buffer);
            s.coarse_fill.setArg(4, coarse_lists);
            queue.enqueueNDRangeKernel(s.coarse_fill, cl::NullRange, pair_range, cl::NullRange, nullptr, &e_cfill);

            // Level 2: each tile against its coarse tile's list.
            cl::Buffer counts(context, CL_MEM_READ_WRITE, std::size_t(tiles) * sizeof(cl_int));
            const cl::NDRange tile_range(roundUp(std::size_t(tiles), kBinGroupSize));
            s.bin_count.setArg(0, frame_buffer);
            s.bin_count.setArg(1, bounds);
            s.bin_count.setArg(2, s.tile_depth);
            s.bin_count.setArg(3, coarse_offset_buffer);
            s.bin_count.setArg(4, coarse_lists);
            s.bin_count.setArg(5, counts);
            queue.enqueueNDRangeKernel(s.bin_count, cl::NullRange, tile_range, cl::NullRange, nullptr, &e_count);
            offsets = prefixSum(queue, counts, std::size_t(tiles));
            const std::int64_t total = offsets.back();
            s.bin_entries = total;
            queue.enqueueWriteBuffer(s.tile_offsets, CL_FALSE, 0, offsets.size() * sizeof(int), offsets.data());
            s.tile_decals =
                cl::Buffer(context, CL_MEM_READ_WRITE, std::size_t(std::max<std::int64_t>(total, 1)) * sizeof(cl_int));
            s.bin_fill.setArg(0, frame_buffer);
            s.bin_fill.setArg(1, bounds);
            s.bin_fill.setArg(2, s.tile_depth);
            s.bin_fill.setArg(3, coarse_offset_buffer);
            s.bin_fill.setArg(4, coarse_lists);
            s.bin_fill.setArg(5, s.tile_offsets);
            s.bin_fill.setArg(6, s.tile_decals);
            queue.enqueueNDRangeKernel(s.bin_fill, cl::NullRange, tile_range, cl::NullRange, nullptr, &e_fill);
            queue.finish();
            stats.tile_bounds_ms = eventMs(e_tiles);
            stats.binning_ms = eventMs(e_bounds) + eventMs(e_cdepth) + eventMs(e_cmask) + eventMs(e_ccount) +
                               eventMs(e_cfill) + eventMs(e_count) + eventMs(e_fill);
            stats.bin_entries = s.bin_entries;
            s.tiles_x = params.tiles_x;
            s.tiles_y = params.tiles_y;
            s.has_binning = true;
        } else {
            s.tile_decals = cl::Buffer(context, CL_MEM_READ_WRITE, sizeof(cl_int));
            queue.enqueueWriteBuffer(s.tile_offsets, CL_FALSE, 0, offsets.size() * sizeof(int), offsets.data());
            s.has_binning = false;
        }

        cl::Event e_occlusion;
        const cl::Buffer occlusion_maps =
            buildOcclusionMaps(context, queue, s.occlusion, occlusion, frame_buffer, depth, position, decal_buffer,
                               frame.width, frame.height, &e_occlusion);

        cl::Event e_shade;
        // The leanest shading kernel that fits: albedo only without blast occlusion; 2D kinds only.
        const bool albedo_only = occlusion.occluders.empty() &&
                                 std::none_of(s.targets.begin() + 1, s.targets.end(), [](bool t) { return t; });
        const bool flat = std::all_of(s.scene.decals.begin(), s.scene.decals.end(), [](const Decal& d) {
            return d.kind == DecalKind::Box || d.kind == DecalKind::Frustum;
        });
        cl::Kernel& shade =
            s.shade[std::size_t((albedo_only ? DC_VARIANT_ALBEDO_ONLY : 0) | (flat ? DC_VARIANT_FLAT : 0))];
        shade.setArg(0, frame_buffer);
        shade.setArg(1, depth);
        shade.setArg(2, position);
        for (int g = 0; g < kSurfaceGroups; ++g) {
            shade.setArg(cl_uint(3 + g), surface_in[std::size_t(g)]);
            shade.setArg(cl_uint(6 + g), surface_out[std::size_t(g)]);
        }
        shade.setArg(9, decal_buffer);
        shade.setArg(10, s.texture_table);
        shade.setArg(11, s.texels);
        shade.setArg(12, s.tile_offsets);
        shade.setArg(13, s.tile_decals);
        shade.setArg(14, cl_int(options.binned && !decals.empty() ? 1 : 0));
        shade.setArg(15, mask_buffer);
        shade.setArg(16, occlusion_maps);
        queue.enqueueNDRangeKernel(shade, cl::NullRange,
                                   cl::NDRange(std::size_t(frame.width), std::size_t(frame.height)), cl::NullRange,
                                   nullptr, &e_shade);
        std::array<std::vector<float>, kSurfaceGroups> results;
        for (int g = 0; g < kSurfaceGroups; ++g) {
            if (!groupWrittenBack(surface, s.targets, g)) continue;
            results[std::size_t(g)].resize(pixels * 4);
            queue.enqueueReadBuffer(surface_out[std::size_t(g)], CL_TRUE, 0, pixels * sizeof(cl_float4),
                                    results[std::size_t(g)].data());
        }
        stats.shading_ms = eventMs(e_shade);
        if (!occlusion.occluders.empty()) stats.occlusion_ms = eventMs(e_occlusion);
        unpackSurface(frame, camera, surface, results, s.targets);
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: {} failed: {}", device_.info().name, e.what(), clErrorName(e.err())));
    }
    return stats;
}

BinningResult Compositor::lastBinning() {
    State& s = *state_;
    BinningResult r;
    if (!s.has_binning) return r;
    r.tiles_x = s.tiles_x;
    r.tiles_y = s.tiles_y;
    const std::size_t tiles = std::size_t(s.tiles_x) * std::size_t(s.tiles_y);
    r.tile_depth.resize(tiles * 2);
    r.tile_offsets.resize(tiles + 1);
    r.tile_decals.resize(std::size_t(s.bin_entries));
    cl::CommandQueue& queue = device_.queue();
    queue.enqueueReadBuffer(s.tile_depth, CL_TRUE, 0, r.tile_depth.size() * sizeof(float), r.tile_depth.data());
    queue.enqueueReadBuffer(s.tile_offsets, CL_TRUE, 0, r.tile_offsets.size() * sizeof(int), r.tile_offsets.data());
    if (!r.tile_decals.empty())
        queue.enqueueReadBuffer(s.tile_decals, CL_TRUE, 0, r.tile_decals.size() * sizeof(int), r.tile_decals.data());
    return r;
}

}  // namespace decalcomp
