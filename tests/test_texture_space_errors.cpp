// Texture-space decals: scene errors and warnings, and what the CLI says about frames
// (docs/texture-space.md "Warnings and errors").
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/scene.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using nlohmann::json;
using test::shellQuote;

std::string deform(const std::string& file) { return test::dataPath("blender-deform/" + file); }

// One rest-pose box decal on `mesh` with the given extra fields.
std::string writeScene(const test::ScratchDir& dir, const std::string& mesh, const json& extra) {
    json decal = {{"kind", "box"},       {"space", "object_rest"}, {"mesh", mesh},
                  {"pass_index", 2},     {"texture", deform("decal_label.png")},
                  {"matrix", json::array({json::array({0.6, 0.0, 0.0, 0.2}), json::array({0.0, 0.0, -0.45, -0.3}),
                                          json::array({0.0, 0.6, 0.0, 0.8}), json::array({0.0, 0.0, 0.0, 1.0})})}};
    for (const auto& [key, value] : extra.items()) {
        if (value.is_null()) decal.erase(key);
        else decal[key] = value;
    }
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << json{{"decals", json::array({decal})}}.dump(2);
    return path;
}

std::string writeObj(const test::ScratchDir& dir, const std::string& name, const std::string& text) {
    const std::string path = dir.file(name);
    std::ofstream(path) << text;
    return path;
}

TEST(TextureSpaceScene, MissingMeshNamesTheField) {
    test::ScratchDir dir;
    test::expectSceneError(writeScene(dir, "absent.obj", json::object()), "decals[0].mesh: ");
    test::expectSceneError(writeScene(dir, "absent.obj", json::object()), "mesh file not found");
}

TEST(TextureSpaceScene, MeshWithoutUvsIsAnError) {
    test::ScratchDir dir;
    writeObj(dir, "flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    test::expectSceneError(writeScene(dir, "flat.obj", json::object()), "corner without UVs");
}

TEST(TextureSpaceScene, OverlappingUvIslandsAreCountedInAWarning) {
    test::ScratchDir dir;
    // two triangles far apart in space sharing one UV triangle, and a third on its own
    writeObj(dir, "stacked.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 5\nv 1 0 5\nv 0 1 5\nv 3 0 0\nv 4 0 0\nv 3 1 0\n"
             "vt 0.1 0.1\nvt 0.4 0.1\nvt 0.1 0.4\nvt 0.6 0.6\nvt 0.9 0.6\nvt 0.6 0.9\n"
             "f 1/1 2/2 3/3\nf 4/1 5/2 6/3\nf 7/4 8/5 9/6\n");
    const DecalScene scene = loadScene(writeScene(dir, "stacked.obj", json::object()));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].overlapping_uv_triangles, 2);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("stacked.obj: 2 of its 3 triangles overlap"), std::string::npos) << scene.warnings[0];
}

TEST(TextureSpaceScene, MeshesAreReadOncePerFile) {
    test::ScratchDir dir;
    json decal = {{"kind", "box"},   {"space", "object_rest"}, {"mesh", deform("mesh_rest.obj")},
                  {"pass_index", 2}, {"texture", deform("decal_label.png")}, {"translate", {0.5, 0, 1}}};
    const std::string path = dir.file("two.json");
    std::ofstream(path) << json{{"decals", json::array({decal, decal})}}.dump();
    const DecalScene scene = loadScene(path);
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.decals[0].rest_mesh, 0);
    EXPECT_EQ(scene.decals[1].rest_mesh, 0);
    EXPECT_EQ(scene.decals[0].mask, scene.decals[1].mask) << "one binding mask for one object";
}

TEST(TextureSpaceScene, FieldsThatDoNotFitAreErrors) {
    test::ScratchDir dir;
    const std::string mesh = deform("mesh_rest.obj");
    test::expectSceneError(writeScene(dir, mesh, {{"space", "world"}}), "decals[0].mesh: belongs to texture-space decals");
    test::expectSceneError(writeScene(dir, mesh, {{"pass_index", nullptr}}), "needs the object it sticks to");
    test::expectSceneError(writeScene(dir, mesh, {{"bake_resolution", 512}}), "decals[0].bake_resolution: belongs to bake mode");
    test::expectSceneError(writeScene(dir, mesh, {{"mode", "bake"}, {"bake_dilation", -1}}), "decals[0].bake_dilation: expected an integer in [0, 1024]");
    test::expectSceneError(writeScene(dir, mesh, {{"space", "object"}}), "decals[0].space: expected one of: world, object_rest");
    test::expectSceneError(writeScene(dir, mesh, {{"mask", {{"ids", {2}}}}}), "decals[0].mask: give the decal's object");
    test::expectSceneError(
        writeScene(dir, mesh, {{"kind", "frustum"}, {"occlusion", true}, {"matrix", nullptr}, {"translate", {0, 0, 1}}}),
        "decals[0].occlusion: blast occlusion is not available for texture-space decals");
}

