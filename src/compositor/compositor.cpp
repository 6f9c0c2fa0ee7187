#include "decalcomp/compositor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "compositor/beauty_transfer.hpp"
#include "compositor/device_buffers.hpp"
#include "compositor/kernel_params.hpp"
#include "compositor/kernels.hpp"
#include "compositor/occlusion_maps.hpp"
#include "compositor/rest_pass.hpp"
#include "compositor/staged_buffer.hpp"
#include "compositor/surface_planes.hpp"
#include "decalcomp/bake.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

constexpr int kBinGroupSize = 64;  // work-items per group in the binning kernels (any size works)
// Below this many tiles per compute unit a work-item per tile leaves a GPU idle, and the tile bounds
// and tests run a work-group per tile. On an H100 (132 units), grouped against a work-item per tile
// with 4096 decals: at 1080p (62 tiles a unit) bounds 0.017 against 0.023 ms, tests 0.023 against
// 0.066; at 1440p (109) bounds 0.027 against 0.023, tests 0.032 against 0.056 but, with 1024 decals,
// 0.029 against 0.020; at 4K (245) 0.059 against 0.034 and 0.060 against 0.050 (docs/benchmarks.md).
constexpr std::size_t kGroupedTilesPerUnit = 96;

// The paths of the shading kernel that the frame takes (kernels/shading.cl tests the same fields):
// a frame with texture-space decals takes the rest pose's loop alone, filtered or not.
ShadingPaths shadingPaths(const cl_types::DcFrame& params) {
    const bool rest = params.rest_decals != 0, filtered = params.filter_taps > 0;
    return {filtered && !params.filter_fast && !rest, filtered && params.filter_fast && !rest, rest};
}

double eventMs(const cl::Event& e) {
    const auto start = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return double(end - start) * 1e-6;
}

// Pixels `range` of the position plane (3 or more components) as float4 per pixel.
void packPosition(const Plane& plane, PixelRange range, float* out) {
    const int copy = std::min(plane.components, 3);
#pragma omp parallel for schedule(static) if (range.last - range.first >= (1u << 16))
    for (std::ptrdiff_t i = std::ptrdiff_t(range.first); i < std::ptrdiff_t(range.last); ++i) {
        float* o = out + i * 4;
        for (int c = 0; c < 4; ++c) o[c] = c < copy ? plane.at(std::size_t(i), c) : 0.0f;
    }
}

// Frames cross to and from a discrete device in this many runs of rows, so the DMA of one run
// overlaps the packing (or unpacking) of the next. Devices that map host memory copy nothing.
int transferChunks(std::size_t pixels, bool unified) { return unified || pixels < (1u << 20) ? 1 : 8; }

PixelRange chunkRange(std::size_t pixels, int chunk, int chunks) {
    return {pixels * std::size_t(chunk) / std::size_t(chunks), pixels * std::size_t(chunk + 1) / std::size_t(chunks)};
}

