#pragma once
// Composites a decal scene into G-buffer frames on an OpenCL device.
#include <cstdint>
#include <memory>
#include <vector>

#include "decalcomp/beauty.hpp"
#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// Binning's per-tile kernels (tile bounds, coarse counts, tile tests): a work-group per tile, or a
// work-item per tile (CPUs, whose work-group barriers cost more than the walk). Device: what was
// measured fastest on the device's type: a work-item per tile on CPUs; on GPUs the grouped coarse
// counts, and the grouped tile bounds and tests on frames with few tiles per compute unit.
enum class TileKernels { Device, Groups, Serial };
// How filtered frames' window scans (kernels/clean_depth.h) learn which neighbours are clean: from a
// plane a pass fills for every pixel first (GPUs: the scans' chains of loads shrink 5-fold), or by
// testing each neighbour's 4-neighbours (CPUs: the scans are rare and the pass costs more); Device
// picks by the device type.
enum class CleanDepths { Device, Plane, Scan };

struct CompositeOptions {
    bool binned = true;                              // false: every pixel tests every decal (for tests and benchmarks)
    TileKernels tile_kernels = TileKernels::Device;  // the same lists either way (tests compare them)
    CleanDepths clean_depths = CleanDepths::Device;  // the same results either way (tests compare them)
    // Threads that pack the planes into the device's staging memory and back: 0 = OpenMP's default
    // (every core), 1 = the calling thread alone. Where several compositors run at once (a batch's
    // workers), the frames are the parallelism, and each pack's team of threads would only spin in
    // the others' way once it is done.
    int host_threads = 0;
};

struct CompositeStats {
    int decals = 0;
    int tiles = 0;
    std::int64_t bin_entries = 0;  // sum over tiles of the tile's decal count
    // Device time from profiling events, milliseconds (shading: with filtered frames' clean-depth pass).
    double tile_bounds_ms = 0, binning_ms = 0, shading_ms = 0;
    // binning_ms in its steps: decal bounds and the coarse lists (level 1), the tiles' tests and
    // counts, their prefix sum, and the tile lists' fill
    double bin_coarse_ms = 0, bin_count_ms = 0, bin_scan_ms = 0, bin_fill_ms = 0;
    double occlusion_ms = 0;  // building blast occlusion maps (0 when no decal occludes)
    double rest_ms = 0;       // texture-space decals' rest pass (0 without them)
    double totalKernelMs() const { return tile_bounds_ms + binning_ms + shading_ms + occlusion_ms + rest_ms; }
};

// What the binning produced for the last frame, for tests and `--stats`.
struct BinningResult {
    int tiles_x = 0, tiles_y = 0;
    std::vector<float> tile_depth;  // min, max planar depth per tile; min > max for empty tiles
    std::vector<int> tile_offsets;  // tiles + 1 entries
    std::vector<int> tile_decals;   // decal indices, per tile in scene order
};

// The attributes composite() may change for a scene: the albedo, and each material attribute
// some decal affects (decalAffects). Callers write exactly these back to their files.
std::vector<Attribute> compositedAttributes(const DecalScene& scene);

class Compositor {
public:
    explicit Compositor(ComputeDevice& device);
    ~Compositor();
    Compositor(const Compositor&) = delete;
    Compositor& operator=(const Compositor&) = delete;

    // Uploads the scene's textures once; decals are re-prepared per frame (they depend on the camera).
    void setScene(const DecalScene& scene);
    // Replaces the decals only, keeping the uploaded textures and masks (animated sequences: the
    // decals change per frame, their textures do not). Throws Error(Input) for indices out of range.
    void setDecals(const std::vector<Decal>& decals);

    // Blends the scene's decals into the frame's material planes in place (albedo, and the normal,
    // roughness, metallic, ao and emission planes the frame has and some decal changes).
    // The frame needs an albedo plane and a depth or position plane matching its depth convention.
    // With `beauty`, the shading kernel also rebuilds the beauty (and rewrites multiplied light
    // terms) at the pixels some decal changed (beauty.hpp). Throws Error(Input/Device).
    CompositeStats composite(GBuffer& frame, const Camera& camera, const CompositeOptions& options = {},
                             BeautyPlanes* beauty = nullptr);

    // Tile depth ranges and per-tile lists of the last binned composite (downloaded on request).
    BinningResult lastBinning();

private:
    struct State;
    ComputeDevice& device_;
    std::unique_ptr<State> state_;
};

}  // namespace decalcomp
