// The command line: bad inputs exit non-zero with a one-line message naming the file and field,
// and leave no output (nor temporary) file behind.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <filesystem>
#include <fstream>
#include <iterator>

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
    test::ScratchDir dir;  // a file where the output's folder should be (missing folders are created)
    std::ofstream(dir.file("blocker")) << "not a folder";
    const std::string out = dir.file("blocker/out.exr");
    const auto r = test::runCli("composite " + blender("gbuffer.exr") + " --decals " + blender("scene.json") +
                                " --camera " + blender("camera.json") + " --device cpu -o " + shellQuote(out));
    EXPECT_EQ(r.exit_code, 5) << r.output;
    EXPECT_NE(r.output.find("blocker/out.exr"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(filesIn(dir.path()), 1u) << "only the blocker";
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

// DECALCOMP_BUILD_NOTICE_AFTER=0 says it at every kernel build, on stderr (not with --quiet); a
// value that is no number of seconds is a usage error naming it.
TEST(Cli, KernelBuildsRunningLongSaySo) {
    const auto composite = [](const test::ScratchDir& out) {
        return shellQuote(DECALCOMP_CLI) + " composite " + blender("gbuffer.exr") + " --decals " +
               blender("scene.json") + " --camera " + blender("camera.json") + " --device cpu -o " +
               shellQuote(out.file("o.exr"));
    };
    test::ScratchDir dir;
    const std::string args = composite(dir);
    auto r = test::runCommand("DECALCOMP_BUILD_NOTICE_AFTER=0 " + args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "decalcomp: note: "), 1u) << r.output;
    EXPECT_NE(r.output.find(": still compiling the OpenCL kernels for binning and point-sampled shading after 0 s"),
              std::string::npos)
        << r.output;
    r = test::runCommand("DECALCOMP_BUILD_NOTICE_AFTER=0 " + args + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("note:"), std::string::npos) << r.output;
    r = test::runCommand("DECALCOMP_BUILD_NOTICE_AFTER=3600 " + args);  // a build that does not run long: silent
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("note:"), std::string::npos) << r.output;
    test::ScratchDir refused;  // the bad value stops the run before anything is written
    r = test::runCommand("DECALCOMP_BUILD_NOTICE_AFTER=soon " + composite(refused));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("DECALCOMP_BUILD_NOTICE_AFTER=soon: not a number of seconds"), std::string::npos)
        << r.output;
    EXPECT_EQ(filesIn(refused.path()), 0u) << "output or temporary files were left behind";
}

// DECALCOMP_KERNEL_FLAVOUR=gpu builds PoCL's kernels the GPUs' way: the same file byte for byte; a
// flavour that is neither is a usage error naming it, with nothing written.
TEST(Cli, KernelFlavourGivesTheSameFileOrAUsageError) {
    const auto composite = [](const test::ScratchDir& out, const char* name) {
        return shellQuote(DECALCOMP_CLI) + " composite " + blender("gbuffer.exr") + " --decals " +
               blender("scene.json") + " --camera " + blender("camera.json") + " --device cpu -q -o " +
               shellQuote(out.file(name));
    };
    test::ScratchDir dir;
    auto r = test::runCommand(composite(dir, "cpu.exr"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::runCommand("DECALCOMP_KERNEL_FLAVOUR=gpu " + composite(dir, "gpu.exr"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string cpu = bytes(dir.file("cpu.exr"));
    EXPECT_GT(cpu.size(), 100000u);
    EXPECT_EQ(cpu, bytes(dir.file("gpu.exr")));
    test::ScratchDir refused;
    r = test::runCommand("DECALCOMP_KERNEL_FLAVOUR=scalar " + composite(refused, "o.exr"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output, "decalcomp: error: DECALCOMP_KERNEL_FLAVOUR=scalar: not a kernel flavour; cpu or gpu\n");
    EXPECT_EQ(filesIn(refused.path()), 0u) << "output or temporary files were left behind";
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

TEST(Cli, InfoListsCryptomatteLayersWithTheirNames) {
    const auto r = test::runCli("info " + blender("gbuffer.exr"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("cryptomatte: 2 layer(s)"), std::string::npos) << r.output;
    // The object layer's manifest, as Cycles wrote it, names sorted.
    EXPECT_NE(r.output.find("  ViewLayer.CryptoObject (" + test::dataPath("blender/gbuffer.exr") +
                            ", key 542cafa, MurmurHash3_32, manifest in the header): 5 name(s): Barrel, Box, Floor, "
                            "Sphere, Wall\n"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("  ViewLayer.CryptoMaterial ("), std::string::npos) << r.output;
    const auto plain = test::runCli("info " + shellQuote(test::dataPath("sample/gbuffer.exr")));
    ASSERT_EQ(plain.exit_code, 0) << plain.output;
    EXPECT_EQ(plain.output.find("cryptomatte:"), std::string::npos) << plain.output;
}

TEST(Cli, InfoJsonHoldsWhatTheTextShows) {
    const auto r = test::runCli("info " + blender("gbuffer.exr") + " --camera " + blender("camera.json") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json doc = nlohmann::json::parse(r.output);  // nothing but the document on stdout
    ASSERT_EQ(doc["files"].size(), 1u);
    EXPECT_EQ(doc["files"][0]["path"], test::dataPath("blender/gbuffer.exr"));
    EXPECT_TRUE(doc["files"][0]["provenance"].is_null());
    EXPECT_EQ(doc["profile"], "blender");
    EXPECT_EQ(doc["attributes"]["albedo"]["channels"],
              (std::vector<std::string>{"ViewLayer.DiffCol.R", "ViewLayer.DiffCol.G", "ViewLayer.DiffCol.B"}));
    ASSERT_EQ(doc["cryptomatte"].size(), 2u);
    EXPECT_EQ(doc["cryptomatte"][0]["names"], (std::vector<std::string>{"Barrel", "Box", "Floor", "Sphere", "Wall"}));
    EXPECT_EQ(doc["cryptomatte"][0]["manifest"], "header");
    // The camera's matrices are the sidecar's, in its row-major layout.
    std::ifstream sidecar_file(test::dataPath("blender/camera.json"));
    const nlohmann::json sidecar = nlohmann::json::parse(sidecar_file);
    for (const char* key : {"world_to_camera", "projection"})
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col)
                EXPECT_NEAR(doc["camera"][key][row][col].get<double>(), sidecar[key][row][col].get<double>(), 1e-12)
                    << key << "[" << row << "][" << col << "]";
    EXPECT_EQ(doc["depth_convention"], "planar");
    EXPECT_TRUE(doc["depth_check"].is_string());
    EXPECT_TRUE(doc["beauty"].is_array());
}

TEST(Cli, InfoPrintsTheMappingOnceAndOffersOnlyWhatItUses) {
    const auto r = test::runCli("info " + shellQuote(test::dataPath("sample/gbuffer.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "<- Z"), 1u) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "<- albedo.R, albedo.G, albedo.B"), 1u) << r.output;
    // info writes nothing, so it has no --add-channels.
    const auto added = test::runCli("info " + shellQuote(test::dataPath("sample/gbuffer.exr")) + " --add-channels ao");
    EXPECT_EQ(added.exit_code, 2) << added.output;
    EXPECT_NE(added.output.find("--add-channels"), std::string::npos) << added.output;
    EXPECT_EQ(test::runCli("info --help").output.find("--add-channels"), std::string::npos);
}

}  // namespace
}  // namespace decalcomp
