// Interrupted runs and failing batches: SIGINT, SIGTERM and SIGHUP during `composite` and `batch`
// remove every temporary and exit 128 + the signal; a batch without --keep-going refuses a range
// with missing inputs before it writes anything, and stops at its first failing frame in frame
// order with every earlier frame written, no later one, and a summary that matches the disk.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "batch/batch_files.hpp"
#include "decalcomp/batch.hpp"
#include "decalcomp/camera.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/frame_pattern.hpp"
#include "decalcomp/temporary_files.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::shellQuote;

// ---- helpers ----

// Polls `condition` every millisecond until it holds (true) or `timeout` passes (false).
bool waitFor(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(1ms);
    }
    return true;
}

// Every file name under `dir`, recursively, relative to it.
std::set<std::string> filesUnder(const fs::path& dir) {
    std::set<std::string> names;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (!it->is_directory(ec)) names.insert(fs::relative(it->path(), dir, ec).string());
    return names;
}

std::set<std::string> temporariesUnder(const fs::path& dir) {
    std::set<std::string> temporaries;
    for (const std::string& name : filesUnder(dir))
        if (name.find(".tmp-") != std::string::npos) temporaries.insert(name);
    return temporaries;
}

// The decalcomp CLI started in the background (fork and exec, no shell in between, so the
// signals' dispositions are the test's own), its stdout and stderr in `log`.
class BackgroundCli {
public:
    BackgroundCli(const std::vector<std::string>& arguments, const std::string& log) {
        std::vector<std::string> argv_strings = {DECALCOMP_CLI};
        argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
        std::vector<char*> argv;  // built before the fork: the child only opens, dups and execs
        for (std::string& a : argv_strings) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_ = ::fork();
        if (pid_ == 0) {
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
    }
    ~BackgroundCli() {
        if (running()) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, &status_, 0);
        }
    }
    BackgroundCli(const BackgroundCli&) = delete;
    BackgroundCli& operator=(const BackgroundCli&) = delete;

    bool started() const { return pid_ > 0; }
    bool running() {
        if (done_ || pid_ <= 0) return false;
        done_ = ::waitpid(pid_, &status_, WNOHANG) == pid_;
        return !done_;
    }
    void signal(int number) const { ::kill(pid_, number); }
    // The exit code once it has ended, within `timeout`; nullopt while it runs, -1 when it died of
    // a signal instead of exiting.
    std::optional<int> exitCode(std::chrono::milliseconds timeout) {
        if (!waitFor([&] { return !running(); }, timeout)) return std::nullopt;
        return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
    }

private:
    pid_t pid_ = -1;
    int status_ = 0;
    bool done_ = false;
};

// One 480x270 frame from decalcomp-gbuffer-gen copied to frames 1..count: big enough that
// reading, compositing and writing a frame take a while, so a signal lands in the middle.
struct LargeSequence {
    test::ScratchDir dir;
    std::string input = (dir.path() / "in" / "frame.####.exr").string();
    std::string camera = dir.file("camera.json");
    std::string scene = test::writeStaticScene(dir.path());
    fs::path out = dir.path() / "out";

    explicit LargeSequence(int count) {
        fs::create_directories(dir.path() / "in");
        const std::string first = FramePattern(input).path(1);
        const auto r = test::runGenerator("--width 480 --height 270 --naming generic", first, camera);
        EXPECT_EQ(r.exit_code, 0) << r.output;
        for (int f = 2; f <= count; ++f) fs::copy_file(first, FramePattern(input).path(f));
    }
};

// Expects the interrupted run to end with 128 + `number`, no temporary left and every output
// there complete; returns whether the run was interrupted (false: it had finished before).
bool expectInterrupted(BackgroundCli& run, int number, const fs::path& out, const std::string& log) {
    const std::optional<int> code = run.exitCode(60s);
    EXPECT_TRUE(code) << "still running 60 s after the signal";
    if (!code || *code == 0) return false;
    EXPECT_EQ(*code, 128 + number) << test::readFileBytes(log);
    EXPECT_NE(test::readFileBytes(log).find("decalcomp: interrupted by SIG"), std::string::npos)
        << test::readFileBytes(log);
    EXPECT_EQ(temporariesUnder(out), std::set<std::string>{}) << "signal " << number;
    for (const std::string& name : filesUnder(out)) {
        if (fs::path(name).extension() != ".exr") continue;
        EXPECT_NO_THROW(readExr((out / name).string())) << name;
    }
    return true;
}

