// Command-line mistakes get decalcomp's one-line error with the command, the option and what to
// do, and exit 2: never CLI11's raw text, a 300-digit bound or "internal error".
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

void expectUsageError(const test::CommandResult& r, const std::string& needle) {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.rfind("decalcomp: error: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "\n"), 1u) << r.output;  // one line
}

TEST(UsageErrors, MisspeltCommandSuggestsTheNearest) {
    expectUsageError(test::runCli("compsite in.exr"), "compsite: not a command; did you mean 'composite'?");
    expectUsageError(test::runCli("bach in.####.exr"), "did you mean 'batch'?");
    expectUsageError(test::runCli("frobnicate"), "frobnicate: not a command; expected one of");
    expectUsageError(test::runCli(""), "no command given");
}

TEST(UsageErrors, NumericBoundsAreReadable) {
    const auto r = test::runCli("batch in.####.exr -o out/ --decals s.json --threads -5");
    expectUsageError(r, "batch: --threads: Value -5 not in range 0 to 1024");
    EXPECT_EQ(r.output.find("179769313486"), std::string::npos) << r.output;
}

TEST(UsageErrors, MissingArgumentsNameTheCommandAndItsHelp) {
    expectUsageError(test::runCli("composite"), "'decalcomp composite --help' lists the options");
    expectUsageError(test::runCli("composite a.exr --decals s.json -o o.exr --bogus"), "--bogus");
}

TEST(UsageErrors, BadPixelFilterNamesTheOptionAndTheSpellings) {
    for (const char* command : {"composite a.exr --decals s.json -o o.exr", "batch in.####.exr -o out/ --decals s.json"}) {
        expectUsageError(test::runCli(std::string(command) + " --pixel-filter gauss:2"),
                         "--pixel-filter: 'gauss:2': expected none or TYPE:WIDTH[:fast] with TYPE box, gaussian or "
                         "blackman-harris");
        expectUsageError(test::runCli(std::string(command) + " --pixel-filter box:12"),
                         "--pixel-filter: 'box:12': the width must be a number of pixels in (0, 8]");
    }
}

TEST(UsageErrors, HelpAndVersionStillExitZero) {
    EXPECT_EQ(test::runCli("--help").exit_code, 0);
    EXPECT_EQ(test::runCli("composite --help").exit_code, 0);
    const auto version = test::runCli("--version");
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_NE(version.output.find("decalcomp"), std::string::npos);
}

TEST(UsageErrors, FolderWhereAFileIsExpectedSaysSo) {
    test::ScratchDir dir;
    const auto r = test::runCli("composite " + test::shellQuote(test::dataPath("sample/gbuffer.exr")) + " --decals " +
                                test::shellQuote(dir.path().string()) + " --device cpu -o " +
                                test::shellQuote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find(dir.path().string() + ": is a folder, not a file; give the scene file itself"),
              std::string::npos)
        << r.output;
    const auto exr = test::runCli("composite " + test::shellQuote(dir.path().string()) + " --decals " +
                                  test::shellQuote(test::dataPath("sample/scene.json")) + " --device cpu -o " +
                                  test::shellQuote(dir.file("out.exr")));
    EXPECT_EQ(exr.exit_code, 3) << exr.output;
    EXPECT_NE(exr.output.find("is a folder, not a file; give the EXR file itself"), std::string::npos) << exr.output;
}

// libpng prints its own "libpng error: ..." line before OIIO reports the failure; only
// decalcomp's line may reach the user.
TEST(UsageErrors, BrokenPngTextureGivesOneLineOfOurOwn) {
    namespace fs = std::filesystem;
    test::ScratchDir dir;
    fs::copy(test::dataPath("sample"), dir.path(), fs::copy_options::recursive);
    const std::string texture = dir.file("textures/scorch.png");
    const std::string bytes = test::readFileBytes(texture);
    std::ofstream(texture, std::ios::binary) << bytes.substr(0, 300);  // header intact, pixel data cut
    const auto r = test::runCli("composite " + test::shellQuote(dir.file("gbuffer.exr")) + " --decals " +
                                test::shellQuote(dir.file("scene.json")) + " --camera " +
                                test::shellQuote(dir.file("camera.json")) + " --device cpu -o " +
                                test::shellQuote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_EQ(r.output.rfind("decalcomp: error: " + dir.file("scene.json") + ": textures.scorch.albedo: ", 0), 0u)
        << r.output;
    EXPECT_EQ(r.output.find("libpng error"), std::string::npos) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "\n"), 1u) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

}  // namespace
}  // namespace decalcomp
