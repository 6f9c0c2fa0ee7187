// The beauty in batch (issue 14, item 3): a short generated sequence with light passes, each frame
// another view (lens shift), composited by `batch` and by `composite` frame by frame: the same
// files bit for bit, and every frame's beauty rebuilt.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstring>

#include "decalcomp/exr_file.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::shellQuote;

TEST(BeautyBatch, EveryFrameRebuildsLikeComposite) {
    test::ScratchDir dir;
    const std::vector<int> frames = {1, 2, 3, 4};
    std::filesystem::create_directories(dir.path() / "in");
    for (int f : frames) {
        const std::string in = dir.file(fmt::format("in/shot.{:04d}.exr", f));
        const auto gen = test::runGenerator(
            fmt::format("--width 96 --height 64 --light-passes --header-camera --lens-shift {},0", 0.1 * (f - 2)), in,
            dir.file(fmt::format("in/shot.{:04d}.camera.json", f)));
        ASSERT_EQ(gen.exit_code, 0) << gen.output;
    }
    const std::string scene = test::writeStaticScene(dir.path());
    const auto batch = test::runCli("batch " + shellQuote(dir.file("in/shot.####.exr")) + " -o " +
                                    shellQuote(dir.file("batch/shot.####.exr")) + " --decals " + shellQuote(scene) +
                                    " --device cpu --beauty on -q");
    ASSERT_EQ(batch.exit_code, 0) << batch.output;
    for (int f : frames) {
        const std::string in = dir.file(fmt::format("in/shot.{:04d}.exr", f));
        const std::string single = dir.file(fmt::format("single.{:04d}.exr", f));
        const auto run = test::runCli("composite " + shellQuote(in) + " --decals " + shellQuote(scene) +
                                      " --device cpu --beauty on -o " + shellQuote(single));
        ASSERT_EQ(run.exit_code, 0) << run.output;
        EXPECT_NE(run.output.find("beauty: rebuilt ViewLayer.Combined.{R,G,B}"), std::string::npos) << run.output;
        const ExrImage input = readExr(in), batched = readExr(dir.file(fmt::format("batch/shot.{:04d}.exr", f)));
        EXPECT_EQ(test::pixelDifference(batched, readExr(single)), "") << "frame " << f;
        std::size_t changed = 0;
        for (const char* c : {"R", "G", "B"}) {
            const std::string name = std::string("ViewLayer.Combined.") + c;
            const auto& a = test::channel(input, name).bytes;
            const auto& b = test::channel(batched, name).bytes;
            for (std::size_t k = 0; k < a.size(); k += 4) changed += std::memcmp(&a[k], &b[k], 4) != 0;
        }
        EXPECT_GT(changed, 100u) << "frame " << f << ": the beauty was not rebuilt";
        if (f > 1) {  // each frame is another view
            EXPECT_NE(test::channel(input, "ViewLayer.Combined.R").bytes,
                      test::channel(readExr(dir.file("in/shot.0001.exr")), "ViewLayer.Combined.R").bytes);
        }
    }
}

}  // namespace
}  // namespace decalcomp
