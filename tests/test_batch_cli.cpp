// `decalcomp batch` end to end on PoCL: every frame equals single-frame compositing of that frame
// (animated decals included), per-frame cameras, --resume, --keep-going, shards, the Slurm
// environment, progress output, and a batch SIGKILLed at random moments then resumed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <thread>

#include "decalcomp/exr_file.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::shellQuote;

struct Sequence {
    test::ScratchDir dir;
    std::string input, scene, output;
    explicit Sequence(const std::vector<int>& frames, bool header_camera = true, int width = 64, int height = 48) {
        input = test::writeSequence(dir.path() / "in", frames, width, height, "frame.####.exr", header_camera);
        scene = test::writeSequenceScene(dir.path());
        output = (dir.path() / "out" / "comp.%04d.exr").string();
    }
    std::string out(int frame) const { return FramePattern(output).path(frame); }
    std::string in(int frame) const { return FramePattern(input).path(frame); }
    std::string args() const {
        return shellQuote(input) + " -o " + shellQuote(output) + " --decals " + shellQuote(scene) + " --device cpu";
    }
};

std::vector<int> writtenFrames(const std::string& log) {
    std::vector<int> frames;
    static const std::regex line("frame (-?[0-9]+) written");
    for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator(); ++it)
        frames.push_back(std::stoi((*it)[1].str()));
    return frames;
}

// Every file under `dir`, relative names.
std::set<std::string> filesUnder(const fs::path& dir) {
    std::set<std::string> names;
    if (!fs::exists(dir)) return names;  // e.g. a run killed before it made the output folder
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (!e.is_directory()) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

TEST(BatchCli, EveryFrameMatchesSingleFrameCompositing) {
    const std::vector<int> frames = {1, 2, 3, 4, 5, 6, 7, 8};
    Sequence s(frames);
    const auto r = test::runCli("batch " + s.args() + " --frames 1-8 --progress lines");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(writtenFrames(r.output).size(), 8u) << r.output;
    ComputeDevice device("cpu");
    const DecalScene scene = loadScene(s.scene);
    int changed = 0;
    for (int f : frames) {
        const ExrImage expected = test::expectedFrame(s.in(f), scene, f, device);
        EXPECT_EQ(test::pixelDifference(readExr(s.out(f)), expected), "") << "frame " << f;
        changed += test::pixelDifference(expected, readExr(s.in(f))) != "";
    }
    EXPECT_EQ(changed, 8) << "decals should land on every frame";
    // The animated decals make frames differ beyond the camera motion: frame 4 has the "flash"
    // decal, frame 2 not; check through the library that the scene really animates.
    EXPECT_EQ(sceneAtFrame(scene, 2).decals.size(), 2u);
    EXPECT_EQ(sceneAtFrame(scene, 4).decals.size(), 3u);
}

TEST(BatchCli, PerFrameCamerasFileAndSidecarPattern) {
    const std::vector<int> frames = {1, 2, 3};
    Sequence s({1, 2, 3, 4}, /*header_camera=*/false);  // cameras for frames 1-3 only
    // One file with a camera per frame, and one sidecar per frame.
    nlohmann::json doc;
    for (int f : frames) {
        const Camera c = test::sequenceCamera(f, 64, 48);
        const std::string sidecar = (s.dir.path() / fmt::format("cam.{:03d}.json", f)).string();
        saveCameraJson(c, 64, 48, sidecar);
        std::ifstream in(sidecar);
        doc["frames"][std::to_string(f)] = nlohmann::json::parse(in);
    }
    const std::string cameras = s.dir.file("cameras.json");
    std::ofstream(cameras) << doc.dump();
    ComputeDevice device("cpu");
    const DecalScene scene = loadScene(s.scene);
    for (const std::string& option : {"--cameras " + shellQuote(cameras),
                                      "--camera " + shellQuote(s.dir.file("cam.%03d.json"))}) {
        fs::remove_all(s.dir.path() / "out");
        const auto r = test::runCli("batch " + s.args() + " --frames 1-3 -q " + option);
        ASSERT_EQ(r.exit_code, 0) << option << "\n" << r.output;
        for (int f : frames)
            EXPECT_EQ(test::pixelDifference(readExr(s.out(f)),
                                            test::expectedFrame(s.in(f), scene, f, device, test::sequenceCamera(f, 64, 48))),
                      "")
                << option << " frame " << f;
    }
    // A frame the cameras file lacks fails with the file and frame named.
    const auto r = test::runCli("batch " + s.args() + " --frames 1-4 -q --cameras " + shellQuote(cameras));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("no camera for frame 4"), std::string::npos) << r.output;
}

