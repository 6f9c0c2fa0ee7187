// decalcomp-bench: times the compositor's kernels on synthetic G-buffers, binned and unbinned.
//
// For every frame size and decal count it renders the demo scene, scatters small decals on its
// visible surfaces, composites once to warm up, then `--repeat` times, and reports medians of the
// device kernel time (OpenCL profiling events: tile bounds + binning + shading) and of the wall time
// of Compositor::composite() (which includes uploads and the download). Links only decalcomp_core,
// so it runs wherever an OpenCL ICD is installed (docs/benchmarks.md).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bake.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_light.hpp"
#include "median.hpp"
#include "texture_space.hpp"
#include "transfers.hpp"

namespace {

using namespace decalcomp;

// Screen tile edge (DC_TILE_SIZE in kernels/shared_types.h, not a public header); runCase checks it
// against CompositeStats::tiles.
constexpr int kTileSize = 16;

struct FrameSize {
    int width = 0, height = 0;
};

FrameSize parseSize(const std::string& text) {
    const auto x = text.find_first_of("xX");
    try {
        if (x != std::string::npos) {
            std::size_t used_w = 0, used_h = 0;
            const int w = std::stoi(text.substr(0, x), &used_w);
            const int h = std::stoi(text.substr(x + 1), &used_h);
            if (used_w == x && used_h == text.size() - x - 1 && w > 0 && h > 0) return {w, h};
        }
    } catch (const std::exception&) {
    }
    throw Error(ErrorKind::Usage, fmt::format("--sizes: '{}' is not WIDTHxHEIGHT", text));
}

using bench::median;

struct Result {
    FrameSize size;
    int decals = 0;
    bool binned = true;
    bool skipped = false;
    double kernel_ms = 0, tile_bounds_ms = 0, binning_ms = 0, shading_ms = 0, wall_ms = 0;
    double kernel_min_ms = 0, kernel_max_ms = 0;
    double bin_coarse_ms = 0, bin_count_ms = 0, bin_scan_ms = 0, bin_fill_ms = 0;  // binning_ms's steps
    // outputHash of the first composite
    std::uint64_t output_hash = 0;
    std::int64_t bin_entries = 0;
    int tiles = 0;
    int max_per_tile = 0;      // longest tile list (binned)
    double mean_per_tile = 0;  // mean list length over all tiles (binned)
};

struct Options {
    std::string device;
    std::vector<std::string> sizes{"1920x1080", "3840x2160"};
    std::vector<int> counts{1, 64, 1024, 4096};
    int repeat = 5;
    bool quick = false;
    std::string csv;  // file, "-" = stdout instead of the table
    double max_unbinned_work = 1920.0 * 1080.0 * 4096.0;
    double min_size = 0.1, max_size = 0.4;
    double same_coverage = 0;  // > 0: each count's decals share the area of one decal of this edge
    int texture_count = 4, texture_size = 32;
    std::uint32_t seed = 1;
    std::string modes = "both";           // both, binned, unbinned
    std::string kind = "box";             // decal kind of every decal
    bool materials = false;               // full texture sets: normal maps and ORM into normal/roughness/metallic
    bool transfers = true;                // measure the transfer and bandwidth floors per size
    bool beauty = false;                  // also rebuild a beauty from two light terms (synth_light.hpp)
    std::string pixel_filter = "none";    // decals integrated over this pixel filter (pixel_filter.hpp)
    std::string tile_kernels = "device";  // binning's per-tile kernels (CompositeOptions::tile_kernels)
    std::string clean_depths = "device";  // filtered frames' clean neighbours (CompositeOptions::clean_depths)
};

// The beauty update's planes for a frame: the synthetic sun and sky, divided (Blender-style).
BeautyPlanes benchBeautyPlanes(const GBuffer& full) {
    const synth::LightPasses light = synth::lightPasses(full);
    BeautyPlanes planes;
    planes.beauty = {3, std::vector<float>(full.pixelCount() * 3)};
    for (std::size_t i = 0; i < full.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) planes.beauty.at(i, c) = light.beauty.at(i, c);
    planes.light = {light.direct, light.indirect};
    planes.direct_terms = 1;
    planes.summed_terms = 2;
    return planes;
}

TileKernels tileKernels(const std::string& name) {
    return name == "groups" ? TileKernels::Groups : name == "serial" ? TileKernels::Serial : TileKernels::Device;
}

CleanDepths cleanDepths(const std::string& name) {
    return name == "plane" ? CleanDepths::Plane : name == "scan" ? CleanDepths::Scan : CleanDepths::Device;
}

// FNV-1a over the bits of a composite's planes and its beauty: the same for devices, drivers and
// build options that leave the arithmetic alone. The GPU machine runs the bench but not the
// command line, so its outputs are compared through this (CSV column output_hash).
std::uint64_t outputHash(const GBuffer& frame, const BeautyPlanes* beauty) {
    std::uint64_t hash = 0xcbf29ce484222325ull;
    const auto add = [&](const Plane& plane) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(plane.samples.data());
        for (std::size_t i = 0; i < plane.samples.size() * sizeof(float); ++i)
            hash = (hash ^ bytes[i]) * 0x100000001b3ull;
    };
    for (const auto& [attribute, plane] : frame.planes) add(plane);
    if (beauty) add(beauty->beauty);
    return hash;
}