// Room for `needed` list entries with headroom, as the kernels' int capacity.
std::size_t listCapacity(std::int64_t needed) {
    if (needed > INT32_MAX / 2) throw deviceError("binning: more than 2^30 tile-decal pairs");
    return std::size_t(std::max<std::int64_t>(needed + needed / 2, 1024));
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

// Everything a frame needs on the device, kept across frames: buffers are reallocated only when
// a frame is larger than any before it, the pinned staging memory with them.
struct Compositor::State {
    // built by the first frame, from the point program (ComputeDevice::program); filtered and
    // texture-space frames' shading kernels come from their own programs (CompositorKernels::shading)
    std::optional<CompositorKernels> kernels;
    cl::CommandQueue queue;  // this compositor's own, so two compositors on a device overlap
    bool unified = false;    // the device works in host memory (PoCL): buffers are mapped, not copied
    bool cpu = false;        // a CPU device: tile bounds without work-group barriers
    std::size_t compute_units = 1;
    bool profiling = true;
    cl::Buffer texture_table, texels;
    std::size_t mask_count = 0;
    std::vector<int> texture_entries;           // scene texture index -> texture table entry
    std::array<bool, kDecalTargets> targets{};  // what the scene's decals change
    DecalScene scene;                           // decals only; textures live on the device
    RestMeshBuffers rest_meshes;                // texture-space decals' meshes, on the device
    RestPassBuffers rest_pass;                  // their per-frame rest points and rotations
    // bake-mode decals' layers (bake.hpp), by bake slot: their scene texture indices, -1 = none
    std::map<int, std::array<int, 3>> bakes;

    // per frame, kept alive until the queue has passed their (non-blocking) uploads
    cl_types::DcFrame frame_params{};
    std::vector<cl_types::DcDecal> decal_params;
    std::array<cl_int, 2> totals{};  // coarse and tile list lengths, read back with the results

    // device memory, grown on demand
    StagedBuffer depth, position, masks;
    StagedBuffer beauty, light;               // the beauty's changes and its light terms (beauty_transfer.hpp)
    std::vector<cl_int> beauty_tile_offsets;  // the tiles those changes were written for, read back
    std::array<StagedBuffer, kSurfaceGroups> surface;
    // Filtered frames: surface groups 0 and 1 as uploaded. Split silhouette pixels read their
    // neighbours' albedo and normal, which the shading kernel changes in place meanwhile.
    std::array<cl::Buffer, 2> original;
    // Filtered frames: each pixel's view depth where it is clean, else NaN (kernels/clean_depth.h).
    cl::Buffer clean_depths;
    cl::Buffer frame_buffer, decal_buffer, bounds, tile_depth, coarse_depth, coarse_counts, coarse_offsets, chunk_masks,
        chunk_starts, coarse_lists, tile_counts, tile_offsets, tile_decals, totals_buffer;
    // Per coarse-list entry, a flag for each tile of its coarse tile: the binning's count pass
    // leaves its tests there for the fill pass.
    cl::Buffer listed;
    std::size_t coarse_capacity = 0, list_capacity = 0;  // list entries (ints)

    // last frame's binning, kept for lastBinning()
    int tiles_x = 0, tiles_y = 0;
    std::int64_t bin_entries = 0;
    bool has_binning = false;
};

Compositor::Compositor(ComputeDevice& device) : device_(device) {
    try {
        state_ = std::make_unique<State>();
        State& s = *state_;
        s.profiling = device_.profiling();
        s.queue = cl::CommandQueue(device_.context(), device_.info().device,
                                   s.profiling ? CL_QUEUE_PROFILING_ENABLE : cl_command_queue_properties(0));
        s.unified = device_.info().device.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() == CL_TRUE;
        s.cpu = (device_.info().device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) != 0;
        s.compute_units = std::max<cl_uint>(device_.info().device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>(), 1);
        // DECALCOMP_STAGING=pinned|mapped overrides the choice (tests run the pinned path on PoCL)
        if (const char* staging = std::getenv("DECALCOMP_STAGING")) {
            if (std::string(staging) == "pinned")
                s.unified = false;
            else if (std::string(staging) == "mapped")
                s.unified = true;
        }
        s.frame_buffer = cl::Buffer(device_.context(), CL_MEM_READ_ONLY, sizeof(cl_types::DcFrame));
        s.totals_buffer = cl::Buffer(device_.context(), CL_MEM_READ_WRITE, 2 * sizeof(cl_int));
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: {}: {}", device_.info().name, e.what(), clErrorName(e.err())));
    }
    setScene(DecalScene{});
}

Compositor::~Compositor() = default;

namespace {

bool needsBake(const Decal& d) {
    return d.space == DecalSpace::ObjectRest && d.rest_mode == RestMode::Bake && !d.baked;
}
int bakeSlot(const Decal& d, std::size_t index) { return d.bake_slot >= 0 ? d.bake_slot : int(index); }

}  // namespace

void Compositor::setScene(const DecalScene& scene) {
    // Bake-mode decals are baked here, once per scene: their layers join the textures.
    std::vector<Texture2D> baked_textures;
    state_->bakes.clear();
    for (std::size_t k = 0; k < scene.decals.size(); ++k) {
        const Decal& d = scene.decals[k];
        if (!needsBake(d) || state_->bakes.count(bakeSlot(d, k))) continue;
        BakedLayers layers = bakeDecal(device_, scene, d);
        auto add = [&](Texture2D* layer) {
            if (!layer) return -1;
            baked_textures.push_back(std::move(*layer));
            return int(scene.textures.size() + baked_textures.size()) - 1;
        };
        state_->bakes[bakeSlot(d, k)] = {add(&layers.albedo), add(layers.orm ? &*layers.orm : nullptr),
                                         add(layers.emission ? &*layers.emission : nullptr)};
    }
    std::vector<Texture2D> with_bakes;
    if (!baked_textures.empty()) {
        with_bakes = scene.textures;
        for (Texture2D& t : baked_textures) with_bakes.push_back(std::move(t));
    }
    const PackedTextures packed = packTextures(baked_textures.empty() ? scene.textures : with_bakes);
    try {
        state_->texture_table = makeBuffer(device_.context(), packed.table);
        state_->texels = makeBuffer(device_.context(), packed.texels);
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: uploading decal textures: {}", device_.info().name, clErrorName(e.err())));
    }
    state_->rest_meshes = uploadRestMeshes(device_.context(), scene.meshes);
    state_->texture_entries = packed.first_entry;
    state_->mask_count = scene.masks.size();
    state_->scene.textures.clear();
    state_->scene.decals.clear();
    setDecals(scene.decals);
}

void Compositor::setDecals(const std::vector<Decal>& input) {
    const int textures = int(state_->texture_entries.size());
    std::vector<Decal> decals = input;
    for (std::size_t k = 0; k < decals.size(); ++k) {
        if (!needsBake(decals[k])) continue;
        const auto bake = state_->bakes.find(bakeSlot(decals[k], k));
        if (bake == state_->bakes.end())
            throw inputError(
                fmt::format("decal '{}': bake mode, and the scene set had no such decal to bake", decals[k].name));
        decals[k] = bakedDecal(decals[k], bake->second[0], bake->second[1], bake->second[2]);
    }
    for (const Decal& d : decals) {
        for (int index : {d.albedo_texture, d.normal_texture, d.orm_texture, d.emission_texture})
            if (index >= textures)
                throw inputError(fmt::format("decal '{}': texture index {} out of range", d.name, index));
        if (d.mask >= int(state_->mask_count))
            throw inputError(fmt::format("decal '{}': mask index {} out of range", d.name, d.mask));
        if (d.space == DecalSpace::ObjectRest &&
            (d.rest_mesh < 0 || d.rest_mesh >= int(state_->rest_meshes.grids.size())))
            throw inputError(fmt::format("decal '{}': rest mesh index {} out of range", d.name, d.rest_mesh));
    }
    state_->scene.decals = decals;
    state_->targets = sceneTargets(state_->scene);
}

namespace {

void checkFrame(const GBuffer& frame, std::size_t mask_count) {
    if (!frame.has(Attribute::Albedo)) throw inputError("G-buffer has no albedo pass to decal");
    const bool uses_position = frame.depth_convention == DepthConvention::Position;
    if (uses_position && !frame.has(Attribute::Position))
        throw inputError("depth convention 'position' needs a position pass");
    if (!uses_position && !frame.has(Attribute::Depth)) throw inputError("G-buffer has no depth pass");
    if (frame.width <= 0 || frame.height <= 0 || frame.display_width <= 0 || frame.display_height <= 0)
        throw inputError("G-buffer has an empty data or display window");
    if (frame.mask_weights.size() != mask_count)
        throw inputError(fmt::format("decal masks: the frame has {} weight planes, the scene {} masks",
                                     frame.mask_weights.size(), mask_count));
    for (const Plane& plane : frame.mask_weights)
        if (plane.components != 1 || plane.samples.size() != frame.pixelCount())
            throw inputError("decal masks: a weight plane does not match the frame size");
}

// Waits for whatever the queue still holds before an error unwinds the frame: a non-blocking
// transfer in flight reads or writes host memory (the totals, the parameters) that the caller may
// free next.
void finishQuietly(cl::CommandQueue& queue) noexcept {
    try {
        queue.finish();
    } catch (...) {  // the error already on its way says more than a second one would
    }
}

}  // namespace

CompositeStats Compositor::composite(GBuffer& frame, const Camera& camera, const CompositeOptions& options,
                                     BeautyPlanes* beauty) {
    State& s = *state_;
    checkFrame(frame, s.mask_count);
    if (beauty) checkBeautyPlanes(*beauty, frame.pixelCount());
    CompositeStats stats;
    if (s.scene.decals.empty()) return stats;  // nothing to blend: the planes stay as they are
    const HostThreads host_threads(options.host_threads);

    cl::Context& context = device_.context();
    cl::CommandQueue& queue = s.queue;
    s.decal_params = makeDecalParams(s.scene, camera, s.texture_entries);
    const OcclusionLayout occlusion = layoutOcclusionMaps(s.scene.decals, s.decal_params);
    const RestBindings rest = bindRestDecals(s.scene.decals, s.rest_meshes, frame.uv_v_down, s.decal_params);
    checkRestPassInputs(rest, frame);
    s.frame_params = makeFrameParams(frame, camera, int(s.decal_params.size()));
    cl_types::DcFrame& params = s.frame_params;
    // Normals are read for angle fades, mip footprints, occlusion slopes, normal maps and the
    // pixel filter's tangent planes: skip their upload otherwise.
    const bool needs_footprint = std::any_of(s.scene.decals.begin(), s.scene.decals.end(),
                                             [](const Decal& d) { return d.filter == TextureFilter::Mip; });
    const bool needs_normals = needs_footprint || frame.pixel_filter.enabled() || !occlusion.occluders.empty() ||
                               rest.needs_frames ||
                               std::any_of(s.scene.decals.begin(), s.scene.decals.end(),
                                           [](const Decal& d) { return d.angle_fade_deg[1] > 0.0; });
    const SurfaceLayout surface = surfaceLayout(frame, s.targets, needs_normals);
    params.attributes = surface.attributes;
    params.has_normal = (surface.attributes & (1 << DC_TARGET_NORMAL)) ? 1 : 0;
    params.reconstruct_normals = needs_normals && !params.has_normal ? 1 : 0;
    params.needs_footprint = needs_footprint ? 1 : 0;
    params.rest_frames = rest.needs_frames ? 1 : 0;
    params.rest_decals = rest.bindings.empty() ? 0 : 1;
    const bool fold_light = beauty && foldsLightTerms(*beauty, params.filter_taps > 0);
    setBeautyParams(params, beauty, fold_light);
    const std::size_t pixels = frame.pixelCount();
    const std::size_t decals = s.decal_params.size();
    const std::size_t tiles = std::size_t(params.tiles_x) * std::size_t(params.tiles_y);
    const std::size_t coarse = std::size_t((params.tiles_x + DC_COARSE_TILES - 1) / DC_COARSE_TILES) *
                               std::size_t((params.tiles_y + DC_COARSE_TILES - 1) / DC_COARSE_TILES);
    const std::size_t chunks = (decals + DC_DECALS_PER_MASK_WORD - 1) / DC_DECALS_PER_MASK_WORD;
    const bool binned = options.binned;
    const bool uses_position = frame.depth_convention == DepthConvention::Position;
    stats.decals = int(decals);
    stats.tiles = int(tiles);

    try {
        // ---- device memory for this size (reallocated only when it grows) ----
        s.depth.reserve(context, queue, (frame.has(Attribute::Depth) ? pixels : 1) * sizeof(float), s.unified);
        s.position.reserve(context, queue, (uses_position ? pixels : 1) * sizeof(cl_float4), s.unified);
        for (int g = 0; g < kSurfaceGroups; ++g)
            s.surface[std::size_t(g)].reserve(
                context, queue, (surface.used[std::size_t(g)] ? pixels : 1) * sizeof(cl_float4), s.unified);
        const bool filtered = params.filter_taps > 0;
        for (int g = 0; g < 2; ++g)
            reserve(context, s.original[std::size_t(g)],
                    (filtered && surface.used[std::size_t(g)] ? pixels : 1) * sizeof(cl_float4));
        const bool clean_plane =
            filtered &&
            (options.clean_depths == CleanDepths::Device ? !s.cpu : options.clean_depths == CleanDepths::Plane);
        params.clean_plane = clean_plane ? 1 : 0;
        reserve(context, s.clean_depths, (clean_plane ? pixels : 1) * sizeof(float));
        s.masks.reserve(context, queue, std::max<std::size_t>(s.mask_count * pixels, 1) * sizeof(float), s.unified);
        const std::size_t light_terms = beauty ? deviceLightTerms(*beauty, fold_light) : 0;
        // one folded term, read by its own pixel alone: the changes overwrite it (beauty_transfer.hpp)
        const bool change_in_light = fold_light && light_terms == 1;
        params.change_in_light = change_in_light ? 1 : 0;
        s.beauty.reserve(context, queue, (beauty && !change_in_light ? pixels : 1) * kBeautyPixelBytes, s.unified);
        StagedBuffer& changes = change_in_light ? s.light : s.beauty;
        if (beauty && binned) s.beauty_tile_offsets.resize(tiles + 1);
        s.light.reserve(context, queue, std::max<std::size_t>(light_terms * pixels, 1) * kBeautyPixelBytes, s.unified);
        reserve(context, s.decal_buffer, decals * sizeof(cl_types::DcDecal));
        reserve(context, s.bounds, decals * sizeof(cl_types::DcDecalBounds));
        reserve(context, s.tile_depth, tiles * sizeof(cl_float2));
        reserve(context, s.coarse_depth, coarse * sizeof(cl_float2));
        reserve(context, s.coarse_counts, coarse * sizeof(cl_int));
        reserve(context, s.coarse_offsets, (coarse + 1) * sizeof(cl_int));
        reserve(context, s.chunk_masks, coarse * chunks * sizeof(cl_ulong));
        reserve(context, s.chunk_starts, coarse * chunks * sizeof(cl_int));
        reserve(context, s.tile_counts, tiles * sizeof(cl_int));
        reserve(context, s.tile_offsets, (tiles + 1) * sizeof(cl_int));
        if (s.coarse_capacity == 0)
            s.coarse_capacity = listCapacity(std::int64_t(coarse) * 4 + std::int64_t(decals) * 4);
        if (s.list_capacity == 0) s.list_capacity = listCapacity(std::int64_t(tiles) * 4 + std::int64_t(decals) * 16);

        // ---- one pass; again only when a list outgrew its capacity (then grown to fit) ----
        for (int attempt = 0;; ++attempt) {
            reserve(context, s.coarse_lists, s.coarse_capacity * sizeof(cl_int));
            reserve(context, s.listed, s.coarse_capacity * DC_COARSE_TILES * DC_COARSE_TILES);
            reserve(context, s.tile_decals, s.list_capacity * sizeof(cl_int));
            queue.enqueueWriteBuffer(s.frame_buffer, CL_FALSE, 0, sizeof(params), &params);
            queue.enqueueWriteBuffer(s.decal_buffer, CL_FALSE, 0, decals * sizeof(cl_types::DcDecal),
                                     s.decal_params.data());
            // The light first: uploaded last, it slowed the first kernel (tile bounds) by 10 % on an
            // H100, which was left writing back what the copy had left in its cache.
            if (beauty && light_terms > 0) {
                packLightTerms(*beauty, fold_light, static_cast<float*>(s.light.beginUpload(queue)));
                s.light.uploadRange(queue, 0, light_terms * pixels * kBeautyPixelBytes);
                s.light.finishUpload(queue);
            }
            // Planes go from the G-buffer straight into the device's staging memory, run by run.
            const int runs = transferChunks(pixels, s.unified);
            const bool has_depth = frame.has(Attribute::Depth);
            float* depth_view = has_depth ? static_cast<float*>(s.depth.beginUpload(queue)) : nullptr;
            float* position_view = uses_position ? static_cast<float*>(s.position.beginUpload(queue)) : nullptr;
            std::array<float*, kSurfaceGroups> group_view{};
            for (int g = 0; g < kSurfaceGroups; ++g)
                if (surface.used[std::size_t(g)])
                    group_view[std::size_t(g)] = static_cast<float*>(s.surface[std::size_t(g)].beginUpload(queue));
            for (int c = 0; c < runs; ++c) {
                const PixelRange r = chunkRange(pixels, c, runs);
                const std::size_t n = r.last - r.first;
                if (has_depth) {
                    parallelCopy(depth_view, frame.planes.at(Attribute::Depth).samples.data(), r);
                    s.depth.uploadRange(queue, r.first * sizeof(float), n * sizeof(float));
                }
                if (uses_position) {
                    packPosition(frame.planes.at(Attribute::Position), r, position_view);
                    s.position.uploadRange(queue, r.first * sizeof(cl_float4), n * sizeof(cl_float4));
                }
                for (int g = 0; g < kSurfaceGroups; ++g) {
                    if (!group_view[std::size_t(g)]) continue;
                    packSurfaceGroup(frame, camera, surface, g, r, group_view[std::size_t(g)]);
                    s.surface[std::size_t(g)].uploadRange(queue, r.first * sizeof(cl_float4), n * sizeof(cl_float4));
                }
                queue.flush();  // start this run's copies while the next is packed
            }
            s.depth.finishUpload(queue);
            s.position.finishUpload(queue);
            for (StagedBuffer& group : s.surface) group.finishUpload(queue);
            if (s.mask_count > 0) {
                auto* out = static_cast<float*>(s.masks.beginUpload(queue));
                for (std::size_t m = 0; m < s.mask_count; ++m)
                    parallelCopy(out + m * pixels, frame.mask_weights[m].samples.data(), {0, pixels});
                s.masks.uploadRange(queue, 0, s.mask_count * pixels * sizeof(float));
                s.masks.finishUpload(queue);
            }

            cl::Event totals_read;
            cl::Event e_tiles, e_bounds, e_cdepth, e_cclear, e_cmask, e_ccount, e_cscan, e_cfill, e_count, e_scan,
                e_fill;
            const cl::Buffer& depth = s.depth.device();
            const cl::Buffer& position = s.position.device();
            if (!s.kernels) s.kernels.emplace(device_.program());
            CompositorKernels& k = *s.kernels;
            if (binned) {
                // Per-tile kernels (TileKernels). By the device, as measured (docs/decisions.md): a
                // work-item per tile on CPUs; on GPUs the coarse counts a work-group per (coarse) tile,
                // and the tile bounds and tests too while a work-item per tile would leave the GPU
                // short of work (fewer than kGroupedTilesPerUnit tiles per compute unit).
                const TileKernels kind = options.tile_kernels;
                const bool gpu = kind == TileKernels::Device && !s.cpu;
                const bool few_tiles = tiles < kGroupedTilesPerUnit * s.compute_units;
                const bool serial_counts = !(kind == TileKernels::Groups || gpu);
                const bool serial_tiles = !(kind == TileKernels::Groups || (gpu && few_tiles));
                e_tiles = serial_tiles
                              ? k.tile_bounds_serial(cl::EnqueueArgs(queue, cl::NDRange(roundUp(tiles, kBinGroupSize))),
                                                     s.frame_buffer, depth, position, s.tile_depth)
                              : k.tile_bounds(cl::EnqueueArgs(queue,
                                                              cl::NDRange(std::size_t(params.tiles_x) * DC_TILE_SIZE,
                                                                          std::size_t(params.tiles_y) * DC_TILE_SIZE),
                                                              cl::NDRange(DC_TILE_SIZE, DC_TILE_SIZE)),
                                              s.frame_buffer, depth, position, s.tile_depth);
                e_bounds = k.decal_bounds(
                    cl::EnqueueArgs(queue, cl::NDRange(roundUp(decals, kBinGroupSize)), cl::NDRange(kBinGroupSize)),
                    s.frame_buffer, s.decal_buffer, s.bounds);
                // Level 1: each decal marks the coarse tiles it overlaps, 64 decals per mask word.
                const cl::NDRange coarse_range(roundUp(coarse, kBinGroupSize)),
                    pair_range(roundUp(coarse * chunks, kBinGroupSize));
                const cl::NDRange scan_range(DC_SCAN_GROUP);
                e_cdepth =
                    k.coarse_depth(cl::EnqueueArgs(queue, coarse_range), s.frame_buffer, s.tile_depth, s.coarse_depth);
                queue.enqueueFillBuffer(s.chunk_masks, cl_uint(0), 0, coarse * chunks * sizeof(cl_ulong), nullptr,
                                        &e_cclear);
                e_cmask =
                    k.coarse_mark(cl::EnqueueArgs(queue, cl::NDRange(roundUp(decals * DC_MARK_LANES, kBinGroupSize))),
                                  s.frame_buffer, s.bounds, s.coarse_depth, s.chunk_masks);
                e_ccount = serial_counts
                               ? k.coarse_count_serial(cl::EnqueueArgs(queue, coarse_range), s.frame_buffer,
                                                       s.chunk_masks, s.chunk_starts, s.coarse_counts)
                               : k.coarse_count(cl::EnqueueArgs(queue, cl::NDRange(coarse * DC_CHUNK_LANES),
                                                                cl::NDRange(DC_CHUNK_LANES)),
                                                s.frame_buffer, s.chunk_masks, s.chunk_starts, s.coarse_counts);
                e_cscan = k.scan(cl::EnqueueArgs(queue, scan_range, scan_range), s.coarse_counts, cl_int(coarse),
                                 s.coarse_offsets);
                e_cfill = k.coarse_fill(cl::EnqueueArgs(queue, pair_range), s.frame_buffer, s.chunk_masks,
                                        s.chunk_starts, s.coarse_offsets, s.coarse_lists, cl_int(s.coarse_capacity));
                // Level 2: each tile against its coarse tile's list.
                const cl::NDRange tile_range(roundUp(tiles, kBinGroupSize));
                e_count = (serial_tiles ? k.bin_count_serial : k.bin_count)(
                    serial_tiles ? cl::EnqueueArgs(queue, tile_range)
                                 : cl::EnqueueArgs(queue, cl::NDRange(tiles * DC_BIN_LANES), cl::NDRange(DC_BIN_LANES)),
                    s.frame_buffer, s.decal_buffer, s.bounds, s.tile_depth, s.coarse_offsets, s.coarse_lists,
                    cl_int(s.coarse_capacity), s.listed, s.tile_counts);
                e_scan = k.scan(cl::EnqueueArgs(queue, scan_range, scan_range), s.tile_counts, cl_int(tiles),
                                s.tile_offsets);
                e_fill = k.bin_fill(cl::EnqueueArgs(queue, tile_range), s.frame_buffer, s.coarse_offsets,
                                    s.coarse_lists, cl_int(s.coarse_capacity), s.listed, s.tile_offsets, s.tile_decals,
                                    cl_int(s.list_capacity));
                queue.enqueueCopyBuffer(s.coarse_offsets, s.totals_buffer, coarse * sizeof(cl_int), 0, sizeof(cl_int));
                queue.enqueueCopyBuffer(s.tile_offsets, s.totals_buffer, tiles * sizeof(cl_int), sizeof(cl_int),
                                        sizeof(cl_int));
                queue.enqueueReadBuffer(s.totals_buffer, CL_FALSE, 0, sizeof(s.totals), s.totals.data(), nullptr,
                                        &totals_read);
            }

            const std::vector<cl::Event> e_rest =
                enqueueRestPass(context, queue, k, s.rest_meshes, rest, frame, s.frame_buffer, depth, position,
                                s.surface[1].device(), s.masks.device(), s.unified, s.rest_pass);
            cl::Event e_occlusion;
            const cl::Buffer occlusion_maps =
                buildOcclusionMaps(context, queue, k, occlusion, s.frame_buffer, depth, position, s.decal_buffer,
                                   frame.width, frame.height, &e_occlusion);

            // The leanest shading kernel that fits: albedo only without blast occlusion; 2D kinds only;
            // point-sampled without texture-space decals.
            const bool albedo_only = occlusion.occluders.empty() &&
                                     std::none_of(s.targets.begin() + 1, s.targets.end(), [](bool t) { return t; });
            const bool flat = std::all_of(s.scene.decals.begin(), s.scene.decals.end(), [](const Decal& d) {
                return d.kind == DecalKind::Box || d.kind == DecalKind::Frustum;
            });
            // a frame without a filter or texture-space decals takes no path: the point program's kernel
            const ShadingPaths paths = shadingPaths(params);
            CompositorKernels::Shade& shade =
                k.shading((albedo_only ? DC_VARIANT_ALBEDO_ONLY : 0) | (flat ? DC_VARIANT_FLAT : 0) |
                              (paths.any() ? 0 : DC_VARIANT_POINT),
                          paths, device_);
            // Binned, one work-group per screen tile: its work-items walk the same decal list. Unbinned
            // the same groups: PoCL keeps a work-group's private variables on its thread's stack, and
            // the groups it picks itself for a whole frame (40 x 78) overflowed it.
            // a work-item per pixel in tile-sized groups (also the clean-depth pass's)
            const cl::EnqueueArgs pixel_range(queue,
                                              cl::NDRange(roundUp(std::size_t(frame.width), DC_TILE_SIZE),
                                                          roundUp(std::size_t(frame.height), DC_TILE_SIZE)),
                                              cl::NDRange(DC_TILE_SIZE, DC_TILE_SIZE));
            const cl::EnqueueArgs shade_range =
                binned ? cl::EnqueueArgs(queue,
                                         cl::NDRange(std::size_t(params.tiles_x) * DC_TILE_SIZE,
                                                     std::size_t(params.tiles_y) * DC_TILE_SIZE),
                                         cl::NDRange(DC_TILE_SIZE, DC_TILE_SIZE))
                       : pixel_range;
            for (int g = 0; g < 2; ++g)
                if (filtered && surface.used[std::size_t(g)])
                    queue.enqueueCopyBuffer(s.surface[std::size_t(g)].device(), s.original[std::size_t(g)], 0, 0,
                                            pixels * sizeof(cl_float4));
            cl::Event e_clean;
            if (clean_plane) e_clean = k.clean_depths(pixel_range, s.frame_buffer, depth, position, s.clean_depths);
            const cl::Event e_shade =
                shade(shade_range, s.frame_buffer, depth, position, s.surface[0].device(), s.surface[1].device(),
                      s.surface[2].device(), s.original[0], s.original[1], s.clean_depths, s.decal_buffer,
                      s.texture_table, s.texels, s.tile_offsets, s.tile_decals, s.bounds, cl_int(binned ? 1 : 0),
                      cl_int(s.list_capacity), s.masks.device(), occlusion_maps, s.beauty.device(), s.light.device(),
                      s.rest_pass.points, s.rest_pass.frames);
            // Only the groups that hold a changed attribute come back, run by run, each unpacked
            // while the next is still on its way.
            std::vector<std::array<cl::Event, kSurfaceGroups>> downloaded(static_cast<std::size_t>(runs));
            for (int c = 0; c < runs; ++c) {
                const PixelRange r = chunkRange(pixels, c, runs);
                for (int g = 0; g < kSurfaceGroups; ++g)
                    if (groupWrittenBack(surface, s.targets, g))
                        s.surface[std::size_t(g)].enqueueDownload(queue, r.first * sizeof(cl_float4),
                                                                  (r.last - r.first) * sizeof(cl_float4),
                                                                  &downloaded[std::size_t(c)][std::size_t(g)]);
            }
            const bool light_back = beauty && beauty->lightRewritten() && light_terms > 0;
            cl::Event beauty_downloaded, light_downloaded;
            if (beauty) changes.enqueueDownload(queue, 0, pixels * kBeautyPixelBytes, &beauty_downloaded);
            // which tiles the beauty's changes were written for (beauty_transfer.hpp)
            if (beauty && binned)
                queue.enqueueReadBuffer(s.tile_offsets, CL_FALSE, 0, (tiles + 1) * sizeof(cl_int),
                                        s.beauty_tile_offsets.data());
            if (light_back)
                s.light.enqueueDownload(queue, 0, light_terms * pixels * kBeautyPixelBytes, &light_downloaded);
            queue.flush();
            if (binned) totals_read.wait();  // the binning's totals are back long before the planes
            if (binned &&
                (std::size_t(s.totals[0]) > s.coarse_capacity || std::size_t(s.totals[1]) > s.list_capacity)) {
                queue.finish();
                // A coarse list that overflowed also cut the tile counts short: at most two regrowths.
                if (attempt >= 2) throw deviceError("binning: the tile lists outgrew their capacity three times");
                s.coarse_capacity = std::max(s.coarse_capacity, listCapacity(s.totals[0]));
                s.list_capacity = std::max(s.list_capacity, listCapacity(s.totals[1]));
                continue;  // the planes are untouched until unpacked: run the frame again
            }
            if (s.unified) queue.finish();  // the mapped buffers are read once the kernels are done
            for (int g = 0; g < kSurfaceGroups; ++g) {
                if (!groupWrittenBack(surface, s.targets, g)) continue;
                StagedBuffer& group = s.surface[std::size_t(g)];
                const auto* result = static_cast<const float*>(group.beginDownload(queue, pixels * sizeof(cl_float4)));
                for (int c = 0; c < runs; ++c) {
                    cl::Event& done = downloaded[std::size_t(c)][std::size_t(g)];
                    if (done()) done.wait();
                    unpackSurfaceGroup(frame, camera, surface, g, chunkRange(pixels, c, runs), result, s.targets);
                }
                group.endDownload(queue);
            }
            if (beauty) {
                queue.finish();
                const auto* beauty_result =
                    static_cast<const float*>(changes.beginDownload(queue, pixels * kBeautyPixelBytes));
                const auto* light_result = light_back ? static_cast<const float*>(s.light.beginDownload(
                                                            queue, light_terms * pixels * kBeautyPixelBytes))
                                                      : nullptr;
                const BeautyChangeTiles where{binned ? s.beauty_tile_offsets.data() : nullptr, params.tiles_x,
                                              int(decals)};
                unpackBeautyPlanes(*beauty, frame.width, frame.height, where, beauty_result, light_result);
                changes.endDownload(queue);
                if (light_back) s.light.endDownload(queue);
            }
            queue.finish();
            if (s.profiling) {
                stats.shading_ms = eventMs(e_shade) + (clean_plane ? eventMs(e_clean) : 0.0);
                if (!occlusion.occluders.empty()) stats.occlusion_ms = eventMs(e_occlusion);
                for (const cl::Event& e : e_rest) stats.rest_ms += eventMs(e);
                if (binned) {
                    stats.tile_bounds_ms = eventMs(e_tiles);
                    stats.bin_coarse_ms = eventMs(e_bounds) + eventMs(e_cdepth) + eventMs(e_cclear) + eventMs(e_cmask) +
                                          eventMs(e_ccount) + eventMs(e_cscan) + eventMs(e_cfill);
                    stats.bin_count_ms = eventMs(e_count);
                    stats.bin_scan_ms = eventMs(e_scan);
                    stats.bin_fill_ms = eventMs(e_fill);
                    stats.binning_ms = stats.bin_coarse_ms + stats.bin_count_ms + stats.bin_scan_ms + stats.bin_fill_ms;
                }
            }
            break;
        }
        s.has_binning = binned;
        s.bin_entries = binned ? s.totals[1] : 0;
        stats.bin_entries = s.bin_entries;
        s.tiles_x = params.tiles_x;
        s.tiles_y = params.tiles_y;
    } catch (const cl::Error& e) {
        finishQuietly(queue);
        throw deviceError(fmt::format("{}: {} failed: {}", device_.info().name, e.what(), clErrorName(e.err())));
    } catch (...) {
        finishQuietly(queue);
        throw;
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
    cl::CommandQueue& queue = s.queue;
    queue.enqueueReadBuffer(s.tile_depth, CL_TRUE, 0, r.tile_depth.size() * sizeof(float), r.tile_depth.data());
    queue.enqueueReadBuffer(s.tile_offsets, CL_TRUE, 0, r.tile_offsets.size() * sizeof(int), r.tile_offsets.data());
    if (!r.tile_decals.empty())
        queue.enqueueReadBuffer(s.tile_decals, CL_TRUE, 0, r.tile_decals.size() * sizeof(int), r.tile_decals.data());
    return r;
}

}  // namespace decalcomp
