// A real single-node Slurm cluster (tests/support/slurm-cluster.sh: munged, slurmctld and slurmd
// under a temporary folder) runs a sequence as an 8-task job array submitted with
// tools/decalcomp-submit; every frame must be written exactly once and be correct.
// CTest label "slurm" (ctest -L slurm runs it alone). Skipped, with the reason, only where the
// slurm-wlm/munge packages cannot be installed or slurmd cannot run (not root).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
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

const std::string kScript = test::dataPath("../tests/support/slurm-cluster.sh");
const std::string kSubmit = test::dataPath("../tools/decalcomp-submit");

class Cluster {
public:
    explicit Cluster(const fs::path& state) : state_(state.string()) {}
    ~Cluster() {
        if (started_) test::runCommand("bash " + shellQuote(kScript) + " stop " + shellQuote(state_));
    }
    test::CommandResult start() {
        started_ = true;
        return test::runCommand("bash " + shellQuote(kScript) + " start " + shellQuote(state_));
    }
    std::string logs() const {
        return test::runCommand("tail -n 15 " + shellQuote(state_) + "/log/*.log").output;
    }

private:
    std::string state_;
    bool started_ = false;
};

TEST(Slurm, EightTaskArrayWritesEveryFrameExactlyOnce) {
    test::ScratchDir dir;
    Cluster cluster(dir.path() / "slurm");
    const auto start_time = std::chrono::steady_clock::now();
    const test::CommandResult started = cluster.start();
    if (started.exit_code == 77) GTEST_SKIP() << started.output;
    ASSERT_EQ(started.exit_code, 0) << started.output;
    ::setenv("SLURM_CONF", (dir.path() / "slurm" / "etc" / "slurm.conf").c_str(), 1);
    const double up_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();

    const std::vector<int> frames = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    const std::string input = test::writeSequence(dir.path() / "in", frames);
    const std::string scene = test::writeSequenceScene(dir.path());
    const std::string output = (dir.path() / "out" / "comp.####.exr").string();
    const fs::path logs = dir.path() / "logs";
    const auto submitted = test::runCommand(
        "sh " + shellQuote(kSubmit) + " --chunk 2 --job-name dctest --log-dir " + shellQuote(logs.string()) + " -- " +
        shellQuote(DECALCOMP_CLI) + " batch " + shellQuote(input) + " -o " + shellQuote(output) + " --decals " +
        shellQuote(scene) + " --device cpu --frames 1-16 --resume --progress lines");
    ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
    std::smatch id_match;
    ASSERT_TRUE(std::regex_search(submitted.output, id_match, std::regex("(^|\n)([0-9]+)\n?$"))) << submitted.output;
    const std::string job = id_match[2].str();
    EXPECT_NE(submitted.output.find("16 frames in 8 tasks"), std::string::npos) << submitted.output;

    // squeue lists the array until every task has ended; scontrol keeps the records (MinJobAge).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(240);
    while (true) {
        const auto queue = test::runCommand("squeue -h -j " + job);
        if (queue.exit_code == 0 && queue.output.empty()) break;
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "array still queued/running:\n"
                                                              << queue.output << cluster.logs();
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    const auto records = test::runCommand("scontrol -o show job " + job);
    std::set<int> completed_tasks;
    static const std::regex task("ArrayTaskId=([0-9]+) .*JobState=([A-Z_]+)");
    std::istringstream lines(records.output);
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (!std::regex_search(line, m, task)) continue;
        EXPECT_EQ(m[2].str(), "COMPLETED") << line;
        if (m[2].str() == "COMPLETED") completed_tasks.insert(std::stoi(m[1].str()));
    }
    EXPECT_EQ(completed_tasks, (std::set<int>{1, 2, 3, 4, 5, 6, 7, 8})) << records.output;

    // Each task's log: the frames it wrote. Together: every frame exactly once, two per task.
    std::multiset<int> written;
    int task_logs = 0;
    for (const auto& entry : fs::directory_iterator(logs)) {
        ++task_logs;
        const std::string log = test::readFileBytes(entry.path().string());
        static const std::regex line("frame ([0-9]+) written");
        int in_this_task = 0;
        for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator(); ++it) {
            written.insert(std::stoi((*it)[1].str()));
            ++in_this_task;
        }
        EXPECT_EQ(in_this_task, 2) << entry.path() << ":\n" << log;
        EXPECT_NE(log.find("shard "), std::string::npos) << log;
    }
    EXPECT_EQ(task_logs, 8);
    EXPECT_EQ(written, std::multiset<int>(frames.begin(), frames.end()));

    ComputeDevice device("cpu");
    const DecalScene decals = loadScene(scene);
    for (int f : frames)
        EXPECT_EQ(test::pixelDifference(readExr(FramePattern(output).path(f)),
                                        test::expectedFrame(FramePattern(input).path(f), decals, f, device)),
                  "")
            << "frame " << f;
    std::cout << "[          ] cluster up in " << up_s << " s, whole test "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count() << " s\n";
}

}  // namespace
}  // namespace decalcomp
