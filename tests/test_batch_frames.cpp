// Batch building blocks without a device: frame ranges, patterns, discovery, shards (and the
// Slurm environment), per-frame camera files, progress text.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include "decalcomp/batch.hpp"
#include "decalcomp/batch_progress.hpp"
#include "decalcomp/frame_cameras.hpp"
#include "decalcomp/error.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

std::vector<int> iota(int first, int last, int step = 1) {
    std::vector<int> v;
    for (int f = first; f <= last; f += step) v.push_back(f);
    return v;
}

TEST(FrameRange, SimpleRange) { EXPECT_EQ(parseFrameRange("1-240"), iota(1, 240)); }

TEST(FrameRange, RangeWithStep) {
    const auto frames = parseFrameRange("1-240x2");
    EXPECT_EQ(frames, iota(1, 239, 2));
    EXPECT_EQ(frames.size(), 120u);
}

TEST(FrameRange, ListOfSinglesAndRanges) {
    std::vector<int> expected = {1, 5};
    for (int f = 10; f <= 20; ++f) expected.push_back(f);
    EXPECT_EQ(parseFrameRange("1,5,10-20"), expected);
    EXPECT_EQ(parseFrameRange(" 7 , 3 "), (std::vector<int>{7, 3}));  // order as given
}

TEST(FrameRange, DuplicatesAreProcessedOnce) {
    EXPECT_EQ(parseFrameRange("1-5,3,5-6"), (std::vector<int>{1, 2, 3, 4, 5, 6}));
}

TEST(FrameRange, NegativeFrames) {
    EXPECT_EQ(parseFrameRange("-3--1"), (std::vector<int>{-3, -2, -1}));
    EXPECT_EQ(parseFrameRange("-2-1"), (std::vector<int>{-2, -1, 0, 1}));
    EXPECT_EQ(parseFrameRange("-4"), (std::vector<int>{-4}));
}

TEST(FrameRange, ErrorsNameThePart) {
    for (const std::string bad : {"", "5-1", "1-10x0", "a", "1-", "1,,2", "1x2", "1-10x", "99999999999"}) {
        try {
            parseFrameRange(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Usage) << bad;
            EXPECT_NE(std::string(e.what()).find("--frames"), std::string::npos) << e.what();
        }
    }
}

TEST(FramePatternTest, HashesPadToTheirCount) {
    EXPECT_EQ(FramePattern("shot/frame.####.exr").path(7), "shot/frame.0007.exr");
    EXPECT_EQ(FramePattern("f.#.exr").path(12), "f.12.exr");
    EXPECT_EQ(FramePattern("f.####.exr").path(123456), "f.123456.exr");
    EXPECT_EQ(FramePattern("f.####.exr").path(-3), "f.-003.exr");  // as printf %04d
}

TEST(FramePatternTest, PrintfStyle) {
    EXPECT_EQ(FramePattern("frame.%04d.exr").path(42), "frame.0042.exr");
    EXPECT_EQ(FramePattern("frame_%d.exr").path(42), "frame_42.exr");
    EXPECT_EQ(FramePattern("100%.%03d.exr").path(5), "100%.005.exr");  // a lone % is text
}

TEST(FramePatternTest, MatchIsTheInverseOfPath) {
    const FramePattern p("/x/f.####.exr");
    EXPECT_EQ(p.match("/x/f.0042.exr"), 42);
    EXPECT_EQ(p.match("/x/f.12345.exr"), 12345);
    EXPECT_FALSE(p.match("/x/f.42.exr"));     // not padded
    EXPECT_FALSE(p.match("/x/f.00042.exr"));  // padded too much
    EXPECT_FALSE(p.match("/x/f.abcd.exr"));
    EXPECT_FALSE(p.match("/x/g.0042.exr"));
}

TEST(FramePatternTest, NeedsExactlyOneToken) {
    EXPECT_THROW(FramePattern("frame.exr"), Error);
    EXPECT_THROW(FramePattern("f.####.%04d.exr"), Error);
    EXPECT_TRUE(FramePattern::hasToken("a.%03d.json"));
    EXPECT_FALSE(FramePattern::hasToken("camera.json"));
}