TEST(BatchCli, ResumeSkipsCompleteOutputs) {
    Sequence s({1, 2, 3, 4, 5, 6});
    ASSERT_EQ(test::runCli("batch " + s.args() + " -q").exit_code, 0);  // frames found by listing
    std::map<int, fs::file_time_type> before;
    for (int f = 1; f <= 6; ++f) before[f] = fs::last_write_time(s.out(f));
    fs::remove(s.out(2));
    fs::remove(s.out(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto r = test::runCli("batch " + s.args() + " --frames 1-6 --resume --progress lines");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::vector<int> written = writtenFrames(r.output);  // in the order they finished
    std::sort(written.begin(), written.end());
    EXPECT_EQ(written, (std::vector<int>{2, 5})) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "skipped: "), 4u) << r.output;
    for (int f : {1, 3, 4, 6}) EXPECT_EQ(fs::last_write_time(s.out(f)), before[f]) << "frame " << f << " rewritten";
    for (int f = 1; f <= 6; ++f) EXPECT_TRUE(fs::exists(s.out(f)));
}

TEST(BatchCli, KeepGoingListsFailedFramesAndExitsNonZero) {
    Sequence s({1, 2, 3, 4, 5, 6});
    std::ofstream(s.in(3)) << "not an exr";
    fs::remove(s.in(5));
    const auto r = test::runCli("batch " + s.args() + " --frames 1-6 --keep-going --progress lines");
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("2 of 6 frames failed: 3, 5"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("frame.0003.exr: not an OpenEXR file"), std::string::npos) << r.output;
    for (int f : {1, 2, 4, 6}) EXPECT_TRUE(fs::exists(s.out(f))) << f;
    for (int f : {3, 5}) EXPECT_FALSE(fs::exists(s.out(f))) << f;

    // Without --keep-going the first failure stops the batch with its own message and code (frames
    // 3-4: with frame 5's input missing the range would be refused before it starts,
    // test_batch_failures.cpp).
    fs::remove_all(s.dir.path() / "out");
    const auto stop = test::runCli("batch " + s.args() + " --frames 3-4 -q");
    EXPECT_EQ(stop.exit_code, 3) << stop.output;
    EXPECT_NE(stop.output.find("decalcomp: error: "), std::string::npos) << stop.output;
    EXPECT_NE(stop.output.find("frame.0003.exr: not an OpenEXR file"), std::string::npos) << stop.output;
    for (const std::string& name : filesUnder(s.dir.path() / "out")) EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
}

TEST(BatchCli, ShardsWriteEveryFrameExactlyOnce) {
    Sequence s({1, 2, 3, 4, 5, 6, 7, 8});
    for (const std::string mode : {"interleaved", "contiguous"}) {
        fs::remove_all(s.dir.path() / "out");
        std::multiset<int> written;
        for (int i = 1; i <= 3; ++i) {
            const auto r = test::runCli("batch " + s.args() + " --frames 1-8 --progress lines --shard-mode " + mode +
                                        " --shard " + std::to_string(i) + "/3");
            ASSERT_EQ(r.exit_code, 0) << r.output;
            for (int f : writtenFrames(r.output)) written.insert(f);
        }
        EXPECT_EQ(written, (std::multiset<int>{1, 2, 3, 4, 5, 6, 7, 8})) << mode;
        EXPECT_EQ(filesUnder(s.dir.path() / "out").size(), 8u);
    }
}

