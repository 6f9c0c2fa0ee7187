// The command line: bad inputs exit non-zero with a one-line message naming the file and field,
// and leave no output (nor temporary) file behind.
#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <filesystem>
#include <fstream>

#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::shellQuote;

std::string blender(const std::string& file) { return shellQuote(test::dataPath("blender/" + file)); }

std::size_t filesIn(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& entry : fs::directory_iterator(dir)) n += entry.is_regular_file();
    return n;
}

// Runs `composite` expecting failure: exit code, message mentions `needle`, nothing written.
void expectCompositeFails(const std::string& args, int expected_exit, const std::string& needle) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto r = test::runCli("composite " + args + " --device cpu -o " + shellQuote(out) + " --preview " +
                                shellQuote(dir.file("out.png")));
    EXPECT_EQ(r.exit_code, expected_exit) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "message should mention '" << needle << "': " << r.output;
    EXPECT_EQ(filesIn(dir.path()), 0u) << "output or temporary files were left behind";
}

TEST(Cli, MissingInputFile) {
    expectCompositeFails("/nonexistent/in.exr --decals " + blender("scene.json") + " --camera " + blender("camera.json"),
                         3, "/nonexistent/in.exr");
}

TEST(Cli, InputIsNotAnExr) {
    expectCompositeFails(blender("camera.json") + " --decals " + blender("scene.json") + " --camera " +
                             blender("camera.json"),
                         3, "camera.json");
}

TEST(Cli, MissingDepthChannel) {
    // A generic-named file with albedo only.
    test::ScratchDir inputs;
    const std::string path = inputs.file("albedo_only.exr");
    {
        Imf::Header header(4, 4);
        std::vector<float> pixels(16, 0.5f);
        Imf::FrameBuffer fb;
        for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) {
            header.channels().insert(c, Imf::Channel(Imf::FLOAT));
            fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float), 4 * sizeof(float)));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(4);
    }
    expectCompositeFails(shellQuote(path) + " --decals " + blender("scene.json") + " --camera " + blender("camera.json"),
                         3, "depth");
}

TEST(Cli, ExplicitChannelThatDoesNotExist) {
    expectCompositeFails(blender("gbuffer.exr") + " --channel depth=Nope.Z --decals " + blender("scene.json") +
                             " --camera " + blender("camera.json"),
                         3, "Nope.Z");
}

TEST(Cli, MalformedSceneJson) {
    test::ScratchDir inputs;
    const std::string scene = inputs.file("broken.json");
    std::ofstream(scene) << "{\"decals\": [ {\"kind\": \"box\", }";
    expectCompositeFails(blender("gbuffer.exr") + " --decals " + shellQuote(scene) + " --camera " + blender("camera.json"),
                         3, "broken.json");
}

TEST(Cli, BadSceneFieldNamesJsonPath) {
    test::ScratchDir inputs;
    const std::string scene = inputs.file("bad_opacity.json");
    std::ofstream(scene) << R"({"textures": {"t": {"albedo": ")" << test::dataPath("blender/decal_ring.png")
                         << R"("}}, "decals": [{"kind": "box", "texture": "t", "opacity": "high",
                            "matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
    expectCompositeFails(blender("gbuffer.exr") + " --decals " + shellQuote(scene) + " --camera " + blender("camera.json"),
                         3, "decals[0].opacity");
}

TEST(Cli, MissingTexture) {
    test::ScratchDir inputs;
    const std::string scene = inputs.file("missing_texture.json");
    std::ofstream(scene) << R"({"textures": {"t": {"albedo": "no_such_texture.png"}}, "decals": [{"kind": "box",
        "texture": "t", "matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
    expectCompositeFails(blender("gbuffer.exr") + " --decals " + shellQuote(scene) + " --camera " + blender("camera.json"),
                         3, "no_such_texture.png");
}

TEST(Cli, SingularCameraMatrix) {
    test::ScratchDir inputs;
    const std::string camera = inputs.file("singular.json");
    std::ofstream(camera) << R"({"world_to_camera": [[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]],
        "projection": [[1,0,0,0],[0,1,0,0],[0,0,-1,-0.2],[0,0,-1,0]]})";
    expectCompositeFails(blender("gbuffer.exr") + " --decals " + blender("scene.json") + " --camera " + shellQuote(camera),
                         3, "world_to_camera");
}

