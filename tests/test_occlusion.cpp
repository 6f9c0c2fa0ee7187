// Blast occlusion (docs/conventions.md "Blast occlusion"): an analytic wall that shadows part of
// a floor from the blast, and the kernels against the reference on random scenes.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <cmath>
#include <cstring>

#include "decalcomp/compositor.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

using test::cpuDevice;

// A floor (z = 0) and a wall (x in [1.9, 2.1], |y| <= 3, z in [0, 1.5]) seen from above and in
// front, so the camera sees the wall's blast-facing side and the floor on both sides of it.
// The blast goes off at (0, 0, 1).
const glm::dvec3 kBlast(0.0, 0.0, 1.0);
const glm::dvec3 kWallCentre(2.0, 0.0, 0.75), kWallHalf(0.1, 3.0, 0.75);

struct WallFrame {
    GBuffer gbuffer;
    Camera camera;
};

WallFrame renderWallFrame() {
    synth::Scene scene;
    scene.materials = {synth::Material{}, synth::Material{glm::vec3(0.3f, 0.6f, 0.3f), glm::vec3(0.3f, 0.6f, 0.3f)}};
    scene.planes.push_back({glm::dvec3(0.0), glm::dvec3(0, 0, 1), 0});
    scene.boxes.push_back({glm::scale(glm::translate(glm::dmat4(1.0), kWallCentre), 2.0 * kWallHalf), 1});
    WallFrame f;
    f.camera.world_to_camera = lookAt(glm::dvec3(-2.5, -7.0, 7.0), glm::dvec3(3.0, 0.5, 0.0), glm::dvec3(0, 0, 1));
    f.camera.projection = perspectiveProjection(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0);
    synth::RenderOptions options;
    options.width = 240;
    options.height = 180;
    f.gbuffer = synth::render(scene, f.camera, options);
    return f;
}

// Whether the segment from the blast to P crosses the wall grown by `grow` (negative shrinks).
bool segmentCrossesWall(const glm::dvec3& p, double grow) {
    const glm::dvec3 lo = kWallCentre - kWallHalf - grow, hi = kWallCentre + kWallHalf + grow;
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec3 dir = p - kBlast;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-12) {
            if (kBlast[a] < lo[a] || kBlast[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - kBlast[a]) / dir[a], tb = (hi[a] - kBlast[a]) / dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

Texture2D constantTexture(int size, int faces, glm::vec4 colour) {
    Texture2D t;
    t.source = "constant";
    t.width = t.height = size;
    t.depth = faces;
    t.texels.assign(std::size_t(size * size * faces), colour);
    return t;
}

enum class Region { Other, ShadowedFloor, LitFloor, WallFront };

// Composites the wall frame with one decal, occlusion on and off, and checks each region.
void checkWallShadow(Decal decal, const Texture2D& texture, int resolution) {
    const WallFrame f = renderWallFrame();
    DecalScene scene;
    scene.textures.push_back(texture);
    decal.albedo_texture = 0;
    decal.occlusion = {true, resolution, 2.0};
    const glm::dmat4 world_to_local = glm::inverse(decal.world_matrix);
    // inside the decal and within 6.4 of the blast: well within the cube's falloff, so the change
    // is visible, and near enough that the slope-scaled bias (which grows with distance times
    // slope on the grazing floor) stays below the gap between wall and floor
    auto covered = [&](const glm::dvec3& p) {
        const glm::dvec3 l(world_to_local * glm::dvec4(p, 1.0));
        return reference::insideDecal(decal, l) && glm::length(p - kBlast) < 6.4;
    };
    std::vector<Region> regions(f.gbuffer.pixelCount(), Region::Other);
    std::size_t counts[4] = {};
    for (int y = 0; y < f.gbuffer.height; ++y)
        for (int x = 0; x < f.gbuffer.width; ++x) {
            const auto p = reference::pixelWorldPoint(f.gbuffer, f.camera, x, y);
            if (!p || !covered(*p)) continue;
            Region r = Region::Other;
            if (std::abs(p->z) < 1e-4) {
                // clear of the wall's base, where the bias (texels x slope) may let the blast through
                if (segmentCrossesWall(*p, -0.05) && p->x > 2.6) r = Region::ShadowedFloor;
                else if (!segmentCrossesWall(*p, 0.3)) r = Region::LitFloor;
            } else if (std::abs(p->x - 1.9) < 1e-4 && p->z > 0.05 && p->z < 1.45 && std::abs(p->y) < 2.95) {
                r = Region::WallFront;
            }
            regions[std::size_t(y) * f.gbuffer.width + x] = r;
            ++counts[int(r)];
        }
    ASSERT_GT(counts[int(Region::ShadowedFloor)], 200u);
    ASSERT_GT(counts[int(Region::LitFloor)], 200u);
    ASSERT_GT(counts[int(Region::WallFront)], 100u);

    const Plane& in = f.gbuffer.planes.at(Attribute::Albedo);
    for (bool occlusion : {true, false}) {
        scene.decals = {decal};
        scene.decals[0].occlusion.enabled = occlusion;
        Compositor compositor(cpuDevice());
        compositor.setScene(scene);
        GBuffer out = f.gbuffer;
        compositor.composite(out, f.camera);
        const Plane& result = out.planes.at(Attribute::Albedo);
        std::size_t wrong[4] = {};
        for (std::size_t i = 0; i < regions.size(); ++i) {
            if (regions[i] == Region::Other) continue;
            const bool untouched = std::memcmp(&in.samples[i * 3], &result.samples[i * 3], 3 * sizeof(float)) == 0;
            const bool expect_untouched = occlusion && regions[i] == Region::ShadowedFloor;
            wrong[int(regions[i])] += untouched != expect_untouched;
        }
        EXPECT_EQ(wrong[int(Region::ShadowedFloor)], 0u) << "occlusion " << occlusion << ": shadowed floor";
        EXPECT_EQ(wrong[int(Region::LitFloor)], 0u) << "occlusion " << occlusion << ": floor the blast reaches";
        EXPECT_EQ(wrong[int(Region::WallFront)], 0u) << "occlusion " << occlusion << ": wall's blast-facing side";
    }
}

TEST(BlastOcclusion, WallShadowsFloorFromCube) {
    Decal cube;
    cube.name = "grenade";
    cube.kind = DecalKind::Cube;
    cube.world_matrix = glm::scale(glm::translate(glm::dmat4(1.0), kBlast), glm::dvec3(16.0));
    checkWallShadow(cube, constantTexture(4, 6, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)), 64);
}

TEST(BlastOcclusion, WallShadowsFloorFromFrustum) {
    Decal frustum;
    frustum.name = "shotgun";
    frustum.kind = DecalKind::Frustum;
    frustum.world_matrix = glm::inverse(lookAt(kBlast, glm::dvec3(5.0, 0.0, 0.0), glm::dvec3(0, 0, 1)));
    frustum.fov_y_deg = 100.0;
    frustum.aspect = 1.6;
    frustum.near = 0.05;
    frustum.far = 12.0;
    checkWallShadow(frustum, constantTexture(4, 1, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f)), 128);
}