TEST(TextureSpaceCli, FrameWithoutUvPassFailsWithoutOutput) {
    test::ScratchDir dir;
    const std::string frame = dir.file("plain.exr");
    ASSERT_EQ(test::runGenerator("--width 64 --height 48", frame).exit_code, 0);
    const std::string out = dir.file("out.exr");
    const auto run = test::runCli("composite " + shellQuote(frame) + " --decals " +
                                  shellQuote(writeScene(dir, deform("mesh_rest.obj"), json::object())) +
                                  " --device cpu -q -o " + shellQuote(out));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.output.find(frame + ": texture-space decal"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("needs a UV pass"), std::string::npos) << run.output;
    EXPECT_EQ(test::occurrences(run.output, "\n"), 1u) << run.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(TextureSpaceCli, ObjectWithoutPixelsIsReported) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto run = test::runCli("composite " + shellQuote(deform("gbuffer.0002.exr")) + " --decals " +
                                  shellQuote(writeScene(dir, deform("mesh_rest.obj"), {{"pass_index", 9}})) +
                                  " --camera " + shellQuote(deform("camera.json")) + " --device cpu -o " + shellQuote(out));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("no pixel of its object is in this frame"), std::string::npos) << run.output;
}

// The same frame with its UV pass written top-down: auto reads it flipped (and says so).
TEST(TextureSpaceCli, TopDownUvPassIsDetectedAndOverridable) {
    test::ScratchDir dir;
    ExrImage frame = readExr(deform("gbuffer.0003.exr"));
    bool flipped = false;
    for (ExrPart& part : frame.parts)
        for (ExrChannel& c : part.channels)
            if (c.qualified == "ViewLayer.UV.V") {
                ASSERT_EQ(c.type, SampleType::Float);
                for (std::size_t k = 0; k + 4 <= c.bytes.size(); k += 4) {
                    float v;
                    std::memcpy(&v, &c.bytes[k], 4);
                    v = 1.0f - v;
                    std::memcpy(&c.bytes[k], &v, 4);
                }
                flipped = true;
            }
    ASSERT_TRUE(flipped);
    const std::string input = dir.file("top_down.exr");
    writeExrAtomic(frame, input);
    const ExrImage truth = readExr(deform("truth.0003.exr"));
    auto composite = [&](const std::string& option, const std::string& out) {
        return test::runCli("composite " + shellQuote(input) + " --decals " + shellQuote(deform("decals.json")) +
                            " --camera " + shellQuote(deform("camera.json")) + " --device cpu " + option + " -o " +
                            shellQuote(out));
    };
    const auto detected = composite("", dir.file("auto.exr"));
    ASSERT_EQ(detected.exit_code, 0) << detected.output;
    EXPECT_NE(detected.output.find("its v runs top-down"), std::string::npos) << detected.output;
    EXPECT_GE(test::scoreAgainstTruth(readExr(dir.file("auto.exr")), truth).psnr, 60.0);
    const auto told = composite("--uv-origin top -q", dir.file("top.exr"));
    ASSERT_EQ(told.exit_code, 0) << told.output;
    EXPECT_GE(test::scoreAgainstTruth(readExr(dir.file("top.exr")), truth).psnr, 60.0);
    const auto forced = composite("--uv-origin bottom -q", dir.file("bottom.exr"));
    ASSERT_EQ(forced.exit_code, 0) << forced.output;
    EXPECT_LT(test::scoreAgainstTruth(readExr(dir.file("bottom.exr")), truth).psnr, 30.0) << "read as stored: wrong";
}

TEST(TextureSpaceCli, BadUvOriginIsAUsageError) {
    const auto run = test::runCli("composite in.exr --decals s.json -o out.exr --uv-origin sideways");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("--uv-origin"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace decalcomp