Result runCase(Compositor& compositor, const GBuffer& frame, const Camera& camera, int decals, int repeat,
               const BeautyPlanes* beauty, const CompositeOptions& options) {
    Result r;
    r.size = {frame.width, frame.height};
    r.decals = decals;
    r.binned = options.binned;
    const Plane pristine = frame.planes.at(Attribute::Albedo);
    GBuffer work = frame;
    std::optional<BeautyPlanes> work_beauty;
    if (beauty) work_beauty = *beauty;

    // Warm-up: first launches, allocations, lazy compilation in some drivers, and a filtered frame's
    // shading program on first use (its cold build is a figure of its own: said when it is long).
    const auto warm0 = std::chrono::steady_clock::now();
    CompositeStats warm = compositor.composite(work, camera, options, work_beauty ? &*work_beauty : nullptr);
    const double warm_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - warm0).count();
    r.output_hash = outputHash(work, work_beauty ? &*work_beauty : nullptr);
    if (warm_s > 1.0)
        fmt::print(stderr, "{}x{}, {} decals: the warm-up composite took {:.1f} s (a program's build on first use)\n",
                   frame.width, frame.height, decals, warm_s);
    r.tiles = warm.tiles;
    const int expected_tiles =
        ((frame.width + kTileSize - 1) / kTileSize) * ((frame.height + kTileSize - 1) / kTileSize);
    if (warm.tiles != expected_tiles)
        fmt::print(stderr, "warning: {} tiles, expected {} for {}-pixel tiles; test ratios are off\n", warm.tiles,
                   expected_tiles, kTileSize);
    r.bin_entries = warm.bin_entries;
    if (options.binned) {
        const BinningResult b = compositor.lastBinning();
        const std::size_t tiles = std::size_t(b.tiles_x) * std::size_t(b.tiles_y);
        for (std::size_t t = 0; t < tiles && t + 1 < b.tile_offsets.size(); ++t)
            r.max_per_tile = std::max(r.max_per_tile, b.tile_offsets[t + 1] - b.tile_offsets[t]);
        r.mean_per_tile = tiles ? double(r.bin_entries) / double(tiles) : 0.0;
    }

    std::vector<double> kernel, tile_bounds, binning, shading, wall, coarse, count, scan, fill;
    for (int i = 0; i < repeat; ++i) {
        work.planes.at(Attribute::Albedo) = pristine;  // same input every repetition, not timed
        if (beauty) *work_beauty = *beauty;
        const auto t0 = std::chrono::steady_clock::now();
        const CompositeStats s = compositor.composite(work, camera, options, work_beauty ? &*work_beauty : nullptr);
        const auto t1 = std::chrono::steady_clock::now();
        kernel.push_back(s.totalKernelMs());
        tile_bounds.push_back(s.tile_bounds_ms);
        binning.push_back(s.binning_ms);
        coarse.push_back(s.bin_coarse_ms);
        count.push_back(s.bin_count_ms);
        scan.push_back(s.bin_scan_ms);
        fill.push_back(s.bin_fill_ms);
        shading.push_back(s.shading_ms);
        wall.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        if (s.bin_entries != r.bin_entries)
            throw deviceError(
                fmt::format("bin entries changed between repetitions: {} then {}", r.bin_entries, s.bin_entries));
    }
    r.kernel_ms = median(kernel);
    r.kernel_min_ms = *std::min_element(kernel.begin(), kernel.end());
    r.kernel_max_ms = *std::max_element(kernel.begin(), kernel.end());
    r.tile_bounds_ms = median(tile_bounds);
    r.binning_ms = median(binning);
    r.bin_coarse_ms = median(coarse);
    r.bin_count_ms = median(count);
    r.bin_scan_ms = median(scan);
    r.bin_fill_ms = median(fill);
    r.shading_ms = median(shading);
    r.wall_ms = median(wall);
    return r;
}