TEST(FramePatternTest, DiscoveryListsMatchingFilesSorted) {
    test::ScratchDir dir;
    for (const char* name : {"f.0010.exr", "f.0002.exr", "f.0003.exr", "f.3.exr", "g.0001.exr", "f.0004.exr.tmp"})
        std::ofstream(dir.file(name)) << "x";
    EXPECT_EQ(discoverFrames(FramePattern(dir.file("f.####.exr"))), (std::vector<int>{2, 3, 10}));
    EXPECT_THROW(discoverFrames(FramePattern(dir.file("none.####.exr"))), Error);
}

TEST(Shards, ParseIsOneBased) {
    const Shard s = parseShard("3/8");
    EXPECT_EQ(s.index, 3);
    EXPECT_EQ(s.count, 8);
    for (const std::string bad : {"0/8", "9/8", "3", "a/b", "1/0", "-1/4"}) EXPECT_THROW(parseShard(bad), Error) << bad;
}

// Every frame lands in exactly one shard, whatever the sizes.
TEST(Shards, EveryFrameInExactlyOneShard) {
    for (ShardMode mode : {ShardMode::Interleaved, ShardMode::Contiguous})
        for (int n : {0, 1, 5, 17, 240})
            for (int count : {1, 2, 3, 8, 20}) {
                const std::vector<int> frames = iota(1, n);
                std::multiset<int> seen;
                std::size_t smallest = frames.size(), largest = 0;
                for (int i = 1; i <= count; ++i) {
                    const auto part = shardFrames(frames, {i, count}, mode);
                    seen.insert(part.begin(), part.end());
                    smallest = std::min(smallest, part.size());
                    largest = std::max(largest, part.size());
                }
                EXPECT_EQ(seen, std::multiset<int>(frames.begin(), frames.end()))
                    << shardModeName(mode) << " n=" << n << " count=" << count;
                EXPECT_LE(largest - std::min(smallest, largest), 1u);  // balanced
            }
}

TEST(Shards, InterleavedAndContiguousOrder) {
    const std::vector<int> frames = iota(1, 10);
    EXPECT_EQ(shardFrames(frames, {2, 3}, ShardMode::Interleaved), (std::vector<int>{2, 5, 8}));
    EXPECT_EQ(shardFrames(frames, {1, 3}, ShardMode::Contiguous), (std::vector<int>{1, 2, 3, 4}));
    EXPECT_EQ(shardFrames(frames, {2, 3}, ShardMode::Contiguous), (std::vector<int>{5, 6, 7}));
    EXPECT_EQ(shardFrames(frames, {3, 3}, ShardMode::Contiguous), (std::vector<int>{8, 9, 10}));
}

EnvironmentLookup environment(std::map<std::string, std::string> vars) {
    auto shared = std::make_shared<std::map<std::string, std::string>>(std::move(vars));
    return [shared](const char* name) -> const char* {
        auto it = shared->find(name);
        return it == shared->end() ? nullptr : it->second.c_str();
    };
}

TEST(Shards, SlurmArrayFromOne) {
    const auto s = shardFromSlurmEnvironment(
        environment({{"SLURM_ARRAY_TASK_ID", "5"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "8"}}));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 5);
    EXPECT_EQ(s->count, 8);
}