// A batch says it when a device's kernel build runs long, once per program, beside its progress.
TEST(BatchCli, KernelBuildsRunningLongSaySo) {
    Sequence s({1, 2, 3});
    const auto r = test::runCommand("DECALCOMP_BUILD_NOTICE_AFTER=0 " + shellQuote(DECALCOMP_CLI) + " batch " +
                                    s.args() + " --frames 1-3 --progress lines");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "decalcomp: note: "), 1u) << r.output;
    EXPECT_NE(r.output.find("still compiling the OpenCL kernels for binning and point-sampled shading"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(writtenFrames(r.output).size(), 3u) << r.output;
}

TEST(BatchCli, SlurmArrayVariablesChooseTheShard) {
    test::ScratchDir dir;
    const std::string args = "batch " + shellQuote(dir.file("f.####.exr")) + " -o " + shellQuote(dir.file("o.####.exr")) +
                             " --frames 1-8 --list-frames";
    const std::string env = "SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=4 ";
    auto r = test::runCommand(env + shellQuote(DECALCOMP_CLI) + " " + args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output, "2\n6\n");
    r = test::runCommand(env + shellQuote(DECALCOMP_CLI) + " " + args + " --shard-mode contiguous");
    EXPECT_EQ(r.output, "3\n4\n");
    r = test::runCommand(env + shellQuote(DECALCOMP_CLI) + " " + args + " --shard 1/2");  // explicit wins
    EXPECT_EQ(r.output, "1\n3\n5\n7\n");
    r = test::runCommand(env + shellQuote(DECALCOMP_CLI) + " " + args + " --no-slurm-shard");
    EXPECT_EQ(r.output, "1\n2\n3\n4\n5\n6\n7\n8\n");
    r = test::runCommand("SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=4 " +
                         shellQuote(DECALCOMP_CLI) + " " + args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("SLURM_ARRAY_TASK_ID=7"), std::string::npos) << r.output;
}

TEST(BatchCli, QuietPrintsNothingAndLinesShowRate) {
    Sequence s({1, 2});
    auto r = test::runCli("batch " + s.args() + " --quiet");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output, "");
    r = test::runCli("batch " + s.args() + " --resume");  // not a terminal: plain lines
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("frame 2 skipped"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("0 written, 2 skipped, 0 failed of 2 frames"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\r'), std::string::npos);
}

TEST(BatchCli, UsageErrors) {
    Sequence s({1});
    auto r = test::runCli("batch " + shellQuote(s.dir.file("in/frame.0001.exr")) + " -o x.####.exr --decals " +
                          shellQuote(s.scene));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("no frame number in the pattern"), std::string::npos) << r.output;
    r = test::runCli("batch " + s.args() + " --shard 0/4");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    r = test::runCli("batch " + shellQuote(s.input) + " -o " + shellQuote(s.input) + " --decals " + shellQuote(s.scene) +
                     " --device cpu -q");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--overwrite-input"), std::string::npos) << r.output;
    r = test::runCli("batch " + shellQuote(s.input) + " -o " + shellQuote(s.output));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--decals is required"), std::string::npos) << r.output;
}

// The batch is killed with SIGKILL at random moments (device set-up, reading, compositing, in the
// middle of writes) and started again with --resume until a run completes; then every frame must
// equal an uninterrupted run's, byte for byte, and no temporary or partial file may be left.
TEST(BatchKill, SigkillAtRandomMomentsThenResume) {
    const int frames = 24;
    std::vector<int> numbers;
    for (int f = 1; f <= frames; ++f) numbers.push_back(f);
    Sequence s(numbers, true, 240, 180);
    const std::string reference = (s.dir.path() / "ref" / "comp.####.exr").string();
    const auto ref_start = std::chrono::steady_clock::now();
    const auto ref = test::runCli("batch " + shellQuote(s.input) + " -o " + shellQuote(reference) + " --decals " +
                                  shellQuote(s.scene) + " --device cpu -q --frames 1-24");
    ASSERT_EQ(ref.exit_code, 0) << ref.output;
    // Kill moments spread over a whole uninterrupted run (set-up included).
    const int full_run_us = int(std::chrono::duration_cast<std::chrono::microseconds>(
                                    std::chrono::steady_clock::now() - ref_start)
                                    .count());

    const std::string out_pattern = (s.dir.path() / "out" / "comp.####.exr").string();
    const std::vector<std::string> argv_strings = {DECALCOMP_CLI, "batch",    s.input,   "-o",   out_pattern,
                                                   "--decals",    s.scene,    "--device", "cpu", "--frames",
                                                   "1-24",        "--resume", "--quiet"};
    std::mt19937 rng(std::random_device{}());
    int kills = 0, runs = 0, killed_while_writing = 0;  // the last: a temporary was left behind
    int bound_us = full_run_us * 6 / 10;
    bool completed = false;
    const auto test_start = std::chrono::steady_clock::now();
    while (!completed && runs < 60) {
        ++runs;
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            std::vector<char*> argv;
            for (const std::string& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            const int null = ::open("/dev/null", O_WRONLY);
            ::dup2(null, 1);
            ::dup2(null, 2);
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        // Up to 25 kills, each at a random moment within the first 60% of a full run's duration;
        // resumed runs are shorter and finish at some point.
        const bool kill_this = kills < 25;
        const auto delay = std::chrono::microseconds(std::uniform_int_distribution<int>(0, bound_us)(rng));
        const auto started = std::chrono::steady_clock::now();
        int status = 0;
        pid_t done = 0;
        while ((done = ::waitpid(pid, &status, WNOHANG)) == 0) {
            if (kill_this && std::chrono::steady_clock::now() - started >= delay) {
                ::kill(pid, SIGKILL);
                done = ::waitpid(pid, &status, 0);
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        ASSERT_EQ(done, pid);
        if (WIFSIGNALED(status)) {
            EXPECT_EQ(WTERMSIG(status), SIGKILL);
            ++kills;
            for (const std::string& name : filesUnder(s.dir.path() / "out"))
                if (name.find(".tmp-") != std::string::npos) {
                    ++killed_while_writing;
                    break;
                }
        } else {
            ASSERT_TRUE(WIFEXITED(status));
            ASSERT_EQ(WEXITSTATUS(status), 0) << "a resumed run failed";
            completed = true;
            if (kills < 3) {  // finished too soon (a loaded machine times runs unevenly): start over
                fs::remove_all(s.dir.path() / "out");
                bound_us /= 2;
                completed = false;
            }
        }
    }
    ASSERT_TRUE(completed) << runs << " runs";
    EXPECT_GE(kills, 3);
    std::set<std::string> expected;
    for (int f = 1; f <= frames; ++f) {
        const std::string out = FramePattern(out_pattern).path(f);
        expected.insert(fs::path(out).filename().string());
        EXPECT_EQ(test::readFileBytes(out), test::readFileBytes(FramePattern(reference).path(f))) << "frame " << f;
    }
    EXPECT_EQ(filesUnder(s.dir.path() / "out"), expected) << "temporary or partial files left";
    std::cout << "[          ] " << runs << " runs, " << kills << " SIGKILLs (" << killed_while_writing
              << " left a temporary file), "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - test_start).count() << " s\n";
}

TEST(SubmitScript, DryRunBuildsAnSbatchArray) {
    test::ScratchDir dir;
    const std::string script = test::dataPath("../tools/decalcomp-submit");
    const std::string batch = shellQuote(DECALCOMP_CLI) + " batch " + shellQuote(dir.file("in.####.exr")) + " -o " +
                              shellQuote(dir.file("out dir/o.####.exr")) + " --decals s.json --frames 1-10 --resume";
    const auto r = test::runCommand("sh " + shellQuote(script) +
                                    " --dry-run --chunk 4 --partition render --time 0:30:00 --mem 8G --max-running 2 "
                                    "--job-name shot1 --log-dir " +
                                    shellQuote(dir.file("logs")) + " -- " + batch);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const std::string needle : {"sbatch", "--array=1-3%2", "--partition=render", "--time=0:30:00", "--mem=8G",
                                     "--job-name=shot1", "--shard-mode contiguous", "%x-%A_%a.out", "--resume"})
        EXPECT_NE(r.output.find(needle), std::string::npos) << needle << "\n" << r.output;
    // Without a chunk size: one task per frame.
    const auto one = test::runCommand("sh " + shellQuote(script) + " --dry-run -- " + batch);
    EXPECT_NE(one.output.find("--array=1-10"), std::string::npos) << one.output;
    const auto bad = test::runCommand("sh " + shellQuote(script) + " --chunk 0 -- " + batch);
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

// A batch reports a problem every frame shares once, after the frames, not once per frame.
TEST(BatchCli, MissingChannelWarningIsReportedOncePerBatch) {
    Sequence s({1, 2, 3});
    const std::string scene = (s.dir.path() / "roughness.json").string();
    std::ofstream(scene) << R"({"decals": [{"name": "gloss", "translate": [0, 0, 0], "scale": 100,
                                           "affects": {"roughness": {"value": 0.1}}}]})";
    const auto r = test::runCli("batch " + shellQuote(s.input) + " -o " + shellQuote(s.output) + " --decals " +
                                shellQuote(scene) + " --device cpu --frames 1-3 --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::occurrences(r.output, "decals change roughness but the input has no roughness channels"), 1u) << r.output;
    for (int f : {1, 2, 3}) EXPECT_TRUE(fs::exists(s.out(f))) << f;
}

}  // namespace
}  // namespace decalcomp
