// Texture-space decals against a second Cycles sequence of our own (issue 11): data/blender-deform-own,
// made by tools/blender/deform_sequence.py (data/README.md). A ball with a box-projection UV layout
// (6 islands) is twisted, squashed and rippled over 5 frames; two box decals placed on its rest
// pose cross UV island borders. A twin ball shares its mesh and UVs under another object index.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/mesh_file.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::findFloatChannel;
using test::scoreAgainstTruth;

constexpr int kFrames = 5;
constexpr float kBall = 2.0f, kTwin = 3.0f;  // IndexOB of the decaled ball and of its twin

std::string own(const std::string& file) { return test::dataPath("blender-deform-own/" + file); }
std::string frameName(const char* stem, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "%s.%04d.exr", stem, frame);
    return name;
}

// The sequence through `decalcomp batch` with `scene`: out.NNNN.exr in `dir`.
void batchSequence(const test::ScratchDir& dir, const std::string& scene) {
    const auto run = test::runCli("batch " + test::shellQuote(own("gbuffer.####.exr")) + " --frames 1-" +
                                  std::to_string(kFrames) + " --decals " + test::shellQuote(scene) + " --camera " +
                                  test::shellQuote(own("camera.json")) + " --device cpu -q -o " +
                                  test::shellQuote(dir.file("out.####.exr")));
    ASSERT_EQ(run.exit_code, 0) << run.output;
}

// One frame through `decalcomp composite`: `out` in `dir`.
void compositeFrame(const test::ScratchDir& dir, int frame, const std::string& scene, const std::string& out) {
    const auto run = test::runCli("composite " + test::shellQuote(own(frameName("gbuffer", frame))) + " --decals " +
                                  test::shellQuote(scene) + " --camera " + test::shellQuote(own("camera.json")) +
                                  " --device cpu -q -o " + test::shellQuote(dir.file(out)));
    ASSERT_EQ(run.exit_code, 0) << "frame " << frame << ": " << run.output;
}

std::vector<float> plane(const ExrImage& image, const std::string& name) {
    std::vector<float> storage;
    EXPECT_TRUE(findFloatChannel(image, name, storage)) << name;
    return storage;
}

TEST(OwnDeformRender, ExactModeMatchesCyclesOnEveryFrameThroughComposite) {
    test::ScratchDir dir;
    for (int f = 1; f <= kFrames; ++f) {
        ASSERT_NO_FATAL_FAILURE(compositeFrame(dir, f, own("scene.json"), frameName("out", f)));
        const auto score = scoreAgainstTruth(readExr(dir.file(frameName("out", f))), readExr(own(frameName("truth", f))));
        std::printf("composite, frame %d: %.1f dB over %zu decal pixels\n", f, score.psnr, score.pixels / 3);
        EXPECT_GT(score.pixels / 3, 2000u) << "frame " << f;
        EXPECT_GE(score.psnr, 60.0) << "frame " << f;
        RecordProperty("psnr_db_frame_" + std::to_string(f), std::to_string(score.psnr));
    }
}

// The batch over the sequence scores the same and writes the same albedo as composite, frame by frame.
TEST(OwnDeformRender, BatchMatchesCyclesAndComposite) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(batchSequence(dir, own("scene.json")));
    for (int f = 1; f <= kFrames; ++f) {
        const ExrImage batch = readExr(dir.file(frameName("out", f)));
        const auto score = scoreAgainstTruth(batch, readExr(own(frameName("truth", f))));
        std::printf("batch, frame %d: %.1f dB over %zu decal pixels\n", f, score.psnr, score.pixels / 3);
        EXPECT_GT(score.pixels / 3, 2000u) << "frame " << f;
        EXPECT_GE(score.psnr, 60.0) << "frame " << f;
        ASSERT_NO_FATAL_FAILURE(compositeFrame(dir, f, own("scene.json"), "single.exr"));
        const ExrImage single = readExr(dir.file("single.exr"));
        for (const char* c : {"R", "G", "B"}) {
            const std::string name = std::string("ViewLayer.DiffCol.") + c;
            const auto a = plane(batch, name), b = plane(single, name);
            ASSERT_EQ(a.size(), b.size());
            EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "frame " << f << " " << name;
        }
    }
}

// The negative control: the rest-pose boxes used as world decals stay where the ball was on frame 1.
TEST(OwnDeformRender, WorldDecalSlidesOffTheDeformedBall) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(batchSequence(dir, own("scene_world.json")));
    const auto rest = scoreAgainstTruth(readExr(dir.file(frameName("out", 1))), readExr(own(frameName("truth", 1))));
    std::printf("world decal, frame 1 (rest pose): %.1f dB\n", rest.psnr);
    EXPECT_GE(rest.psnr, 40.0) << "on the rest pose the world decal is the same decal";
    for (int f = 2; f <= kFrames; ++f) {
        const auto score = scoreAgainstTruth(readExr(dir.file(frameName("out", f))), readExr(own(frameName("truth", f))));
        std::printf("world decal, frame %d: %.1f dB\n", f, score.psnr);
        EXPECT_LT(score.psnr, 20.0) << "frame " << f;
    }
}