// ---- signals ----

// The batch is signalled as soon as a temporary appears (a frame is being written): it exits 128 +
// the signal with no temporary left, and what it wrote is complete. A run that finished before the
// signal landed is started again (at most three times per signal).
TEST(BatchSignals, SigintSigtermSighupRemoveEveryTemporaryAndExit128PlusSignal) {
    LargeSequence s(24);
    for (int number : {SIGINT, SIGTERM, SIGHUP}) {
        int interrupted = 0;
        for (int attempt = 0; attempt < 3 && interrupted == 0; ++attempt) {
            fs::remove_all(s.out);
            const std::string log = s.dir.file("batch.log");
            BackgroundCli run({"batch", s.input, "-o", (s.out / "comp.####.exr").string(), "--preview",
                               (s.out / "preview.####.png").string(), "--decals", s.scene, "--camera", s.camera,
                               "--device", "cpu", "--frames", "1-24", "--progress", "lines"},
                              log);
            ASSERT_TRUE(run.started());
            // A temporary of the second frame or later, so the first frame's outputs are there too.
            const bool writing = waitFor(
                [&] {
                    if (!run.running()) return true;
                    const std::set<std::string> tmp = temporariesUnder(s.out);
                    return !tmp.empty() && tmp.begin()->find(".0001.") == std::string::npos;
                },
                120s);
            ASSERT_TRUE(writing) << "no temporary appeared in 120 s\n" << test::readFileBytes(log);
            run.signal(number);
            interrupted += expectInterrupted(run, number, s.out, log);
        }
        EXPECT_EQ(interrupted, 1) << "signal " << number << ": three runs finished before the signal";
    }
}

// A signal between frames (after the first frame's outputs appeared): the same exit and no
// temporary, and --resume then finishes the sequence.
TEST(BatchSignals, SigtermBetweenFramesThenResumeCompletesTheSequence) {
    LargeSequence s(6);
    const std::vector<std::string> args = {"batch",    s.input,  "-o",       (s.out / "comp.####.exr").string(),
                                           "--decals", s.scene,  "--camera", s.camera,
                                           "--device", "cpu",    "--frames", "1-6",
                                           "--resume", "--quiet"};
    const std::string log = s.dir.file("batch.log");
    {
        BackgroundCli run(args, log);
        ASSERT_TRUE(run.started());
        ASSERT_TRUE(waitFor([&] { return !run.running() || fs::exists(s.out / "comp.0001.exr"); }, 120s));
        run.signal(SIGTERM);
        expectInterrupted(run, SIGTERM, s.out, log);
    }
    BackgroundCli resume(args, log);
    ASSERT_EQ(resume.exitCode(300s), 0) << test::readFileBytes(log);
    for (int f = 1; f <= 6; ++f) EXPECT_TRUE(fs::exists(s.out / fmt::format("comp.{:04d}.exr", f))) << f;
    EXPECT_EQ(temporariesUnder(s.out), std::set<std::string>{});
}

