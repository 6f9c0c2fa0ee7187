// The image module (src/images/image_codecs.hpp): OpenImageIO is loaded only when a program first
// reads or writes an image other than an EXR frame, and a module that cannot be loaded is a
// one-line error of the run that needed it, not of every run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "decalcomp/textures.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::runCli;
using test::runCommand;
using test::shellQuote;

// Whether a library whose file name contains `name` is mapped into this process.
bool mapped(const std::string& name) {
    std::ifstream maps("/proc/self/maps");
    std::stringstream text;
    text << maps.rdbuf();
    return text.str().find(name) != std::string::npos;
}

std::string sampleArguments(const std::string& output) {
    return shellQuote(test::dataPath("sample/gbuffer.exr")) + " --decals " +
           shellQuote(test::dataPath("sample/scene.json")) + " --camera " +
           shellQuote(test::dataPath("sample/camera.json")) + " --device cpu -q -o " + shellQuote(output);
}

TEST(ImageModule, OpenImageIOLoadsWithTheFirstTextureOnly) {
    // This executable links no OpenImageIO of its own: only the module brings it in.
    EXPECT_FALSE(mapped("libOpenImageIO")) << "loaded before any image was read";
    EXPECT_FALSE(mapped("decalcomp-images.so"));
    const Texture2D texture = loadTexture2D(test::dataPath("sample/textures/plate.png"));
    EXPECT_GT(texture.width, 0);
    EXPECT_TRUE(mapped("decalcomp-images.so"));
    EXPECT_TRUE(mapped("libOpenImageIO"));
}

TEST(ImageModule, MissingModuleFailsOnlyTheRunsThatNeedImages) {
    const test::ScratchDir dir;
    const std::string absent = dir.file("nowhere/decalcomp-images.so");
    const std::string env = "DECALCOMP_IMAGE_MODULE=" + shellQuote(absent) + " ";

    // The sample's decals have PNG textures: an input error naming the texture and the module.
    const std::string output = dir.file("out.exr");
    const test::CommandResult textured =
        runCommand(env + shellQuote(DECALCOMP_CLI) + " composite " + sampleArguments(output));
    EXPECT_EQ(textured.exit_code, 3) << textured.output;
    EXPECT_EQ(test::occurrences(textured.output, "\n"), 1u) << textured.output;
    EXPECT_EQ(textured.output.rfind("decalcomp: error: ", 0), 0u) << textured.output;
    EXPECT_NE(textured.output.find("texture '" + test::dataPath("sample/textures/")), std::string::npos)
        << textured.output;
    EXPECT_NE(textured.output.find("cannot load OpenImageIO's module"), std::string::npos) << textured.output;
    EXPECT_NE(textured.output.find(absent), std::string::npos) << textured.output;
    EXPECT_FALSE(std::filesystem::exists(output));

    // A run without images needs no module.
    const test::CommandResult info =
        runCommand(env + shellQuote(DECALCOMP_CLI) + " info " + shellQuote(test::dataPath("sample/gbuffer.exr")));
    EXPECT_EQ(info.exit_code, 0) << info.output;
}

TEST(ImageModule, ALibraryThatIsNotTheModuleIsRefused) {
    const test::ScratchDir dir;
    const std::string output = dir.file("out.exr");
    // A real shared object without the module's entry points.
    const test::CommandResult run = runCommand("DECALCOMP_IMAGE_MODULE=" + shellQuote(DECALCOMP_LIBDEFLATE) + " " +
                                               shellQuote(DECALCOMP_CLI) + " composite " + sampleArguments(output));
    EXPECT_EQ(run.exit_code, 3) << run.output;
    EXPECT_NE(run.output.find("not the module of this decalcomp"), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(ImageModule, PreviewWithoutTheModuleIsAnOutputErrorThatLeavesNoFiles) {
    const test::ScratchDir dir;
    const std::string output = dir.file("out.exr"), preview = dir.file("preview.png");
    const std::string scene = dir.file("untextured.json");
    std::ofstream(scene) << R"({"decals": [{"name": "plain", "translate": [0.3, -1.6, 0], "scale": [1.6, 1.6, 0.5],
                                "affects": {"albedo": {"value": [1, 0, 0]}}}]})";
    const test::CommandResult run =
        runCommand("DECALCOMP_IMAGE_MODULE=" + shellQuote(dir.file("absent.so")) + " " + shellQuote(DECALCOMP_CLI) +
                   " composite " + shellQuote(test::dataPath("sample/gbuffer.exr")) + " --decals " + shellQuote(scene) +
                   " --camera " + shellQuote(test::dataPath("sample/camera.json")) + " --device cpu -q -o " +
                   shellQuote(output) + " --preview " + shellQuote(preview));
    EXPECT_EQ(run.exit_code, 5) << run.output;
    EXPECT_NE(run.output.find(preview + ": cannot load OpenImageIO's module"), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(preview));
    EXPECT_FALSE(std::filesystem::exists(output));  // a frame's outputs are written together or not at all
}

}  // namespace
}  // namespace decalcomp