// Random scenes with occlusion on for every frustum and cube decal, at coarse map resolutions
// so holes and neighbourhoods across cube faces are exercised.
DecalScene occludingDecals(const test::RandomFrame& f, std::uint32_t seed) {
    DecalScene decals = test::makeRandomDecals(f, seed, 120);
    int k = 0;
    for (Decal& d : decals.decals)
        if (d.kind == DecalKind::Frustum || d.kind == DecalKind::Cube) {
            d.occlusion = {true, 16 << (k % 3), k % 2 ? 2.0 : 0.5};
            ++k;
        }
    return decals;
}

class OcclusionScenes : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(OcclusionScenes, KernelMatchesReference) {
    const test::RandomFrame f = test::makeRandomFrame(GetParam());
    const DecalScene decals = occludingDecals(f, GetParam());
    const auto [out, c] = test::compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error << " over " << c.compared << " pixels";
    EXPECT_LT(double(c.ambiguous), test::ambiguousShare(f.gbuffer) * double(f.gbuffer.pixelCount()))
        << "too many boundary pixels to be meaningful";
    // occlusion must change something, or the comparison says nothing about it
    DecalScene open = decals;
    for (Decal& d : open.decals) d.occlusion.enabled = false;
    Compositor compositor(cpuDevice());
    compositor.setScene(open);
    GBuffer unoccluded = f.gbuffer;
    compositor.composite(unoccluded, f.camera);
    EXPECT_NE(unoccluded.planes.at(Attribute::Albedo).samples, out.planes.at(Attribute::Albedo).samples);
}

TEST_P(OcclusionScenes, BinnedEqualsUnbinnedExactly) {
    const test::RandomFrame f = test::makeRandomFrame(GetParam());
    EXPECT_EQ(test::binnedUnbinnedDifferences(f, occludingDecals(f, GetParam())), 0u);
}

INSTANTIATE_TEST_SUITE_P(Occlusion, OcclusionScenes, ::testing::Range(1u, 9u));

}  // namespace
}  // namespace decalcomp
