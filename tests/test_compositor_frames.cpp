// The compositor across frames: device memory kept between frames of different sizes and decal
// counts, tile lists that outgrow their first capacity (the frame runs again, nothing dropped),
// and in-place shading that leaves untouched pixels bit for bit; packing on the calling thread
// alone (CompositeOptions::host_threads).
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <thread>

#include "decalcomp/compositor.hpp"
#include "decalcomp/synth.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

struct SynthFrame {
    Camera camera;
    GBuffer gbuffer;
};

SynthFrame renderFrame(int width, int height) {
    SynthFrame f;
    f.camera = synth::demoCamera(width, height);
    f.gbuffer = synth::render(synth::demoScene(), f.camera, synth::RenderOptions{width, height});
    return f;
}

DecalScene scatter(const SynthFrame& f, int count, double min_size, double max_size, std::uint32_t seed) {
    synth::ScatterOptions options;
    options.count = count;
    options.min_size = min_size;
    options.max_size = max_size;
    options.seed = seed;
    return synth::scatterDecals(f.gbuffer, f.camera, options);
}

bool sameBits(const Plane& a, const Plane& b) {
    return a.samples.size() == b.samples.size() &&
           std::memcmp(a.samples.data(), b.samples.data(), a.samples.size() * sizeof(float)) == 0;
}

GBuffer compositeOnce(const DecalScene& scene, const SynthFrame& f, bool binned) {
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    GBuffer g = f.gbuffer;
    compositor.composite(g, f.camera, CompositeOptions{binned});
    return g;
}

// Big decals over a 512x512 frame: far more tile-decal pairs than the lists' first capacity.
TEST(CompositorFrames, OverflowingTileListsRunAgainAndMatchUnbinned) {
    const SynthFrame f = renderFrame(512, 512);
    const DecalScene scene = scatter(f, 400, 3.0, 6.0, 7);
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    GBuffer binned = f.gbuffer;
    const CompositeStats stats = compositor.composite(binned, f.camera, CompositeOptions{true});
    ASSERT_GT(stats.bin_entries, 100000);  // well past the first capacity (tiles*4 + decals*16)*1.5
    const BinningResult lists = compositor.lastBinning();
    EXPECT_EQ(std::int64_t(lists.tile_decals.size()), stats.bin_entries);
    EXPECT_EQ(std::int64_t(lists.tile_offsets.back()), stats.bin_entries);
    const GBuffer unbinned = compositeOnce(scene, f, false);
    EXPECT_TRUE(sameBits(binned.planes.at(Attribute::Albedo), unbinned.planes.at(Attribute::Albedo)));
    EXPECT_FALSE(sameBits(binned.planes.at(Attribute::Albedo), f.gbuffer.planes.at(Attribute::Albedo)));
}

// A batch's workers pack on their own thread (host_threads 1): the same bits as every core's
// packing, with normals and a roughness plane packed and unpacked too; OpenMP's setting is the
// caller's again afterwards, and other threads never see it change.
TEST(CompositorFrames, OneHostThreadPacksWhatEveryCorePacks) {
    SynthFrame f = renderFrame(512, 300);  // past the pixel count from which packing is spread over cores
    f.gbuffer.planes[Attribute::Roughness] = Plane{1, std::vector<float>(f.gbuffer.pixelCount(), 0.25f)};
    DecalScene scene = scatter(f, 60, 0.5, 2.0, 5);
    for (Decal& d : scene.decals) {
        d.angle_fade_deg = {60.0, 80.0};  // needs the normals uploaded
        d.effect(DecalTarget::Roughness) = TargetEffect{1.0f, BlendOp::Replace, glm::vec3(0.75f)};
    }
    const int before = omp_get_max_threads();
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    GBuffer every = f.gbuffer, one = f.gbuffer;
    compositor.composite(every, f.camera, CompositeOptions{});
    CompositeOptions single;
    single.host_threads = 1;
    int seen_elsewhere = 0;
    std::thread other([&] { seen_elsewhere = omp_get_max_threads(); });
    compositor.composite(one, f.camera, single);
    other.join();
    EXPECT_EQ(omp_get_max_threads(), before);
    EXPECT_EQ(seen_elsewhere, before);
    for (Attribute a : {Attribute::Albedo, Attribute::Normal, Attribute::Roughness}) {
        ASSERT_TRUE(one.has(a));
        EXPECT_TRUE(sameBits(one.planes.at(a), every.planes.at(a))) << attributeName(a);
    }
    EXPECT_FALSE(sameBits(one.planes.at(Attribute::Albedo), f.gbuffer.planes.at(Attribute::Albedo)));
    EXPECT_FALSE(sameBits(one.planes.at(Attribute::Roughness), f.gbuffer.planes.at(Attribute::Roughness)));
}

