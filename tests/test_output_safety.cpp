// No run writes over what it reads: outputs and previews are checked against the EXR inputs, the
// scene, the camera sidecar and the textures, by inode (symlinks and hard links count), and
// against each other, before any work; nothing is created or replaced when the check refuses.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::shellQuote;

// The sample frame, scene and textures copied into a scratch folder the test may damage.
struct Sample {
    test::ScratchDir dir;
    std::string input, scene, camera, texture;
    Sample() {
        fs::copy(test::dataPath("sample"), dir.path(), fs::copy_options::recursive);
        input = dir.file("gbuffer.exr");
        scene = dir.file("scene.json");
        camera = dir.file("camera.json");
        texture = dir.file("textures/scorch.png");
    }
    std::string composite(const std::string& extra) const {
        return "composite " + shellQuote(input) + " --decals " + shellQuote(scene) + " --camera " + shellQuote(camera) +
               " --device cpu -q " + extra;
    }
};

void expectRefused(const test::CommandResult& r, const std::string& needle) {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
}

TEST(OutputSafety, PreviewNamingTheInputIsRefusedAndTheInputKept) {
    Sample s;
    const std::string before = test::readFileBytes(s.input);
    const auto r = test::runCli(s.composite("-o " + shellQuote(s.dir.file("out.exr")) + " --preview " +
                                            shellQuote(s.input)));
    expectRefused(r, "the preview would replace the input");
    EXPECT_TRUE(test::readFileBytes(s.input) == before);
    EXPECT_FALSE(fs::exists(s.dir.file("out.exr")));
}

TEST(OutputSafety, PreviewNamingTheOutputIsRefused) {
    Sample s;
    const std::string out = s.dir.file("out.exr");
    expectRefused(test::runCli(s.composite("-o " + shellQuote(out) + " --preview " + shellQuote(out))),
                  "the preview would replace the output");
    EXPECT_FALSE(fs::exists(out));
}

TEST(OutputSafety, OutputsNeedAnExrName) {
    Sample s;
    const std::string before = test::readFileBytes(s.scene);
    expectRefused(test::runCli(s.composite("-o " + shellQuote(s.scene))), "give it an .exr name");
    EXPECT_TRUE(test::readFileBytes(s.scene) == before);
}

TEST(OutputSafety, SceneCameraAndTexturesAreNeverReplaced) {
    Sample s;
    // .exr names that are the scene, the camera and a texture through symbolic links
    for (const std::string& target : {s.scene, s.camera, s.texture}) {
        const std::string link = s.dir.file("link-" + fs::path(target).stem().string() + ".exr");
        fs::create_symlink(target, link);
        const std::string before = test::readFileBytes(target);
        expectRefused(test::runCli(s.composite("-o " + shellQuote(link))), "which this run reads");
        EXPECT_TRUE(test::readFileBytes(target) == before) << target;
        // not even with --overwrite-input, which is for the EXR inputs only
        expectRefused(test::runCli(s.composite("-o " + shellQuote(link) + " --overwrite-input")), "which this run reads");
        EXPECT_TRUE(test::readFileBytes(target) == before) << target;
    }
}

TEST(OutputSafety, HardLinkToTheInputCountsAsTheInput) {
    Sample s;
    const std::string alias = s.dir.file("alias.exr");
    fs::create_hard_link(s.input, alias);
    const std::string before = test::readFileBytes(s.input);
    expectRefused(test::runCli(s.composite("-o " + shellQuote(alias))), "--overwrite-input");
    EXPECT_TRUE(test::readFileBytes(s.input) == before);
    // allowed on request: the composited frame is renamed into place under the output's name,
    // which breaks the link, so the other name keeps the original frame
    const auto allowed = test::runCli(s.composite("-o " + shellQuote(alias) + " --overwrite-input"));
    ASSERT_EQ(allowed.exit_code, 0) << allowed.output;
    EXPECT_TRUE(test::readFileBytes(alias) != before);
    EXPECT_TRUE(test::readFileBytes(s.input) == before);
}

TEST(OutputSafety, BatchPreviewPatternNamingTheInputsIsRefused) {
    test::ScratchDir dir;
    const std::string input = test::writeSequence(dir.path() / "in", {1, 2});
    const std::string scene = test::writeSequenceScene(dir.path());
    const std::string before = test::readFileBytes(FramePattern(input).path(1));
    const auto r = test::runCli("batch " + shellQuote(input) + " -o " + shellQuote(dir.file("out/c.####.exr")) +
                                " --decals " + shellQuote(scene) + " --device cpu --preview " + shellQuote(input) +
                                " --frames 1-2 -q");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("the preview would replace the input"), std::string::npos) << r.output;
    EXPECT_TRUE(test::readFileBytes(FramePattern(input).path(1)) == before);
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

TEST(OutputFolders, CompositeCreatesMissingFoldersForTheOutputAndThePreview) {
    Sample s;
    const std::string out = s.dir.file("shots/a/b/out.exr"), preview = s.dir.file("previews/p/out.png");
    const auto r = test::runCli(s.composite("-o " + shellQuote(out) + " --preview " + shellQuote(preview)));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GT(fs::file_size(out), 0u);
    EXPECT_GT(fs::file_size(preview), 0u);
}

TEST(OutputFolders, AFailedWriteTakesBackTheFoldersItMade) {
    Sample s;
    std::ofstream(s.dir.file("blocker")) << "a file where a folder should be";
    const std::string preview = s.dir.file("previews/p/out.png");
    const auto r = test::runCli(s.composite("-o " + shellQuote(s.dir.file("blocker/out.exr")) + " --preview " +
                                            shellQuote(preview)));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("blocker/out.exr"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(s.dir.file("previews"))) << r.output;
}

}  // namespace
}  // namespace decalcomp
