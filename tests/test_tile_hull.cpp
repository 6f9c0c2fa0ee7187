// The binning's second level tests each decal's own volume against the hull of a tile's points
// (kernels/binning.cl, dc_tile_hull): a decal turned on the screen lists the tiles it covers, not
// every tile of its screen rectangle, and no tile it reaches is left out.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include "decalcomp/compositor.hpp"
#include "decalcomp/synth.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

constexpr int kSize = 256;
constexpr double kPi = 3.14159265358979323846;

// A wall at y = 0 facing a camera 6 units in front of it, in the given depth convention.
struct Wall {
    Camera camera;
    GBuffer gbuffer;
};

Wall wall(DepthConvention depth, bool orthographic) {
    synth::Scene scene;
    synth::Material material;
    material.albedo = glm::vec3(0.5f);
    scene.materials.push_back(material);
    synth::InfinitePlane plane;
    plane.normal = glm::dvec3(0.0, -1.0, 0.0);
    scene.planes.push_back(plane);
    Wall w;
    w.camera.world_to_camera = glm::lookAt(glm::dvec3(0.3, -6.0, 0.2), glm::dvec3(0.3, 0.0, 0.2), glm::dvec3(0, 0, 1));
    w.camera.projection = orthographic ? glm::ortho(-2.5, 2.5, -2.5, 2.5, 0.5, 50.0)
                                       : perspectiveProjection(50.0 * kPi / 180.0, 1.0, 0.5, 50.0);
    synth::RenderOptions options;
    options.width = options.height = kSize;
    options.depth = depth;
    w.gbuffer = synth::render(scene, w.camera, options);
    return w;
}

// A square decal on the wall turned 45 degrees about the wall's normal (a diamond on screen), and
// a frustum projector aimed at the wall at a slant.
DecalScene turnedDecals() {
    DecalScene scene;
    Texture2D red;
    red.source = "test";
    red.width = red.height = 1;
    red.texels = {glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)};
    scene.textures.push_back(red);
    Decal box;
    box.name = "diamond";
    box.world_matrix = glm::scale(glm::rotate(glm::dmat4(1.0), kPi / 4, glm::dvec3(0, 1, 0)), glm::dvec3(2.5, 0.4, 2.5));
    box.albedo_texture = 0;
    scene.decals.push_back(box);
    Decal frustum;
    frustum.name = "projector";
    frustum.kind = DecalKind::Frustum;
    frustum.world_matrix = glm::inverse(glm::lookAt(glm::dvec3(1.5, -2.0, -1.0), glm::dvec3(-0.6, 0.0, 0.8),
                                                    glm::dvec3(1, 0, 1)));
    frustum.fov_y_deg = 20.0;
    frustum.aspect = 1.0;
    frustum.near = 0.1;
    frustum.far = 5.0;
    frustum.albedo_texture = 0;
    scene.decals.push_back(frustum);
    return scene;
}

struct Listed {
    std::set<int> tiles;    // tiles whose list holds the decal
    std::set<int> reached;  // tiles with a pixel the decal changed, composited alone and unbinned
    int rect_tiles = 0;     // tiles of the screen rectangle of the reached pixels
};

Listed listed(const Wall& w, const DecalScene& scene, int decal) {
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    GBuffer binned = w.gbuffer;
    compositor.composite(binned, w.camera, CompositeOptions{true});
    const BinningResult bins = compositor.lastBinning();
    Listed out;
    for (int t = 0; t < bins.tiles_x * bins.tiles_y; ++t)
        for (int k = bins.tile_offsets[std::size_t(t)]; k < bins.tile_offsets[std::size_t(t) + 1]; ++k)
            if (bins.tile_decals[std::size_t(k)] == decal) out.tiles.insert(t);

    DecalScene alone = scene;
    alone.decals = {scene.decals[std::size_t(decal)]};
    Compositor single(test::cpuDevice());
    single.setScene(alone);
    GBuffer g = w.gbuffer;
    single.composite(g, w.camera, CompositeOptions{false});
    const Plane& before = w.gbuffer.planes.at(Attribute::Albedo);
    const Plane& after = g.planes.at(Attribute::Albedo);
    int x0 = kSize, y0 = kSize, x1 = -1, y1 = -1;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const std::size_t i = std::size_t(y) * kSize + std::size_t(x);
            if (std::memcmp(&before.samples[i * 3], &after.samples[i * 3], 3 * sizeof(float)) == 0) continue;
            out.reached.insert((y / 16) * bins.tiles_x + x / 16);
            x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        }
    if (x1 >= 0) out.rect_tiles = (x1 / 16 - x0 / 16 + 1) * (y1 / 16 - y0 / 16 + 1);
    return out;
}

struct Case {
    DepthConvention depth;
    bool orthographic;
};

class TileHull : public ::testing::TestWithParam<Case> {};

// Every tile the decal reaches is listed, and hardly more: a diamond covers half its screen
// rectangle. Measured (perspective, every convention): the diamond lists 72 tiles and reaches 71 of
// the 121 in its rectangle, the projector 40 and 35 of 63; with screen rectangles alone they listed
// 132 and 182 (the projector's volume reaches far past the wall).
TEST_P(TileHull, TurnedDecalsListTheTilesTheyCover) {
    const Wall w = wall(GetParam().depth, GetParam().orthographic);
    const DecalScene scene = turnedDecals();
    for (int decal = 0; decal < 2; ++decal) {
        const Listed l = listed(w, scene, decal);
        SCOPED_TRACE(scene.decals[std::size_t(decal)].name);
        std::printf("%s: %zu tiles listed, %zu reached, %d in the reached rectangle\n",
                    scene.decals[std::size_t(decal)].name.c_str(), l.tiles.size(), l.reached.size(), l.rect_tiles);
        ASSERT_GT(l.reached.size(), 20u);
        for (int t : l.reached) EXPECT_TRUE(l.tiles.count(t)) << "tile " << t << " reached but not listed";
        EXPECT_LE(l.tiles.size(), l.reached.size() * 5 / 4 + 2);
        EXPECT_LT(double(l.tiles.size()), 0.8 * l.rect_tiles);
    }
}

std::string caseName(const ::testing::TestParamInfo<Case>& param) {
    return std::string(depthConventionName(param.param.depth)) + (param.param.orthographic ? "_orthographic" : "_perspective");
}

INSTANTIATE_TEST_SUITE_P(Conventions, TileHull,
                         ::testing::Values(Case{DepthConvention::Planar, false}, Case{DepthConvention::Radial, false},
                                           Case{DepthConvention::Ndc, false}, Case{DepthConvention::Planar, true}),
                         caseName);

// A pixel filter's taps leave their pixel's ray, so filtered frames keep the screen rectangles:
// the diamond then lists at least its whole reached rectangle.
TEST(TileHull, FilteredFramesListTheWholeRectangle) {
    Wall w = wall(DepthConvention::Planar, false);
    w.gbuffer.pixel_filter = parsePixelFilter("box:1", "test");
    const Listed l = listed(w, turnedDecals(), 0);
    EXPECT_GE(int(l.tiles.size()), l.rect_tiles);
}

}  // namespace
}  // namespace decalcomp
