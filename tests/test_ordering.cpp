// Decal order: (priority, then file order), identical in every tile and stable whatever the
// number of decals. 10,000 decals over one region on PoCL, against the scalar reference.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>

#include "decalcomp/compositor.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/scene.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using json = nlohmann::json;

constexpr int kDecals = 10000;
constexpr int kWidth = 64, kHeight = 48;
const glm::vec3 kBase(0.2f, 0.3f, 0.4f);

ComputeDevice& cpuDevice() {
    static ComputeDevice device("cpu");
    return device;
}

// A wall facing the camera at planar depth 5 over the whole frame.
struct Frame {
    GBuffer gbuffer;
    Camera camera;
};

Frame wall() {
    Frame f;
    f.camera.world_to_camera = glm::dmat4(1.0);  // at the origin, looking down -Z
    f.camera.projection = perspectiveProjection(glm::radians(60.0), double(kWidth) / kHeight, 0.1, 100.0);
    GBuffer& g = f.gbuffer;
    g.width = g.display_width = kWidth;
    g.height = g.display_height = kHeight;
    g.depth_convention = DepthConvention::Planar;
    g.planes[Attribute::Depth] = Plane{1, std::vector<float>(g.pixelCount(), 5.0f)};
    Plane albedo{3, {}};
    for (std::size_t i = 0; i < g.pixelCount(); ++i) albedo.samples.insert(albedo.samples.end(), {kBase.r, kBase.g, kBase.b});
    g.planes[Attribute::Albedo] = albedo;
    return f;
}

// Decal k: the same footprint on the wall for all (only the depth extent varies, which does not
// change which wall pixels are inside), with its own flat 1x1 colour.
glm::dmat4 boxMatrix(int k) {
    glm::dmat4 m(1.0);
    m[0][0] = 4.0, m[1][1] = 3.0, m[2][2] = 1.0 + 0.001 * (k % 5);
    m[3] = glm::dvec4(0.3, -0.2, -5.0, 1.0);
    return m;
}

glm::vec3 colourOf(int k) {
    return {float(k % 100) / 99.0f, float((k / 100) % 100) / 99.0f, float(k) / float(kDecals)};
}

DecalScene overlappingDecals(float opacity) {
    DecalScene scene;
    for (int k = 0; k < kDecals; ++k) {
        const glm::vec3 c = colourOf(k);
        Texture2D texture;
        texture.source = fmt::format("flat{}", k);
        texture.width = texture.height = 1;
        texture.texels = {glm::vec4(c, 1.0f)};
        scene.textures.push_back(texture);
        Decal d;
        d.name = fmt::format("d{}", k);
        d.world_matrix = boxMatrix(k);
        d.albedo_texture = k;
        d.opacity = opacity;
        d.filter = k % 2 ? TextureFilter::Nearest : TextureFilter::Linear;
        scene.decals.push_back(d);
    }
    return scene;
}

Plane composite(const Frame& f, const DecalScene& scene, bool binned, BinningResult* binning = nullptr) {
    static Compositor compositor(cpuDevice());
    compositor.setScene(scene);
    GBuffer out = f.gbuffer;
    compositor.composite(out, f.camera, CompositeOptions{binned});
    if (binning) *binning = compositor.lastBinning();
    return out.planes.at(Attribute::Albedo);
}

glm::vec3 pixel(const Plane& p, std::size_t i) { return {p.at(i, 0), p.at(i, 1), p.at(i, 2)}; }

bool sameBits(const Plane& a, const Plane& b) {
    return a.samples.size() == b.samples.size() &&
           std::memcmp(a.samples.data(), b.samples.data(), a.samples.size() * sizeof(float)) == 0;
}

TEST(Ordering, TenThousandOpaqueDecalsLeaveTheLastColour) {
    const Frame f = wall();
    const DecalScene scene = overlappingDecals(1.0f);
    BinningResult binning;
    const Plane binned = composite(f, scene, true, &binning);
    const Plane unbinned = composite(f, scene, false);
    EXPECT_TRUE(sameBits(binned, unbinned));

    const auto ref = reference::shade(f.gbuffer, f.camera, scene);
    const glm::vec3 last = colourOf(kDecals - 1);
    std::size_t inside = 0, outside = 0;
    for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
        const glm::vec3 got = pixel(binned, i);
        // Same footprint for all: a pixel gets every decal or none, whatever the rounding.
        ASSERT_TRUE(got == last || got == kBase) << "pixel " << i;
        if (ref.ambiguous[i]) continue;
        ASSERT_EQ(got, pixel(ref.albedo, i)) << "pixel " << i;
        (got == last ? inside : outside) += 1;
    }
    EXPECT_GT(inside, 600u);
    EXPECT_GT(outside, 200u);

    // Every tile the footprint touches lists all decals, in scene order: no cliff, no drop.
    std::size_t full_tiles = 0;
    std::vector<int> all(kDecals);
    std::iota(all.begin(), all.end(), 0);
    for (std::size_t t = 0; t + 1 < binning.tile_offsets.size(); ++t) {
        const auto begin = binning.tile_decals.begin() + binning.tile_offsets[t];
        const auto end = binning.tile_decals.begin() + binning.tile_offsets[t + 1];
        if (begin == end) continue;
        ASSERT_TRUE(std::equal(begin, end, all.begin(), all.end())) << "tile " << t;
        ++full_tiles;
    }
    EXPECT_GT(full_tiles, 4u);
}