const Result* find(const std::vector<Result>& results, int w, int h, int decals, bool binned) {
    for (const auto& r : results)
        if (r.size.width == w && r.size.height == h && r.decals == decals && r.binned == binned && !r.skipped)
            return &r;
    return nullptr;
}

std::string ms(double v) {
    return v >= 100 ? fmt::format("{:.1f}", v) : v >= 1 ? fmt::format("{:.2f}", v) : fmt::format("{:.3f}", v);
}

void printTable(const std::vector<Result>& results, std::FILE* out) {
    fmt::print(out, "{:>9} {:>6} {:>8} | {:>10} {:>8} {:>8} {:>10} | {:>10} | {:>10} {:>8} {:>8} | {:>9}\n", "size",
               "decals", "mode", "kernel ms", "tilebnd", "binning", "shading", "wall ms", "bin entr.", "mean/t",
               "max/t", "speedup");
    fmt::print(out, "{}\n", std::string(130, '-'));
    for (const auto& r : results) {
        const std::string size = fmt::format("{}x{}", r.size.width, r.size.height);
        const char* mode = r.binned ? "binned" : "unbinned";
        if (r.skipped) {
            fmt::print(out, "{:>9} {:>6} {:>8} | {:>10} {:>8} {:>8} {:>10} | {:>10} | {:>10} {:>8} {:>8} | {:>9}\n",
                       size, r.decals, mode, "skipped", "", "", "", "skipped", "", "", "", "");
            continue;
        }
        std::string speedup;
        if (r.binned)
            if (const Result* u = find(results, r.size.width, r.size.height, r.decals, false); u && r.kernel_ms > 0)
                speedup = fmt::format("{:.1f}x", u->kernel_ms / r.kernel_ms);
        fmt::print(out, "{:>9} {:>6} {:>8} | {:>10} {:>8} {:>8} {:>10} | {:>10} | {:>10} {:>8} {:>8} | {:>9}\n", size,
                   r.decals, mode, ms(r.kernel_ms), r.binned ? ms(r.tile_bounds_ms) : "-",
                   r.binned ? ms(r.binning_ms) : "-", ms(r.shading_ms), ms(r.wall_ms),
                   r.binned ? fmt::format("{}", r.bin_entries) : "-",
                   r.binned ? fmt::format("{:.2f}", r.mean_per_tile) : "-",
                   r.binned ? fmt::format("{}", r.max_per_tile) : "-", speedup);
    }
}

void writeCsv(const std::vector<Result>& results, std::ostream& out) {
    out << "width,height,decals,mode,status,kernel_ms,kernel_min_ms,kernel_max_ms,tile_bounds_ms,binning_ms,"
           "shading_ms,wall_ms,tiles,bin_entries,mean_per_tile,max_per_tile,bin_coarse_ms,bin_count_ms,bin_scan_ms,"
           "bin_fill_ms,output_hash\n";
    for (const auto& r : results) {
        out << fmt::format("{},{},{},{},{}", r.size.width, r.size.height, r.decals, r.binned ? "binned" : "unbinned",
                           r.skipped ? "skipped" : "ok");
        if (r.skipped) {
            out << ",,,,,,,,,,,,,,,,\n";
            continue;
        }
        out << fmt::format(
            ",{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{},{},{:.3f},{},{:.4f},{:.4f},{:.4f},{:.4f},{:016x}\n",
            r.kernel_ms, r.kernel_min_ms, r.kernel_max_ms, r.tile_bounds_ms, r.binning_ms, r.shading_ms, r.wall_ms,
            r.tiles, r.binned ? r.bin_entries : 0, r.mean_per_tile, r.max_per_tile, r.bin_coarse_ms, r.bin_count_ms,
            r.bin_scan_ms, r.bin_fill_ms, r.output_hash);
    }
}