// `composite` of one large frame with a preview, signalled while a temporary exists; a run that
// finished before the signal landed is started again (at most five times per signal).
TEST(CompositeSignals, SigintAndSigtermRemoveTheTemporaries) {
    test::ScratchDir dir;
    const std::string input = dir.file("frame.exr"), camera = dir.file("camera.json");
    const auto g = test::runGenerator("--width 1280 --height 720 --naming generic", input, camera);
    ASSERT_EQ(g.exit_code, 0) << g.output;
    const std::string scene = test::writeStaticScene(dir.path());
    const fs::path out = dir.path() / "out";
    for (int number : {SIGINT, SIGTERM}) {
        int interrupted = 0;
        for (int attempt = 0; attempt < 5 && interrupted == 0; ++attempt) {
            fs::remove_all(out);
            fs::create_directories(out);
            const std::string log = dir.file("composite.log");
            BackgroundCli run({"composite", input, "--decals", scene, "--camera", camera, "--device", "cpu", "-o",
                               (out / "comp.exr").string(), "--preview", (out / "preview.png").string()},
                              log);
            ASSERT_TRUE(run.started());
            ASSERT_TRUE(waitFor([&] { return !run.running() || !temporariesUnder(out).empty(); }, 120s));
            run.signal(number);
            interrupted += expectInterrupted(run, number, out, log);
        }
        EXPECT_EQ(interrupted, 1) << "signal " << number << ": five runs finished before the signal";
    }
}