// Every ball pixel's UV lies on the rest mesh, and the rest point found there is the truth's own
// (the RestPosition AOV: the rest_position attribute that Geometry Nodes stored before deforming).
TEST(OwnDeformRender, RestPointsFromTheUvPassMatchTheTruth) {
    const RestMesh mesh = loadRestMesh(own("mesh_rest.obj"));
    EXPECT_EQ(mesh.triangles.size(), 1520u);
    EXPECT_EQ(mesh.overlapping_uv_triangles, 0);
    for (int f = 1; f <= kFrames; ++f) {
        const ExrImage gbuffer = readExr(own(frameName("gbuffer", f)));
        const ExrImage truth = readExr(own(frameName("truth", f)));
        const auto u = plane(gbuffer, "ViewLayer.UV.U"), v = plane(gbuffer, "ViewLayer.UV.V");
        const auto id = plane(truth, "ViewLayer.IndexOB.X");
        const auto rx = plane(truth, "ViewLayer.RestPosition.R"), ry = plane(truth, "ViewLayer.RestPosition.G"),
                   rz = plane(truth, "ViewLayer.RestPosition.B");
        ASSERT_EQ(u.size(), rz.size());
        std::size_t ball = 0, found = 0;
        double worst = 0;
        for (std::size_t i = 0; i < u.size(); ++i) {
            if (id[i] != kBall) continue;
            ++ball;
            const auto hit = findRestPoint(mesh, glm::vec2(u[i], v[i]));
            if (!hit) continue;
            ++found;
            worst = std::max(worst, double(glm::length(hit->position - glm::vec3(rx[i], ry[i], rz[i]))));
        }
        std::printf("frame %d: %zu ball pixels, rest points within %.2g of the truth's\n", f, ball, worst);
        EXPECT_GT(ball, 10000u);
        EXPECT_EQ(found, ball) << "frame " << f << ": every ball pixel's UV lies on the mesh";
        EXPECT_LT(worst, 1e-4) << "frame " << f;
    }
}

// The decals reach pixels of several UV islands (they cross seams): the truth's decal pixels, mapped
// to the rest mesh, land on triangles of more than one island, counted by UV connectivity.
TEST(OwnDeformRender, DecalsCrossUvIslandBorders) {
    const RestMesh mesh = loadRestMesh(own("mesh_rest.obj"));
    // Islands: triangles sharing a corner of the same rest vertex (same UV) are connected.
    std::vector<int> parent(mesh.triangles.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
    const auto find = [&](int a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    std::vector<int> first_triangle(mesh.vertices.size(), -1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int corner = int(mesh.triangles[t][k]);
            if (first_triangle[corner] < 0) first_triangle[corner] = int(t);
            else parent[find(int(t))] = find(first_triangle[corner]);
        }
    std::set<int> islands;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) islands.insert(find(int(t)));
    EXPECT_EQ(islands.size(), 6u);

    const ExrImage gbuffer = readExr(own(frameName("gbuffer", 1)));
    const ExrImage truth = readExr(own(frameName("truth", 1)));
    const auto u = plane(gbuffer, "ViewLayer.UV.U"), v = plane(gbuffer, "ViewLayer.UV.V");
    const auto mask = plane(truth, "ViewLayer.DecalMask.X");
    std::set<int> under_decals;
    for (std::size_t i = 0; i < u.size(); ++i) {
        if (mask[i] <= 0.5f) continue;
        if (const auto hit = findRestPoint(mesh, glm::vec2(u[i], v[i]))) under_decals.insert(find(int(hit->triangle)));
    }
    std::printf("decal pixels of frame 1 lie on %zu of %zu UV islands\n", under_decals.size(), islands.size());
    EXPECT_GE(under_decals.size(), 3u);
}

// The twin ball (same mesh and UVs, another object index), the floor and the background keep every
// sample bit for bit on every frame; the ball changes.
TEST(OwnDeformRender, TwinAndOtherObjectsStayUntouched) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(batchSequence(dir, own("scene.json")));
    for (int f = 1; f <= kFrames; ++f) {
        const ExrImage before = readExr(own(frameName("gbuffer", f))), after = readExr(dir.file(frameName("out", f)));
        const auto id = plane(before, "ViewLayer.IndexOB.X");
        std::size_t changed_ball = 0, twin = 0;
        for (std::size_t i = 0; i < id.size(); ++i) twin += id[i] == kTwin;
        for (const char* c : {"R", "G", "B"}) {
            const std::string name = std::string("ViewLayer.DiffCol.") + c;
            const auto a = plane(before, name), b = plane(after, name);
            ASSERT_EQ(a.size(), b.size());
            for (std::size_t i = 0; i < id.size(); ++i) {
                if (id[i] == kBall) changed_ball += a[i] != b[i];
                else ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(float)), 0)
                         << "frame " << f << ", pixel " << i << " of object " << id[i];
            }
        }
        EXPECT_GT(twin, 3000u) << "frame " << f << ": the twin is in view";
        EXPECT_GT(changed_ball, 2000u) << "frame " << f;
    }
}

}  // namespace
}  // namespace decalcomp
