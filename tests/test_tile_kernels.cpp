// Binning's per-tile kernels come in two forms: a work-group per tile (GPUs) and a work-item per
// tile (CPUs). PoCL runs both, so the GPU form is checked here against the CPU form: the same tile
// depths, the same lists in the same order, and the same composited planes bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "decalcomp/compositor.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/synth.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

struct Case {
    const char* name;
    int decals;
    double min_size, max_size;
    const char* pixel_filter;  // "none" or a filter: binning then reaches the tiles' aprons
};

class TileKernelForms : public ::testing::TestWithParam<Case> {};

// Decal counts on both sides of one 64-decal mask chunk and of DC_CHUNK_LANES chunks; small decals
// (few coarse tiles each) and large ones (many); with and without a pixel filter.
INSTANTIATE_TEST_SUITE_P(Scenes, TileKernelForms,
                         ::testing::Values(Case{"one", 1, 0.3, 0.3, "none"}, Case{"few", 40, 0.2, 1.0, "none"},
                                           Case{"chunks", 300, 0.05, 0.6, "none"},
                                           Case{"many_small", 4200, 0.02, 0.08, "none"},
                                           Case{"large", 12, 2.0, 4.0, "none"},
                                           Case{"filtered", 300, 0.05, 0.6, "blackman-harris:3:fast"}),
                         [](const auto& scene) { return std::string(scene.param.name); });

// The frame composited with one form of the per-tile kernels: its binning and planes.
std::pair<BinningResult, GBuffer> compositeWith(TileKernels kind, const GBuffer& frame, const Camera& camera,
                                                const DecalScene& scene) {
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    GBuffer out = frame;
    CompositeOptions options;
    options.tile_kernels = kind;
    compositor.composite(out, camera, options);
    return {compositor.lastBinning(), std::move(out)};
}

TEST_P(TileKernelForms, GroupsAndSerialGiveTheSameListsAndPixels) {
    const Case& c = GetParam();
    const Camera camera = synth::demoCamera(200, 150);
    GBuffer frame = synth::render(synth::demoScene(), camera, {200, 150});
    frame.pixel_filter = parsePixelFilter(c.pixel_filter, "test");
    synth::ScatterOptions scatter{c.decals, c.min_size, c.max_size};
    scatter.seed = 11;
    const DecalScene scene = synth::scatterDecals(frame, camera, scatter);

    const auto [groups, groups_frame] = compositeWith(TileKernels::Groups, frame, camera, scene);
    const auto [serial, serial_frame] = compositeWith(TileKernels::Serial, frame, camera, scene);

    EXPECT_EQ(groups.tile_depth, serial.tile_depth);
    EXPECT_EQ(groups.tile_offsets, serial.tile_offsets);
    EXPECT_EQ(groups.tile_decals, serial.tile_decals);
    EXPECT_GT(serial.tile_decals.size(), 0u);
    const auto& a = groups_frame.planes.at(Attribute::Albedo).samples;
    const auto& b = serial_frame.planes.at(Attribute::Albedo).samples;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
    EXPECT_NE(b, frame.planes.at(Attribute::Albedo).samples) << "no decal reached the frame";
}

// The serial form reads a whole tile row of planar depth as one vector; a frame whose depth pass
// holds every value dc_view_depth refuses (NaN, infinities, zero, negative, nearer than the near
// limit, at the background depth) gives both forms the same tile ranges, empty tiles included.
TEST(TileKernelForms, HostileDepthsGiveTheSameTileRanges) {
    const Camera camera = synth::demoCamera(200, 150);
    GBuffer frame = synth::render(synth::demoScene(), camera, {200, 150});
    ASSERT_EQ(frame.depth_convention, DepthConvention::Planar);
    const float hostile[] = {std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             0.0f,
                             -2.0f,
                             1e-7f,
                             1e10f,
                             3e38f};
    Plane& depth = frame.planes.at(Attribute::Depth);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const int tile = (y / 16) * 13 + x / 16;
            const std::size_t i = std::size_t(y) * frame.width + x;
            if (tile % 3 == 0)
                depth.at(i, 0) = hostile[(x + 3 * y) % 8];  // mixed with valid depths
            else if (tile % 7 == 1)
                depth.at(i, 0) = hostile[(x * y) % 8];  // nothing valid: an empty tile
        }
    synth::ScatterOptions scatter{40, 0.2, 1.0};
    scatter.seed = 5;
    const DecalScene scene =
        synth::scatterDecals(synth::render(synth::demoScene(), camera, {200, 150}), camera, scatter);
    const auto groups = compositeWith(TileKernels::Groups, frame, camera, scene).first.tile_depth;
    const auto serial = compositeWith(TileKernels::Serial, frame, camera, scene).first.tile_depth;
    ASSERT_EQ(groups.size(), serial.size());
    ASSERT_EQ(serial.size(), 2u * 13 * 10);  // (min, max) per tile
    EXPECT_EQ(std::memcmp(groups.data(), serial.data(), serial.size() * sizeof(float)), 0);
    std::size_t empty = 0;
    for (std::size_t t = 0; t < serial.size(); t += 2) empty += !(serial[t] <= serial[t + 1]);
    EXPECT_GT(empty, 0u) << "some tile should hold no valid depth";
    EXPECT_LT(empty, serial.size() / 4);
}

}  // namespace
}  // namespace decalcomp