void printHeadline(const std::vector<Result>& results, std::FILE* out) {
    fmt::print(out, "\nHeadline (1920x1080, median device kernel time):\n");
    for (int n : {1024, 4096}) {
        const Result* b = find(results, 1920, 1080, n, true);
        const Result* u = find(results, 1920, 1080, n, false);
        if (b && u && b->kernel_ms > 0) {
            // Pixel-decal box tests: every pixel x every decal unbinned; at most the tile's pixels x its
            // list length binned. Their ratio bounds what binning can gain in the shading kernel.
            const double tests_unbinned = double(u->size.width) * u->size.height * n;
            const double tests_binned = double(b->bin_entries) * kTileSize * kTileSize;
            fmt::print(out,
                       "  {:>4} decals: unbinned / binned = {:.1f}x  ({} ms vs {} ms; shading alone {:.1f}x; "
                       "pixel-decal tests {:.1f}x fewer binned)\n",
                       n, u->kernel_ms / b->kernel_ms, ms(u->kernel_ms), ms(b->kernel_ms),
                       b->shading_ms > 0 ? u->shading_ms / b->shading_ms : 0.0,
                       tests_binned > 0 ? tests_unbinned / tests_binned : 0.0);
        } else {
            fmt::print(out, "  {:>4} decals: unbinned / binned = n/a ({} not run or skipped)\n", n,
                       !b && !u ? "binned and unbinned"
                       : !b     ? "binned"
                                : "unbinned");
        }
    }
    const Result* b1 = find(results, 1920, 1080, 1, true);
    const Result* b4096 = find(results, 1920, 1080, 4096, true);
    if (b1 && b4096 && b1->kernel_ms > 0)
        fmt::print(out, "  binned 4096 decals / binned 1 decal = {:.2f}x  ({} ms vs {} ms)\n",
                   b4096->kernel_ms / b1->kernel_ms, ms(b4096->kernel_ms), ms(b1->kernel_ms));
    else
        fmt::print(out, "  binned 4096 decals / binned 1 decal = n/a (not run)\n");
}

