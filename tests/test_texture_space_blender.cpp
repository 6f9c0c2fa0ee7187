// Texture-space decals against Cycles' truth (data/blender-deform, README "Deforming sequence"): a
// tube that bends and twists over 6 frames with a box decal placed on its rest pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/mesh_file.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::findFloatChannel;
using test::scoreAgainstTruth;

std::string deform(const std::string& file) { return test::dataPath("blender-deform/" + file); }
std::string frameName(const char* stem, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "%s.%04d.exr", stem, frame);
    return name;
}

// The sequence through `decalcomp batch` with `scene`, outputs out.NNNN.exr in `dir`.
void batchSequence(const test::ScratchDir& dir, const std::string& scene, const std::string& extra = "") {
    const auto run = test::runCli("batch " + test::shellQuote(deform("gbuffer.####.exr")) + " --frames 1-6 --decals " +
                                  test::shellQuote(scene) + " --camera " + test::shellQuote(deform("camera.json")) +
                                  " --device cpu -q " + extra + " -o " + test::shellQuote(dir.file("out.####.exr")));
    ASSERT_EQ(run.exit_code, 0) << run.output;
}

TEST(BlenderDeform, ExactModeMatchesCyclesOnEveryFrame) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(batchSequence(dir, deform("decals.json")));
    for (int f = 1; f <= 6; ++f) {
        const auto score = scoreAgainstTruth(readExr(dir.file(frameName("out", f))), readExr(deform(frameName("truth", f))));
        std::printf("frame %d: %.1f dB over %zu decal pixels\n", f, score.psnr, score.pixels / 3);
        EXPECT_GT(score.pixels / 3, 2000u) << "frame " << f;
        EXPECT_GE(score.psnr, 60.0) << "frame " << f;
        RecordProperty("psnr_db_frame_" + std::to_string(f), std::to_string(score.psnr));
    }
}

// The negative control: the rest-pose box used as a world decal stays where the tube was on frame 1.
TEST(BlenderDeform, WorldDecalSlidesOffTheDeformedSurface) {
    std::ifstream in(deform("decals.json"));
    nlohmann::json scene = nlohmann::json::parse(in);
    nlohmann::json& decal = scene["decals"][0];
    decal["world_matrix"] = decal["world_matrix_rest_pose"];
    for (const char* key : {"space", "matrix", "mesh", "pass_index", "cryptomatte_object", "scale"}) decal.erase(key);
    decal["texture"] = deform("decal_label.png");
    test::ScratchDir dir;
    const std::string scene_file = dir.file("world.json");
    std::ofstream(scene_file) << scene.dump(2);
    ASSERT_NO_FATAL_FAILURE(batchSequence(dir, scene_file));
    const auto rest = scoreAgainstTruth(readExr(dir.file(frameName("out", 1))), readExr(deform(frameName("truth", 1))));
    EXPECT_GE(rest.psnr, 40.0) << "on the rest pose the world decal is the same decal";
    for (int f = 2; f <= 6; ++f) {
        const auto score = scoreAgainstTruth(readExr(dir.file(frameName("out", f))), readExr(deform(frameName("truth", f))));
        std::printf("world decal, frame %d: %.1f dB\n", f, score.psnr);
        EXPECT_LT(score.psnr, 20.0) << "frame " << f;
    }
}

// The rest points the library finds through the UV pass are the truth's own (RestPosition AOV).
TEST(BlenderDeform, RestPointsFromTheUvPassMatchTheTruth) {
    const RestMesh mesh = loadRestMesh(deform("mesh_rest.obj"));
    EXPECT_EQ(mesh.triangles.size(), 5248u);
    EXPECT_EQ(mesh.overlapping_uv_triangles, 0);
    for (int f : {1, 3, 6}) {
        const ExrImage gbuffer = readExr(deform(frameName("gbuffer", f)));
        const ExrImage truth = readExr(deform(frameName("truth", f)));
        std::vector<float> u, v, id, rx, ry, rz;
        ASSERT_TRUE(findFloatChannel(gbuffer, "ViewLayer.UV.U", u) && findFloatChannel(gbuffer, "ViewLayer.UV.V", v));
        ASSERT_TRUE(findFloatChannel(truth, "ViewLayer.IndexOB.X", id));
        ASSERT_TRUE(findFloatChannel(truth, "ViewLayer.RestPosition.R", rx) &&
                    findFloatChannel(truth, "ViewLayer.RestPosition.G", ry) &&
                    findFloatChannel(truth, "ViewLayer.RestPosition.B", rz));
        std::size_t tube = 0, found = 0;
        double worst = 0;
        for (std::size_t i = 0; i < u.size(); ++i) {
            if (id[i] != 2.0f) continue;
            ++tube;
            const auto hit = findRestPoint(mesh, glm::vec2(u[i], v[i]));
            if (!hit) continue;
            ++found;
            worst = std::max(worst, double(glm::length(hit->position - glm::vec3(rx[i], ry[i], rz[i]))));
        }
        EXPECT_GT(tube, 10000u);
        EXPECT_EQ(found, tube) << "frame " << f << ": every tube pixel's UV lies on the mesh";
        EXPECT_LT(worst, 1e-4) << "frame " << f;
    }
}

// The twin tube beside it has the same UVs and another object index: it keeps every sample.
TEST(BlenderDeform, OtherObjectsWithTheSameUvsStayUntouched) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto run = test::runCli("composite " + test::shellQuote(deform(frameName("gbuffer", 3))) + " --decals " +
                                  test::shellQuote(deform("decals.json")) + " --camera " +
                                  test::shellQuote(deform("camera.json")) + " --device cpu -q -o " + test::shellQuote(out));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const ExrImage before = readExr(deform(frameName("gbuffer", 3))), after = readExr(out);
    std::vector<float> id, a, b;
    ASSERT_TRUE(findFloatChannel(before, "ViewLayer.IndexOB.X", id));
    std::size_t changed_tube = 0;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.DiffCol.") + c;
        ASSERT_TRUE(findFloatChannel(before, name, a) && findFloatChannel(after, name, b));
        for (std::size_t i = 0; i < id.size(); ++i) {
            if (id[i] == 2.0f) changed_tube += a[i] != b[i];
            else ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(float)), 0) << "pixel " << i << " of object " << id[i];
        }
    }
    EXPECT_GT(changed_tube, 2000u);
}

}  // namespace
}  // namespace decalcomp