TEST(Shards, SlurmArrayFromZeroAndWithSteps) {
    auto s = shardFromSlurmEnvironment(
        environment({{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 1);
    // --array=10-40:10 -> ids 10, 20, 30, 40
    s = shardFromSlurmEnvironment(environment({{"SLURM_ARRAY_TASK_ID", "30"},
                                               {"SLURM_ARRAY_TASK_MIN", "10"},
                                               {"SLURM_ARRAY_TASK_STEP", "10"},
                                               {"SLURM_ARRAY_TASK_COUNT", "4"}}));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 3);
    EXPECT_EQ(s->count, 4);
}

TEST(Shards, SlurmOutsideAnArrayOrInconsistent) {
    EXPECT_FALSE(shardFromSlurmEnvironment(environment({{"SLURM_JOB_ID", "12"}})));
    EXPECT_THROW(shardFromSlurmEnvironment(environment({{"SLURM_ARRAY_TASK_ID", "3"}})), Error);  // no COUNT
    EXPECT_THROW(shardFromSlurmEnvironment(environment(
                     {{"SLURM_ARRAY_TASK_ID", "9"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "3"}})),
                 Error);  // a list with gaps: 1,5,9
    EXPECT_THROW(shardFromSlurmEnvironment(environment(
                     {{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "3"}})),
                 Error);
}

TEST(BatchWorkers, AQuarterOfTheHardwareThreadsSharedAmongTheDevicesFromTwoToEight) {
    EXPECT_EQ(defaultCompositeWorkers(1, 1), 2);
    EXPECT_EQ(defaultCompositeWorkers(2, 1), 2);   // the 2-core VM: as before
    EXPECT_EQ(defaultCompositeWorkers(16, 1), 4);  // the GPU host: the reader stays busy
    EXPECT_EQ(defaultCompositeWorkers(20, 1), 5);
    EXPECT_EQ(defaultCompositeWorkers(16, 2), 2);
    EXPECT_EQ(defaultCompositeWorkers(128, 8), 4);
    EXPECT_EQ(defaultCompositeWorkers(64, 1), 8);  // each holds a frame: capped
    EXPECT_EQ(defaultCompositeWorkers(16, 0), 4);  // no device (--io-only): as one
}

TEST(BatchPlanTest, ExplicitShardWinsOverSlurm) {
    BatchRequest r;
    r.input = "in.####.exr";
    r.output = "out.####.exr";
    r.frames = "1-10";
    r.getenv = environment({{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
    BatchPlan plan = planBatch(r);
    EXPECT_EQ(plan.frames, (std::vector<int>{2, 4, 6, 8, 10}));
    EXPECT_NE(plan.shard_source.find("SLURM_ARRAY_TASK_ID=2"), std::string::npos);
    r.shard = Shard{1, 5};
    r.shard_mode = ShardMode::Contiguous;
    plan = planBatch(r);
    EXPECT_EQ(plan.frames, (std::vector<int>{1, 2}));
    EXPECT_EQ(plan.range_frames, 10);
    r.shard.reset();
    r.shard_from_environment = false;
    EXPECT_EQ(planBatch(r).frames.size(), 10u);
}

const char* kRows = "[[1,0,0,0],[0,1,0,0],[0,0,1,-5],[0,0,0,1]]";
const char* kProjection = "[[1.5,0,0,0],[0,2,0,0],[0,0,-1.002,-0.2002],[0,0,-1,0]]";

TEST(PerFrameCameras, ObjectFormWithDefaultProjection) {
    test::ScratchDir dir;
    const std::string path = dir.file("cameras.json");
    std::ofstream(path) << "{\"projection\": " << kProjection << ", \"frames\": {\"1\": {\"world_to_camera\": " << kRows
                        << "}, \"2\": {\"world_to_camera\": [[1,0,0,1],[0,1,0,0],[0,0,1,-5],[0,0,0,1]]}}}";
    const auto cameras = loadPerFrameCameras(path);
    ASSERT_EQ(cameras.size(), 2u);
    EXPECT_DOUBLE_EQ(cameras.at(1).world_to_camera[3][2], -5.0);  // row 2, column 3
    EXPECT_DOUBLE_EQ(cameras.at(2).world_to_camera[3][0], 1.0);
    EXPECT_DOUBLE_EQ(cameras.at(2).projection[0][0], 1.5);
    const FrameCameras provider("", path);
    EXPECT_TRUE(provider.explicitCamera(2));
    try {
        provider.explicitCamera(3);
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no camera for frame 3"), std::string::npos) << e.what();
    }
}

TEST(PerFrameCameras, ArrayFormAndErrors) {
    test::ScratchDir dir;
    const std::string path = dir.file("cameras.json");
    std::ofstream(path) << "{\"frames\": [{\"frame\": 7, \"world_to_camera\": " << kRows << ", \"projection\": "
                        << kProjection << "}]}";
    EXPECT_EQ(loadPerFrameCameras(path).count(7), 1u);
    auto expectError = [&](const std::string& text, const std::string& needle) {
        std::ofstream(path) << text;
        try {
            loadPerFrameCameras(path);
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError("{\"frames\": {\"1\": {\"world_to_camera\": " + std::string(kRows) + "}}}", "frames[\"1\"]: missing 'projection'");
    expectError("{\"frames\": {\"x\": {}}}", "whole frame number");
    expectError("{\"frames\": [{\"frame\": 1, \"world_to_camera\": " + std::string(kRows) + ", \"projection\": " +
                    kProjection + "}, {\"frame\": 1, \"world_to_camera\": " + kRows + ", \"projection\": " + kProjection +
                    "}]}",
                "given twice");
    expectError("{\"cameras\": []}", "expected an object with \"frames\"");
}

TEST(BatchProgressText, DurationsAndRates) {
    EXPECT_EQ(formatDuration(7), "0:07");
    EXPECT_EQ(formatDuration(62), "1:02");
    EXPECT_EQ(formatDuration(3723), "1:02:03");
    BatchProgress p;
    p.total = 100;
    p.written = 20;
    p.skipped = 30;
    p.elapsed_s = 10;
    EXPECT_DOUBLE_EQ(framesPerSecond(p), 2.0);  // skipped frames cost nothing
    EXPECT_DOUBLE_EQ(*secondsLeft(p), 25.0);
}

TEST(BatchProgressText, LinesAndBar) {
    BatchReport report;
    report.plan.frames = {1, 2};
    report.progress.total = 2;
    report.devices = {"dev"};
    std::ostringstream lines;
    ProgressPrinter printer(lines, ProgressStyle::Lines);
    printer.started(report);
    BatchProgress p{2, 1, 0, 0, 0.5};
    printer.frameFinished(FrameResult{1, FrameStatus::Written, "o.0001.exr", "", std::nullopt}, p);
    p.failed = 1;
    printer.frameFinished(FrameResult{2, FrameStatus::Failed, "o.0002.exr", "broken", ErrorKind::Input}, p);
    printer.finished(report);
    EXPECT_NE(lines.str().find("frame 1 written o.0001.exr (1/2, 2.00 fps"), std::string::npos) << lines.str();
    EXPECT_NE(lines.str().find("frame 2 FAILED: broken"), std::string::npos) << lines.str();
    EXPECT_EQ(lines.str().find('\r'), std::string::npos);

    std::ostringstream bar;
    ProgressPrinter barPrinter(bar, ProgressStyle::Bar);
    barPrinter.frameFinished(FrameResult{1, FrameStatus::Written, "o.0001.exr", "", std::nullopt}, BatchProgress{2, 1, 0, 0, 0.5});
    EXPECT_NE(bar.str().find("\r["), std::string::npos) << bar.str();
    EXPECT_NE(bar.str().find("1/2 frames, 2.00 fps, 0:01 left"), std::string::npos) << bar.str();

    std::ostringstream quiet;
    ProgressPrinter quietPrinter(quiet, ProgressStyle::Quiet);
    quietPrinter.started(report);
    quietPrinter.frameFinished(FrameResult{2, FrameStatus::Failed, "o", "broken", ErrorKind::Input}, p);
    quietPrinter.finished(report);
    EXPECT_TRUE(quiet.str().empty());
}

// A slow kernel build's notice goes above the bar, which the next frame draws again.
TEST(BatchProgressPrinter, SlowBuildNoticeClearsTheBarAndIsItsOwnLine) {
    std::ostringstream bar;
    ProgressPrinter printer(bar, ProgressStyle::Bar);
    printer.frameFinished(FrameResult{1, FrameStatus::Written, "o.0001.exr", "", std::nullopt},
                          BatchProgress{2, 1, 0, 0, 0.5});
    const std::size_t drawn = bar.str().size();
    printer.slowBuild("GPU: still compiling");
    const std::string after = bar.str().substr(drawn);
    EXPECT_EQ(after.front(), '\r');
    EXPECT_NE(after.find("\rdecalcomp: note: GPU: still compiling\n"), std::string::npos) << after;

    std::ostringstream quiet;
    ProgressPrinter quietPrinter(quiet, ProgressStyle::Quiet);
    quietPrinter.slowBuild("GPU: still compiling");
    EXPECT_TRUE(quiet.str().empty());
}

}  // namespace
}  // namespace decalcomp