// One compositor over frames that grow, shrink and change their decals gives what a fresh
// compositor gives for each.
TEST(CompositorFrames, KeptDeviceMemoryGivesWhatAFreshCompositorGives) {
    Compositor kept(test::cpuDevice());
    const std::pair<int, int> sizes[] = {{96, 64}, {200, 150}, {64, 48}, {200, 150}};
    std::uint32_t seed = 1;
    for (const auto& [w, h] : sizes) {
        const SynthFrame f = renderFrame(w, h);
        const DecalScene scene = scatter(f, int(20 * seed), 0.3, 1.5, seed);
        kept.setScene(scene);
        GBuffer g = f.gbuffer;
        kept.composite(g, f.camera);
        const GBuffer fresh = compositeOnce(scene, f, true);
        EXPECT_TRUE(sameBits(g.planes.at(Attribute::Albedo), fresh.planes.at(Attribute::Albedo))) << w << "x" << h;
        ++seed;
    }
}

// Shading works in place: background pixels, even inside a decal's volume, keep every bit (a NaN
// payload included) while the pixels around them change.
TEST(CompositorFrames, UntouchedPixelsKeepTheirBits) {
    SynthFrame f = renderFrame(128, 96);
    Plane& albedo = f.gbuffer.planes.at(Attribute::Albedo);
    const std::uint32_t payload = 0x7fc0beefu;  // a quiet NaN with a payload
    float odd;
    std::memcpy(&odd, &payload, sizeof odd);
    // A background pixel in the middle of the floor, where the decals are: never decaled.
    Plane& depth = f.gbuffer.planes.at(Attribute::Depth);
    const std::size_t sky = std::size_t(48) * 128 + 64;
    depth.samples[sky] = std::numeric_limits<float>::infinity();
    albedo.at(sky, 0) = odd;
    const DecalScene scene = scatter(f, 8, 0.2, 0.4, 3);
    // and one decal over the whole view, so the pixel lies inside a decal's volume
    DecalScene covering = scene;
    covering.decals.push_back(scatter(f, 1, 40.0, 40.0, 5).decals.front());
    const GBuffer out = compositeOnce(covering, f, true);
    const Plane& result = out.planes.at(Attribute::Albedo);
    std::uint32_t bits;
    std::memcpy(&bits, &result.samples[sky * std::size_t(result.components)], sizeof bits);
    EXPECT_EQ(bits, payload);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < result.samples.size(); ++i)
        if (std::memcmp(&result.samples[i], &albedo.samples[i], sizeof(float)) != 0) ++changed;
    EXPECT_GT(changed, 0u);
}

// Pinned staging in runs of rows (what a GPU gets) and mapped buffers (PoCL's default) give the
// same bits, for depth and for position-pass frames large enough to be sent in several runs.
TEST(CompositorFrames, PinnedRunsAndMappedBuffersAgree) {
    for (DepthConvention convention : {DepthConvention::Planar, DepthConvention::Position}) {
        SynthFrame f = renderFrame(1280, 840);  // over 2^20 pixels: 8 runs
        f.gbuffer.depth_convention = convention;
        const DecalScene scene = scatter(f, 200, 0.3, 1.5, 11);
        std::array<GBuffer, 2> results;
        int k = 0;
        for (const char* staging : {"pinned", "mapped"}) {
            ::setenv("DECALCOMP_STAGING", staging, 1);
            results[std::size_t(k++)] = compositeOnce(scene, f, true);
        }
        ::unsetenv("DECALCOMP_STAGING");
        EXPECT_TRUE(sameBits(results[0].planes.at(Attribute::Albedo), results[1].planes.at(Attribute::Albedo)))
            << depthConventionName(convention);
        EXPECT_FALSE(sameBits(results[0].planes.at(Attribute::Albedo), f.gbuffer.planes.at(Attribute::Albedo)));
    }
}

}  // namespace
}  // namespace decalcomp