TEST(Ordering, TenThousandHalfOpaqueDecalsMatchTheReference) {
    const Frame f = wall();
    const DecalScene scene = overlappingDecals(0.5f);
    const Plane binned = composite(f, scene, true);
    EXPECT_TRUE(sameBits(binned, composite(f, scene, false)));
    const auto ref = reference::shade(f.gbuffer, f.camera, scene);
    std::size_t compared = 0;
    for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
        if (ref.ambiguous[i]) continue;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(binned.at(i, c), ref.albedo.at(i, c), 1e-5) << "pixel " << i;
        ++compared;
    }
    EXPECT_GT(compared, 2500u);
    // The mix is dominated by the last decals: reversing the order gives another colour.
    DecalScene reversed = scene;
    std::reverse(reversed.decals.begin(), reversed.decals.end());
    const Plane other = composite(f, reversed, true);
    const std::size_t centre = std::size_t(kHeight / 2) * kWidth + kWidth / 2;
    EXPECT_GT(glm::length(pixel(other, centre) - pixel(binned, centre)), 0.1f);
}

// ---- the scene loader ---------------------------------------------------------------------

// Priority of decal k in file order: a few levels, interleaved.
int priorityOf(int k) { return int((std::uint32_t(k) * 2654435761u) >> 29) - 3; }  // in [-3, 4]

void writePng(const std::string& path, std::uint8_t r, std::uint8_t g) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    const std::uint8_t px[] = {r, g, 128, 255};
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    ASSERT_TRUE(out->close());
}

// 10,000 decals with the box footprint above, cycling through `textures` textures.
std::string writeScene(const test::ScratchDir& dir, int textures) {
    json scene = {{"textures", json::object()}, {"decals", json::array()}};
    for (int t = 0; t < textures; ++t) {
        const std::string name = fmt::format("t{}.png", t);
        writePng(dir.file(name), std::uint8_t(t * 4), std::uint8_t(255 - t * 3));
        scene["textures"][fmt::format("t{}", t)] = name;
    }
    for (int k = 0; k < kDecals; ++k) {
        const glm::dmat4 m = boxMatrix(k);
        json rows = json::array();
        for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
        scene["decals"].push_back({{"name", fmt::format("d{}", k)},
                                   {"texture", fmt::format("t{}", k % textures)},
                                   {"matrix", rows},
                                   {"priority", priorityOf(k)}});
    }
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << scene.dump();
    return path;
}

TEST(Ordering, LoaderSortsTenThousandPrioritiesStably) {
    test::ScratchDir dir;
    const DecalScene scene = loadScene(writeScene(dir, 3));
    ASSERT_EQ(scene.decals.size(), std::size_t(kDecals));
    std::vector<int> expected(kDecals);
    std::iota(expected.begin(), expected.end(), 0);
    std::stable_sort(expected.begin(), expected.end(), [](int a, int b) { return priorityOf(a) < priorityOf(b); });
    std::set<int> priorities;
    for (int k = 0; k < kDecals; ++k) {
        ASSERT_EQ(scene.decals[std::size_t(k)].name, fmt::format("d{}", expected[std::size_t(k)])) << "position " << k;
        priorities.insert(priorityOf(k));
    }
    EXPECT_GE(priorities.size(), 6u);  // the order really was shuffled
}

TEST(Ordering, WinnerIsTheLastInPriorityThenFileOrder) {
    test::ScratchDir dir;
    const DecalScene scene = loadScene(writeScene(dir, 64));
    // Independently of the loader: the highest priority, and the latest in the file among those.
    int winner = 0;
    for (int k = 1; k < kDecals; ++k)
        if (priorityOf(k) >= priorityOf(winner)) winner = k;
    ASSERT_NE(winner, kDecals - 1) << "the test wants a winner that is not simply the last in the file";
    const auto it = std::find_if(scene.decals.begin(), scene.decals.end(),
                                 [&](const Decal& d) { return d.name == fmt::format("d{}", winner); });
    ASSERT_NE(it, scene.decals.end());
    const glm::vec4 texel = scene.textures.at(std::size_t(it->albedo_texture)).texels.at(0);

    const Frame f = wall();
    const Plane out = composite(f, scene, true);
    const std::size_t centre = std::size_t(kHeight / 2) * kWidth + kWidth / 2;
    EXPECT_EQ(pixel(out, centre), glm::vec3(texel));
}

}  // namespace
}  // namespace decalcomp