TEST(Cli, NoCameraAnywhere) {
    // No sidecar, no header camera and no position pass to solve one from.
    test::ScratchDir inputs;
    const std::string path = inputs.file("no_position.exr");
    const auto gen = test::runCommand(shellQuote(DECALCOMP_GEN) + " --width 32 --height 24 --no-position -o " +
                                      shellQuote(path));
    ASSERT_EQ(gen.exit_code, 0) << gen.output;
    expectCompositeFails(shellQuote(path) + " --decals " + blender("scene.json"), 3, "no position pass");
}

TEST(Cli, UnwritableOutputLeavesNothing) {
    test::ScratchDir dir;
    const std::string out = dir.file("missing_dir/out.exr");
    const auto r = test::runCli("composite " + blender("gbuffer.exr") + " --decals " + blender("scene.json") +
                                " --camera " + blender("camera.json") + " --device cpu -o " + shellQuote(out));
    EXPECT_EQ(r.exit_code, 5) << r.output;
    EXPECT_NE(r.output.find("missing_dir/out.exr"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(filesIn(dir.path()), 0u);
}

TEST(Cli, RefusesToOverwriteInput) {
    test::ScratchDir dir;
    const std::string in = dir.file("in.exr");
    fs::copy_file(test::dataPath("blender/gbuffer.exr"), in);
    const auto size_before = fs::file_size(in);
    const auto r = test::runCli("composite " + shellQuote(in) + " --decals " + blender("scene.json") + " --camera " +
                                blender("camera.json") + " --device cpu -o " + shellQuote(in));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--overwrite-input"), std::string::npos) << r.output;
    EXPECT_EQ(fs::file_size(in), size_before);
    EXPECT_EQ(filesIn(dir.path()), 1u);
}

TEST(Cli, CompositeWritesExrAndPreview) {
    test::ScratchDir dir;
    const auto r = test::runCli("composite " + blender("gbuffer.exr") + " --decals " + blender("scene.json") +
                                " --camera " + blender("camera.json") + " --device cpu -o " + shellQuote(dir.file("o.exr")) +
                                " --preview " + shellQuote(dir.file("o.png")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GT(fs::file_size(dir.file("o.exr")), 100000u);
    EXPECT_GT(fs::file_size(dir.file("o.png")), 1000u);
    EXPECT_EQ(filesIn(dir.path()), 2u);
}

TEST(Cli, UsageErrorsExitTwo) {
    EXPECT_EQ(test::runCli("").exit_code, 2);
    EXPECT_EQ(test::runCli("composite").exit_code, 2);
    EXPECT_EQ(test::runCli("composite " + blender("gbuffer.exr") + " --decals x.json -o o.exr --depth sideways").exit_code, 2);
}

TEST(Cli, HelpForEveryCommand) {
    for (const char* cmd : {"", "composite ", "info ", "devices "}) {
        const auto r = test::runCli(std::string(cmd) + "--help");
        EXPECT_EQ(r.exit_code, 0) << cmd;
        EXPECT_NE(r.output.find("Usage"), std::string::npos) << cmd << r.output;
    }
}

TEST(Cli, DevicesListsPocl) {
    const auto r = test::runCli("devices");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("cpu"), std::string::npos) << r.output;
}

TEST(Cli, InfoReportsProfileCameraAndDepth) {
    const auto r = test::runCli("info " + blender("gbuffer.exr") + " --camera " + blender("camera.json"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    for (const char* needle : {"profile: blender", "ViewLayer.Depth.Z", "depth convention: planar", "world_to_camera",
                               "camera.json (perspective)"})
        EXPECT_NE(r.output.find(needle), std::string::npos) << needle << "\n" << r.output;
}

}  // namespace
}  // namespace decalcomp
