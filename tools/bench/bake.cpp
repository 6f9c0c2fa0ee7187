#include "bake.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "decalcomp/bake.hpp"
#include "median.hpp"
#include "texture_space.hpp"

namespace decalcomp::bench {

void benchBake(ComputeDevice& device, Compositor& compositor, int width, int height, int repeat, std::FILE* out) {
    TubeBench b = tubeBench(width, height);
    DecalScene& scene = b.scene;
    Decal& decal = scene.decals[0];
    decal.space = DecalSpace::ObjectRest;
    decal.rest_mesh = 0;
    decal.rest_mode = RestMode::Bake;
    decal.bake_dilation = 8;  // the default
    // A 2048² bake takes seconds on a CPU device: at most 3 runs each.
    const int bakes = std::clamp(repeat, 1, 3);
    fmt::print(out, "\ntexture-space bake, {} triangles, dilation {}, median of {}:\n", b.tube.triangles.size(),
               decal.bake_dilation, bakes);
    for (int size : {1024, 2048}) {
        decal.bake_resolution = size;
        std::vector<double> kernel, wall;
        for (int r = 0; r < bakes; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            const BakedLayers layers = bakeDecal(device, scene, decal);
            wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            kernel.push_back(layers.bake_kernel_ms);
        }
        fmt::print(out, "  {}²: bake kernel {:.1f} ms, bakeDecal() {:.1f} ms (apron, uploads, read-back)\n", size,
                   median(kernel), median(wall));
    }
    decal.bake_resolution = 2048;
    const Timing baked = timeFrames(compositor, scene, b.frame, b.camera, repeat);
    decal.rest_mode = RestMode::Exact;
    const Timing exact = timeFrames(compositor, scene, b.frame, b.camera, repeat);
    decal.space = DecalSpace::World;
    decal.rest_mesh = -1;
    const Timing world = timeFrames(compositor, scene, b.frame, b.camera, repeat);
    fmt::print(out, "frame {}x{}, the decal on {} pixels (exact {}, world {}), composite() after the bake:\n", width,
               height, baked.changed, exact.changed, world.changed);
    auto line = [&](const char* name, const Timing& t) {
        fmt::print(out, "  {:<22} kernels {:.3f} ms (rest pass {:.3f}, shading {:.3f}), composite() {:.2f} ms\n", name,
                   t.kernel_ms, t.rest_ms, t.shading_ms, t.wall_ms);
    };
    line("bake mode (2048²):", baked);
    line("exact mode:", exact);
    line("world box:", world);
    if (world.kernel_ms > 0)
        fmt::print(out, "  kernels / world box: bake {:.2f}x, exact {:.2f}x\n", baked.kernel_ms / world.kernel_ms,
                   exact.kernel_ms / world.kernel_ms);
}

}  // namespace decalcomp::bench
