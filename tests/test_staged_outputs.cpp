// A frame's outputs written in two halves (decalcomp/pipeline.hpp StagedOutputs): staged, every
// output sits in a temporary and none in place; committed, all are in place and no temporary is
// left; dropped uncommitted or failed half-way, nothing is left, not even the folders it made.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/temporary_files.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;

// Every file under `dir` (recursively) whose name marks it as a temporary.
std::set<std::string> temporariesUnder(const fs::path& dir) {
    std::set<std::string> found;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().filename().string().find(".tmp-") != std::string::npos) found.insert(it->path().string());
    return found;
}

struct Outputs {
    test::ScratchDir dir;
    ExrImage image;
    std::string a, b, preview;  // in folders that do not exist yet
    Outputs() {
        const std::string input = dir.file("in.exr");
        const test::CommandResult generated = test::runGenerator("--width 32 --height 16", input);
        EXPECT_EQ(generated.exit_code, 0) << generated.output;
        image = readExr(input);
        a = (dir.path() / "new" / "a.exr").string();
        b = (dir.path() / "new" / "deeper" / "b.exr").string();
        preview = (dir.path() / "new" / "preview.png").string();
    }
    StagedOutputs stage(const std::vector<std::string>& paths) const {
        std::vector<PendingOutput> pending;
        for (const std::string& path : paths) pending.push_back({&image, path});
        return stageOutputsTogether(pending, &preview,
                                    [](const std::string& temporary) { std::ofstream(temporary) << "png bytes"; });
    }
};

TEST(StagedOutputs, NothingIsInPlaceBeforeTheCommitAndEverythingAfter) {
    const Outputs o;
    const int live_before = liveTemporaryCount();
    StagedOutputs staged = o.stage({o.a, o.b});
    for (const std::string& path : {o.a, o.b, o.preview}) EXPECT_FALSE(fs::exists(path)) << path;
    EXPECT_EQ(temporariesUnder(o.dir.path() / "new").size(), 3u);
    EXPECT_EQ(liveTemporaryCount(), live_before + 3);
    EXPECT_EQ(staged.stats().pixels_reencoded, 2u * 32 * 16 * o.image.parts.size());  // both outputs, every pixel

    staged.commit();
    for (const std::string& path : {o.a, o.b, o.preview}) EXPECT_TRUE(fs::exists(path)) << path;
    EXPECT_EQ(temporariesUnder(o.dir.path()), std::set<std::string>{});
    EXPECT_EQ(liveTemporaryCount(), live_before);
    EXPECT_EQ(readExr(o.a).parts.front().channels.size(), o.image.parts.front().channels.size());
    staged.discard();  // after a commit: nothing to take back
    EXPECT_TRUE(fs::exists(o.b));
}

TEST(StagedOutputs, DroppedUncommittedLeavesNothingNotEvenItsFolders) {
    const Outputs o;
    const int live_before = liveTemporaryCount();
    {
        StagedOutputs staged = o.stage({o.a, o.b});
        StagedOutputs moved = std::move(staged);  // the moved-from object holds nothing to discard
        EXPECT_EQ(temporariesUnder(o.dir.path() / "new").size(), 3u);
    }
    EXPECT_FALSE(fs::exists(o.dir.path() / "new"));
    EXPECT_EQ(liveTemporaryCount(), live_before);
}

TEST(StagedOutputs, AFailedWriteTakesBackWhatItHadWritten) {
    const Outputs o;
    const int live_before = liveTemporaryCount();
    std::ofstream(o.dir.file("a-file")) << "not a folder";
    const std::string impossible = o.dir.file("a-file") + "/c.exr";  // below a regular file
    EXPECT_THROW(o.stage({o.a, impossible}), Error);
    EXPECT_FALSE(fs::exists(o.dir.path() / "new"));  // o.a's and the preview's temporaries, and their folder
    EXPECT_EQ(temporariesUnder(o.dir.path()), std::set<std::string>{});
    EXPECT_EQ(liveTemporaryCount(), live_before);
}

}  // namespace
}  // namespace decalcomp