// composite() and its kernels against what they must move, per frame size (albedo-only scenes:
// depth and the (albedo, roughness) float4 group up, the group down; the kernels read both and
// write the group at most once).
void printFloors(const std::vector<Result>& results, const FrameSize& size, const bench::TransferRates& t,
                 std::FILE* out) {
    const double pixels = double(size.width) * size.height;
    const double up = pixels * (4 + 16), down = pixels * 16;
    const double pinned_ms = 1e-6 * (up / t.upload_pinned_gbs + down / t.download_pinned_gbs);
    const double pageable_ms = 1e-6 * (up / t.upload_pageable_gbs + down / t.download_pageable_gbs);
    const double kernel_floor_ms = 1e-6 * (pixels * (4 + 16 + 16)) / t.buffer_copy_gbs;
    fmt::print(out,
               "\n{}x{} floors: upload {:.1f} GB/s pinned, {:.1f} pageable; download {:.1f} pinned, {:.1f} pageable; "
               "device copy {:.0f} GB/s buffers, {:.0f} GB/s images (pinned upload into an image {:.1f} GB/s)\n",
               size.width, size.height, t.upload_pinned_gbs, t.upload_pageable_gbs, t.download_pinned_gbs,
               t.download_pageable_gbs, t.buffer_copy_gbs, t.image_copy_gbs, t.image_upload_gbs);
    fmt::print(out, "  planes moved: {:.1f} MB up, {:.1f} MB down = {} ms pinned, {} ms pageable; kernel floor {} ms\n",
               up * 1e-6, down * 1e-6, ms(pinned_ms), ms(pageable_ms), ms(kernel_floor_ms));
    for (const Result& r : results) {
        if (r.skipped || !r.binned || r.size.width != size.width || r.size.height != size.height) continue;
        fmt::print(out,
                   "  {:>5} decals binned: composite() {} ms = {:.2f}x pinned floor, {:.2f}x pageable; kernels {} ms = "
                   "{:.1f}x kernel floor\n",
                   r.decals, ms(r.wall_ms), r.wall_ms / pinned_ms, r.wall_ms / pageable_ms, ms(r.kernel_ms),
                   r.kernel_ms / kernel_floor_ms);
    }
    const Result* one = find(results, size.width, size.height, 1, true);
    const Result* many = find(results, size.width, size.height, 4096, true);
    if (one && many && one->kernel_ms > 0)
        fmt::print(out, "  binned kernels 4096 decals / 1 decal = {:.2f}x\n", many->kernel_ms / one->kernel_ms);
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    CLI::App app{"decalcomp-bench: kernel timings of the decal compositor on synthetic G-buffers"};
    app.add_option("--device", opt.device,
                   "OpenCL device: \"\" = first GPU else CPU, an index, gpu/cpu, or part of a name/vendor/platform");
    app.add_option("--sizes", opt.sizes, "frame sizes, WIDTHxHEIGHT, comma-separated")->delimiter(',');
    app.add_option("--counts", opt.counts, "decal counts, comma-separated")->delimiter(',')->check(CLI::PositiveNumber);
    app.add_option("--repeat", opt.repeat, "timed repetitions per case (median reported)")->check(CLI::PositiveNumber);
    app.add_flag("--quick", opt.quick, "CI-sized run: 480x270 with 1 and 64 decals");
    app.add_option("--csv", opt.csv, "also write the results as CSV to this file (\"-\": CSV on stdout, no table)");
    app.add_option("--max-unbinned-work", opt.max_unbinned_work,
                   "skip unbinned cases with pixels x decals above this (default 1920*1080*4096)");
    app.add_option("--modes", opt.modes, "both, binned or unbinned")
        ->check(CLI::IsMember({"both", "binned", "unbinned"}));
    app.add_option("--min-size", opt.min_size, "smallest decal edge, world units (demo scene is ~10 units across)");
    app.add_option("--max-size", opt.max_size, "largest decal edge, world units");
    app.add_option("--same-coverage", opt.same_coverage,
                   "instead of --min-size/--max-size: every count's decals together cover the area of one decal "
                   "of this edge (world units): N decals of edge EDGE / sqrt(N), so that 1 and 4096 decals do the "
                   "same number of pixel-decal lookups (issue 9's \"same coverage\")")
        ->check(CLI::PositiveNumber);
    app.add_option("--textures", opt.texture_count, "procedural textures")->check(CLI::PositiveNumber);
    app.add_option("--texture-size", opt.texture_size, "texture edge, texels")->check(CLI::PositiveNumber);
    app.add_option("--seed", opt.seed, "decal scatter seed");
    app.add_flag("--materials", opt.materials,
                 "every decal also carries a normal map and an ORM map, written into the frame's normal, "
                 "roughness and metallic planes (default: albedo only)");
    app.add_option("--kind", opt.kind, "decal kind of every decal")
        ->check(CLI::IsMember({"box", "volume", "frustum", "cube"}));
    app.add_flag("--beauty", opt.beauty,
                 "also rebuild a beauty from a direct and an indirect light term in the shading kernel");
    app.add_option("--pixel-filter", opt.pixel_filter,
                   "integrate decals over this pixel filter (TYPE:WIDTH, e.g. blackman-harris:3; default none); the "
                   "frames then keep their normal pass, as renders with a filter have one");
    app.add_option(
           "--tile-kernels", opt.tile_kernels,
           "binning's per-tile kernels: device (by the device: work-items on CPUs; on GPUs grouped coarse counts, "
           "and grouped tile bounds and tests on frames with few tiles per compute unit), groups or serial")
        ->check(CLI::IsMember({"device", "groups", "serial"}));
    app.add_option("--clean-depths", opt.clean_depths,
                   "how filtered frames' silhouette and crease scans learn which neighbours are clean: device (a "
                   "plane filled first on GPUs, each neighbour tested on CPUs), plane or scan")
        ->check(CLI::IsMember({"device", "plane", "scan"}));
    bool texture_space = false;
    app.add_flag("--texture-space", texture_space,
                 "instead: a texture-space box decal on a 102,400-triangle tube against the same box in the world "
                 "(same pixels), at the first --sizes entry");
    bool bake = false;
    app.add_flag("--bake", bake,
                 "instead: the texture-space bake kernel on the 102,400-triangle tube at 1024² and 2048², then the "
                 "decal in bake mode, exact mode and as a world box (same pixels), at the first --sizes entry");
    bool no_transfers = false;
    app.add_flag("--no-transfers", no_transfers, "skip measuring the transfer and bandwidth floors");
    bool list = false;
    app.add_flag("--list-devices", list, "list OpenCL devices and exit");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        if (list) {
            for (const auto& d : listDevices())
                fmt::print("{}: {} ({}, {}, {})\n", d.index, d.name, d.type, d.platform, d.version);
            return 0;
        }
        opt.transfers = !no_transfers;
        if (opt.quick) {
            if (app.count("--sizes") == 0) opt.sizes = {"480x270"};
            if (app.count("--counts") == 0) opt.counts = {1, 64};
        }
        std::vector<FrameSize> sizes;
        for (const auto& s : opt.sizes) sizes.push_back(parseSize(s));
        if (opt.min_size <= 0 || opt.max_size < opt.min_size)
            throw Error(ErrorKind::Usage, "--min-size/--max-size: need 0 < min <= max");

        const bool csv_stdout = opt.csv == "-";
        std::FILE* info = csv_stdout ? stderr : stdout;

        ComputeDevice device(opt.device);
        const DeviceInfo& di = device.info();
        fmt::print(info, "device: {} ({}, {}, {}; {} compute units, {} MHz)\n", di.name, di.type, di.platform,
                   di.version, di.device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>(),
                   di.device.getInfo<CL_DEVICE_MAX_CLOCK_FREQUENCY>());
        if (opt.same_coverage > 0)
            fmt::print(info, "decals: N of edge {} / sqrt(N) world units (the same coverage for every count)",
                       opt.same_coverage);
        else
            fmt::print(info, "decals: {}-{} world units", opt.min_size, opt.max_size);
        fmt::print(info, ", {} textures of {}^2 texels, seed {}; repeat {} (median), 1 warm-up\n", opt.texture_count,
                   opt.texture_size, opt.seed, opt.repeat);
        if (std::ifstream loadavg("/proc/loadavg"); loadavg) {
            std::string line;
            std::getline(loadavg, line);
            fmt::print(info, "host load average (1/5/15 min, runnable/threads, last pid): {}\n", line);
        }
        std::fflush(info);

        const auto build0 = std::chrono::steady_clock::now();
        // binning and the point-sampled shading; a filtered frame's shading program builds in the
        // first case's warm-up (ComputeDevice::shadingProgram)
        device.program();
        Compositor compositor(device);
        fmt::print(info, "program build (binning, point-sampled shading): {:.0f} ms\n\n",
                   std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - build0).count());

        if (bake) {
            bench::benchBake(device, compositor, sizes.front().width, sizes.front().height, opt.repeat, info);
            return 0;
        }
        if (texture_space) {
            bench::benchTextureSpace(compositor, sizes.front().width, sizes.front().height, opt.repeat, info);
            return 0;
        }
        const synth::Scene scene = synth::demoScene();
        std::vector<Result> results;
        for (const FrameSize& size : sizes) {
            const Camera camera = synth::demoCamera(size.width, size.height);
            GBuffer full = synth::render(scene, camera, synth::RenderOptions{size.width, size.height});
            const std::optional<BeautyPlanes> beauty_planes =
                opt.beauty ? std::optional<BeautyPlanes>(benchBeautyPlanes(full)) : std::nullopt;
            for (int count : opt.counts) {
                synth::ScatterOptions scatter;
                scatter.count = count;
                scatter.min_size = opt.min_size;
                scatter.max_size = opt.max_size;
                if (opt.same_coverage > 0) scatter.min_size = scatter.max_size = opt.same_coverage / std::sqrt(count);
                scatter.texture_count = opt.texture_count;
                scatter.texture_size = opt.texture_size;
                scatter.seed = opt.seed;
                DecalScene decal_scene = synth::scatterDecals(full, camera, scatter);
                const DecalKind kinds[] = {DecalKind::Box, DecalKind::Volume, DecalKind::Frustum, DecalKind::Cube};
                for (DecalKind k : kinds)
                    if (opt.kind == decalKindName(k)) synth::convertDecals(decal_scene, k, opt.seed);
                if (opt.materials)  // the procedural textures stand in for normal and ORM maps
                    for (Decal& d : decal_scene.decals) {
                        d.normal_texture = d.albedo_texture;
                        d.orm_texture = (d.albedo_texture + 1) % int(decal_scene.textures.size());
                    }
                compositor.setScene(decal_scene);
                // Keep only the planes the compositor reads, so frame copies stay cheap.
                GBuffer frame = full;
                frame.pixel_filter = parsePixelFilter(opt.pixel_filter, "--pixel-filter");
                auto used = [&](Attribute a) {
                    if (a == Attribute::Depth || a == Attribute::Albedo) return true;
                    if (a == Attribute::Normal && frame.pixel_filter.enabled()) return true;
                    return opt.materials &&
                           (a == Attribute::Normal || a == Attribute::Roughness || a == Attribute::Metallic);
                };
                for (auto it = frame.planes.begin(); it != frame.planes.end();)
                    it = used(it->first) ? std::next(it) : frame.planes.erase(it);
                for (bool binned : {true, false}) {
                    if ((binned && opt.modes == "unbinned") || (!binned && opt.modes == "binned")) continue;
                    fmt::print(info, "  {}x{} {:>5} decals {:<8} ...", size.width, size.height, count,
                               binned ? "binned" : "unbinned");
                    std::fflush(info);
                    const double work = double(size.width) * size.height * count;
                    if (!binned && work > opt.max_unbinned_work) {
                        Result r;
                        r.size = size;
                        r.decals = count;
                        r.binned = false;
                        r.skipped = true;
                        results.push_back(r);
                        fmt::print(info, " skipped (pixels x decals {:.3g} > --max-unbinned-work {:.3g})\n", work,
                                   opt.max_unbinned_work);
                        continue;
                    }
                    const auto t0 = std::chrono::steady_clock::now();
                    CompositeOptions options;
                    options.binned = binned;
                    options.tile_kernels = tileKernels(opt.tile_kernels);
                    options.clean_depths = cleanDepths(opt.clean_depths);
                    results.push_back(runCase(compositor, frame, camera, count, opt.repeat,
                                              beauty_planes ? &*beauty_planes : nullptr, options));
                    fmt::print(info, " kernel {} ms ({:.1f} s)\n", ms(results.back().kernel_ms),
                               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                    std::fflush(info);
                }
            }
        }

        if (!opt.csv.empty()) {
            if (csv_stdout) {
                writeCsv(results, std::cout);
            } else {
                std::ofstream file(opt.csv);
                writeCsv(results, file);
                if (!file) throw outputError(fmt::format("--csv {}: cannot write", opt.csv));
            }
        }
        fmt::print(info, "\n");
        if (!csv_stdout) printTable(results, stdout);
        printHeadline(results, info);
        if (opt.transfers)
            for (const FrameSize& size : sizes)
                printFloors(results, size,
                            bench::measureTransfers(device, std::size_t(size.width) * std::size_t(size.height) * 16,
                                                    std::max(3, opt.repeat)),
                            info);
        return 0;
    } catch (const Error& e) {
        fmt::print(stderr, "decalcomp-bench: {}\n", e.what());
        return int(e.kind());
    } catch (const std::exception& e) {
        fmt::print(stderr, "decalcomp-bench: {}\n", e.what());
        return 1;
    }
}