// The registry on its own, in a child process (removeLiveTemporaries is for a process that is
// about to exit): live temporaries are removed, committed ones stay under their final names.
TEST(TemporaryFiles, RemoveLiveTemporariesRemovesOnlyUncommittedOnes) {
    test::ScratchDir dir;
    const std::string kept = dir.file("kept.exr"), live_a = dir.file("a.exr"), live_b = dir.file("b.exr");
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const int before = liveTemporaryCount();
        const std::string kept_temporary = temporaryPathFor(kept);
        createTemporary(kept_temporary, kept);
        commitTemporaries({{kept_temporary, kept}});
        createTemporary(temporaryPathFor(live_a), live_a);
        createTemporary(temporaryPathFor(live_b), live_b);
        const bool counted = liveTemporaryCount() == before + 2;
        removeLiveTemporaries();
        ::_exit(counted ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "liveTemporaryCount";
    EXPECT_EQ(filesUnder(dir.path()), std::set<std::string>{"kept.exr"});
}

// A termination signal is handled on one thread while the others run on until _exit: a writer
// that opens its temporary just after the handler removed it must not create it again (found by
// the batch's signal test, where a worker opened its preview after the handler's unlink).
TEST(TemporaryFiles, AWriteAfterTheRemovalLeavesNothingBehind) {
    test::ScratchDir dir;
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const std::string target = dir.file("late.exr");
        const std::string opening_name = createTemporary(temporaryPathFor(target), target);
        removeLiveTemporaries();
        std::ofstream late(opening_name, std::ios::binary | std::ios::trunc);
        late << "written after the removal";
        late.close();
        ::_exit(late ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the late write failed";
    EXPECT_EQ(filesUnder(dir.path()), std::set<std::string>{});
}

TEST(TemporaryFiles, DiscardAndFailedCreateLeaveNothingRegistered) {
    test::ScratchDir dir;
    const int before = liveTemporaryCount();
    const std::string target = dir.file("out.exr"), temporary = temporaryPathFor(target);
    const std::string prefix = ".out.exr.tmp-" + std::to_string(::getpid()) + "-";
    EXPECT_EQ(fs::path(temporary).filename().string().rfind(prefix, 0), 0u) << temporary;
    EXPECT_NE(temporaryPathFor(target), temporary);  // a second write of the output gets its own
    createTemporary(temporary, target);
    EXPECT_TRUE(fs::exists(temporary));
    EXPECT_EQ(liveTemporaryCount(), before + 1);
    discardTemporary(temporary);
    EXPECT_FALSE(fs::exists(temporary));
    EXPECT_EQ(liveTemporaryCount(), before);

    const std::string missing = dir.file("no-such-folder/out.exr");
    const std::string message =
        test::errorMessage(ErrorKind::Output, [&] { createTemporary(temporaryPathFor(missing), missing); });
    EXPECT_EQ(message.rfind(missing + ": ", 0), 0u) << message;
    EXPECT_EQ(liveTemporaryCount(), before);
}

// ---- a batch's inputs and failures ----

constexpr int kWidth = 64, kHeight = 48;

struct SmallSequence {
    test::ScratchDir dir;
    std::string input, scene, output;
    explicit SmallSequence(int count) {
        std::vector<int> frames;
        for (int f = 1; f <= count; ++f) frames.push_back(f);
        input = test::writeSequence(dir.path() / "in", frames, kWidth, kHeight);
        scene = test::writeStaticScene(dir.path());
        output = (dir.path() / "out" / "comp.####.exr").string();
    }
    std::string in(int frame) const { return FramePattern(input).path(frame); }
    std::string out(int frame) const { return FramePattern(output).path(frame); }
    test::CommandResult batch(const std::string& extra) const {
        return test::runCli("batch " + shellQuote(input) + " -o " + shellQuote(output) + " --decals " +
                            shellQuote(scene) + " --device cpu --progress lines " + extra);
    }
};

std::vector<int> framesLogged(const std::string& log, const std::string& what) {
    std::vector<int> frames;
    const std::regex line("frame (-?[0-9]+) " + what);
    for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator(); ++it)
        frames.push_back(std::stoi((*it)[1].str()));
    return frames;
}

std::size_t errorLines(const std::string& log) { return test::occurrences(log, "decalcomp: error: "); }

TEST(BatchInputs, MissingInputsOfTheRangeFailBeforeAnythingIsWritten) {
    SmallSequence s(6);
    // A --pass pattern of its own, with frame 5's file missing, and frame 4's input missing.
    const std::string pass = (s.dir.path() / "pass" / "albedo.####.exr").string();
    fs::create_directories(s.dir.path() / "pass");
    for (int f = 1; f <= 6; ++f) fs::copy_file(s.in(f), FramePattern(pass).path(f));
    fs::remove(s.in(4));
    fs::remove(FramePattern(pass).path(5));
    const std::string with_pass = "--frames 1-6 --pass albedo=" + shellQuote(pass);

    const auto r = s.batch(with_pass);
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_EQ(errorLines(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("decalcomp: error: " + s.in(4) + ": frame 4 input: no such file"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("2 inputs missing in all, in frames 4, 5"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--keep-going"), std::string::npos) << r.output;
    EXPECT_EQ(framesLogged(r.output, "written"), std::vector<int>{}) << r.output;
    EXPECT_FALSE(fs::exists(s.dir.path() / "out")) << "nothing may be written, not even the output folder";

    // Only the --pass file missing: it is named, as the --pass it is.
    fs::copy_file(s.in(3), s.in(4));
    const auto p = s.batch(with_pass);
    EXPECT_EQ(p.exit_code, 3) << p.output;
    EXPECT_NE(p.output.find(FramePattern(pass).path(5) + ": frame 5 --pass albedo: no such file; nothing was written"),
              std::string::npos)
        << p.output;
    EXPECT_FALSE(fs::exists(s.dir.path() / "out"));

    // --keep-going processes the frames that are there and lists the one that is not.
    const auto k = s.batch(with_pass + " --keep-going");
    EXPECT_EQ(k.exit_code, 3) << k.output;
    EXPECT_NE(k.output.find("1 of 6 frames failed: 5"), std::string::npos) << k.output;
    for (int f : {1, 2, 3, 4, 6}) EXPECT_TRUE(fs::exists(s.out(f))) << f;
}

TEST(BatchInputs, MissingCameraSidecarOrFolderInPlaceOfAFileIsRefusedFirst) {
    SmallSequence s(4);
    for (int f = 1; f <= 4; ++f)
        if (f != 3)
            saveCameraJson(test::sequenceCamera(f, kWidth, kHeight), kWidth, kHeight,
                           s.dir.file(fmt::format("cam.{:04d}.json", f)));
    const auto r = s.batch("--frames 1-4 --camera " + shellQuote(s.dir.file("cam.####.json")));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find(s.dir.file("cam.0003.json") + ": frame 3 --camera: no such file"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(s.dir.path() / "out"));

    fs::remove(s.in(2));
    fs::create_directory(s.in(2));
    const auto d = s.batch("--frames 1-4");
    EXPECT_EQ(d.exit_code, 3) << d.output;
    EXPECT_NE(d.output.find(s.in(2) + ": frame 2 input: a folder, not a file"), std::string::npos) << d.output;
    EXPECT_FALSE(fs::exists(s.dir.path() / "out"));

    // Frames --resume will skip are not read, so their inputs need not be there.
    fs::remove(s.in(2));
    fs::create_directories(s.dir.path() / "out");
    fs::copy_file(s.in(1), s.out(2));
    const auto resumed = s.batch("--frames 1-4 --resume");
    EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
}

// What a stopped batch must leave: exactly the frames before `first_failure` written (and logged,
// in order), none from it on, no temporary, and a summary whose counts are those files.
void expectStoppedAt(const SmallSequence& s, const test::CommandResult& r, int first_failure, int frames,
                     const std::string& message) {
    std::vector<int> before;
    for (int f = 1; f < first_failure; ++f) before.push_back(f);
    EXPECT_EQ(framesLogged(r.output, "written"), before) << r.output;
    EXPECT_EQ(framesLogged(r.output, "FAILED"), std::vector<int>{first_failure}) << r.output;
    EXPECT_NE(r.output.find("decalcomp: error: " + message), std::string::npos) << r.output;
    for (int f = 1; f <= frames; ++f) EXPECT_EQ(fs::exists(s.out(f)), f < first_failure) << "frame " << f;
    EXPECT_EQ(temporariesUnder(s.dir.path() / "out"), std::set<std::string>{});
    EXPECT_EQ(filesUnder(s.dir.path() / "out").size(), before.size());
    EXPECT_NE(r.output.find(fmt::format("batch: {} written, 0 skipped, 1 failed of {} frames", before.size(), frames)),
              std::string::npos)
        << r.output;
    EXPECT_NE(
        r.output.find(fmt::format("stopped at frame {}, {} not processed", first_failure, frames - first_failure)),
        std::string::npos)
        << r.output;
}

// Frame 3 of 6 is not an EXR: its read fails at once, while frames 1 and 2 are still being
// composited. Every run, whatever the workers and queues, stops at frame 3 with 1 and 2 written.
TEST(BatchFirstFailure, CorruptFrameStopsTheBatchThereEveryRun) {
    SmallSequence s(6);
    std::ofstream(s.in(3)) << "not an exr";
    const char* settings[] = {"--workers 1 --queue 1", "--workers 2 --queue 2", "--workers 3 --queue 4",
                              "--workers 2 --queue 1", "--workers 4 --queue 3", "--workers 1 --queue 4",
                              "--workers 3 --queue 1", "--workers 2 --queue 3"};
    for (const char* setting : settings) {
        fs::remove_all(s.dir.path() / "out");
        const auto r = s.batch(std::string("--frames 1-6 ") + setting);
        EXPECT_EQ(r.exit_code, 3) << setting << "\n" << r.output;
        SCOPED_TRACE(setting);
        expectStoppedAt(s, r, 3, 6, s.in(3) + ": not an OpenEXR file");
    }
}

// Frame 3 fails while it is prepared (no albedo channels), later than frame 5, whose read fails
// at once: the first failure in frame order is 3's, and that is where the batch stops. With
// --keep-going both are listed in frame order.
TEST(BatchFirstFailure, FirstInFrameOrderWinsOverFirstInTime) {
    SmallSequence s(6);
    test::ChannelSamples no_albedo = test::genericPasses(test::renderSequenceFrame(3, kWidth, kHeight));
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) no_albedo.erase(c);
    test::writeFloatExr(s.in(3), kWidth, kHeight, no_albedo, test::sequenceCamera(3, kWidth, kHeight));
    std::ofstream(s.in(5)) << "not an exr";
    for (int run = 0; run < 6; ++run) {
        fs::remove_all(s.dir.path() / "out");
        const auto r = s.batch(fmt::format("--frames 1-6 --workers {} --queue {}", 1 + run % 3, 1 + run % 2));
        EXPECT_EQ(r.exit_code, 3) << r.output;
        SCOPED_TRACE(run);
        expectStoppedAt(s, r, 3, 6, s.in(3) + ": no albedo channels found");
    }
    fs::remove_all(s.dir.path() / "out");
    const auto k = s.batch("--frames 1-6 --keep-going");
    EXPECT_EQ(k.exit_code, 3) << k.output;
    EXPECT_NE(k.output.find("2 of 6 frames failed: 3, 5"), std::string::npos) << k.output;
    EXPECT_EQ(framesLogged(k.output, "written"), (std::vector<int>{1, 2, 4, 6})) << k.output;
    EXPECT_NE(k.output.find("batch: 4 written, 0 skipped, 2 failed of 6 frames"), std::string::npos) << k.output;
    EXPECT_EQ(k.output.find("stopped at"), std::string::npos) << k.output;
}

// With --resume the skipped frames count too: the summary is what is on disk.
TEST(BatchFirstFailure, ResumedRunStopsAtTheFailureWithSkippedFramesCounted) {
    SmallSequence s(6);
    ASSERT_EQ(s.batch("--frames 1-2 -q").exit_code, 0);
    std::ofstream(s.in(4)) << "not an exr";
    const auto r = s.batch("--frames 1-6 --resume");
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_EQ(framesLogged(r.output, "skipped"), (std::vector<int>{1, 2})) << r.output;
    EXPECT_EQ(framesLogged(r.output, "written"), (std::vector<int>{3})) << r.output;
    EXPECT_NE(r.output.find("batch: 1 written, 2 skipped, 1 failed of 6 frames"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("stopped at frame 4, 2 not processed"), std::string::npos) << r.output;
    for (int f = 1; f <= 6; ++f) EXPECT_EQ(fs::exists(s.out(f)), f <= 3) << f;
}

// Encoded frames hold their temporaries until their turn to be renamed: however deep the queues
// and many the workers, the frames in flight never hold more than the registry keeps.
// A library caller stops the batch by throwing from its progress callback. The observer here
// takes its time before throwing on frame 1, so that an unbounded writer would commit every later
// frame meanwhile: at most frame 2 may be written after it, whatever the timing.
TEST(BatchObserver, AnExceptionFromTheObserverLeavesAtMostTheNextFrameWritten) {
    SmallSequence s(6);
    struct Stopper : BatchObserver {
        void frameFinished(const FrameResult&, const BatchProgress&) override {
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
            throw std::runtime_error("stop");
        }
    } stopper;
    BatchRequest request;
    request.input = s.input;
    request.output = s.output;
    request.scene = s.scene;
    request.device = "cpu";
    request.shard_from_environment = false;
    EXPECT_THROW(runBatch(request, &stopper), std::runtime_error);
    EXPECT_TRUE(fs::exists(s.out(1)));
    for (int f = 3; f <= 6; ++f) EXPECT_FALSE(fs::exists(s.out(f))) << "frame " << f;
    EXPECT_EQ(temporariesUnder(fs::path(s.output).parent_path()), std::set<std::string>{});
}

TEST(BatchFramesInFlight, BoundedByTheTemporariesTheyMayHold) {
    BatchRequest request;
    EXPECT_EQ(batch::framesInFlight(request, 2), 2 * 2 + 2 + 1);  // the defaults: queues and workers
    request.queue_depth = 64;
    request.preview = "preview.####.png";
    request.pass_files = {{Attribute::Depth, "depth.####.exr"}, {Attribute::Normal, "normal.####.exr"}};
    request.extra_inputs = {"ids.####.exr"};
    const int frames = batch::framesInFlight(request, 64);
    EXPECT_GE(frames, 1);
    EXPECT_LE(frames * (4 + 1), kMaxLiveTemporaries - 1);  // 4 files a frame, each an output, and a preview
    EXPECT_EQ(frames, (kMaxLiveTemporaries - 1) / 5);
}

}  // namespace
}  // namespace decalcomp
