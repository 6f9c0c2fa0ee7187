// The same inputs give bit-identical outputs (issue 10, item 8): across runs, across PoCL's worker
// thread counts (POCL_MAX_PTHREAD_COUNT, PoCL 3's pthread device; POCL_CPU_MAX_CU_COUNT, its name
// from PoCL 4 on), across OpenMP thread counts (host-side packing of planes, OMP_NUM_THREADS),
// and for batch also across OpenEXR threads, compositing workers and devices opened twice. Each
// run's outputs are compared byte for byte with the first run's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::shellQuote;

// Thread settings of one run; 0 leaves the variable unset (the library's default).
struct Threads {
    int pocl = 0;  // PoCL worker threads
    int omp = 0;   // OpenMP threads
    std::string label() const {
        return "POCL threads " + (pocl ? std::to_string(pocl) : std::string("default")) + ", OMP threads " +
               (omp ? std::to_string(omp) : std::string("default"));
    }
    std::string environment() const {
        std::string env = "env -u POCL_MAX_PTHREAD_COUNT -u POCL_CPU_MAX_CU_COUNT -u OMP_NUM_THREADS ";
        if (pocl)
            env += "POCL_MAX_PTHREAD_COUNT=" + std::to_string(pocl) + " POCL_CPU_MAX_CU_COUNT=" + std::to_string(pocl) +
                   " ";
        if (omp) env += "OMP_NUM_THREADS=" + std::to_string(omp) + " ";
        return env;
    }
};

test::CommandResult runWith(const Threads& threads, const std::string& arguments) {
    return test::runCommand(threads.environment() + shellQuote(DECALCOMP_CLI) + " " + arguments);
}

// Every regular file under `dir` by relative name -> bytes.
std::map<std::string, std::string> filesUnder(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file()) files[fs::relative(entry.path(), dir).string()] = test::readFileBytes(entry.path());
    return files;
}

// The first byte where two files differ, for the failure message.
std::string firstDifference(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return "sizes " + std::to_string(a.size()) + " and " + std::to_string(b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) return "first differing byte at offset " + std::to_string(i);
    return "identical";
}

void expectSameFiles(const std::map<std::string, std::string>& reference, const std::map<std::string, std::string>& run,
                     const std::string& what) {
    ASSERT_EQ(run.size(), reference.size()) << what;
    for (const auto& [name, bytes] : reference) {
        auto it = run.find(name);
        ASSERT_NE(it, run.end()) << what << ": no " << name;
        EXPECT_TRUE(it->second == bytes) << what << ": " << name << " differs from the first run's ("
                                         << firstDifference(bytes, it->second) << ")";
    }
}

// The demo scene of data/sample (every decal kind: box with mip filtering and normal, ORM maps,
// volume, frustum with distance fade, cube with blast occlusion) over a freshly generated demo
// G-buffer small enough for a quick test but with many 16x16 tiles.
TEST(Determinism, CompositeIsBitIdenticalAcrossRunsAndThreadCounts) {
    test::ScratchDir dir;
    fs::copy(test::dataPath("sample"), dir.path() / "in", fs::copy_options::recursive);
    const fs::path in = dir.path() / "in";
    fs::remove(in / "gbuffer.exr");
    const auto gen = test::runGenerator("--naming generic --width 192 --height 108", (in / "frame.exr").string(),
                                        (in / "camera.json").string());
    ASSERT_EQ(gen.exit_code, 0) << gen.output;

    const std::vector<Threads> settings = {{1, 1}, {2, 1}, {4, 1}, {1, 2}, {3, 4}, {0, 0}, {0, 0}, {8, 3}};
    std::map<std::string, std::string> reference;
    for (std::size_t i = 0; i < settings.size(); ++i) {
        const fs::path out = dir.path() / ("out" + std::to_string(i));
        fs::create_directories(out);
        const auto r = runWith(settings[i], "composite " + shellQuote((in / "frame.exr").string()) + " --decals " +
                                                shellQuote((in / "scene.json").string()) + " --camera " +
                                                shellQuote((in / "camera.json").string()) + " -o " +
                                                shellQuote((out / "frame.exr").string()) + " --preview " +
                                                shellQuote((out / "preview.png").string()) + " --device cpu -q");
        ASSERT_EQ(r.exit_code, 0) << settings[i].label() << ": " << r.output;
        const auto files = filesUnder(out);
        if (i == 0) {
            ASSERT_EQ(files.size(), 2u);
            // the run did composite something, so the comparison means something
            EXPECT_FALSE(files.at("frame.exr") == test::readFileBytes(in / "frame.exr"));
            reference = files;
        } else {
            expectSameFiles(reference, files, settings[i].label() + " (run " + std::to_string(i + 1) + ")");
        }
    }
}

// A four-frame sequence with static, fading and keyframed decals: batch outputs are the same
// whatever the threads, the number of compositing workers, OpenEXR's threads, or how many devices
// the frames are spread over.
TEST(Determinism, BatchIsBitIdenticalAcrossThreadCountsWorkersAndDevices) {
    test::ScratchDir dir;
    const std::string input = test::writeSequence(dir.path() / "in", {1, 2, 3, 4}, 96, 72);
    const std::string scene = test::writeSequenceScene(dir.path() / "in");

    struct Run {
        Threads threads;
        std::string flags;
    };
    const std::vector<Run> runs = {
        {{1, 1}, "--device cpu --workers 1 --threads 1 --queue 1"},
        {{2, 1}, "--device cpu --workers 2 --threads 2"},
        {{4, 2}, "--device cpu --workers 3 --threads 4 --queue 3"},
        {{1, 4}, "--device cpu --workers 1 --threads 0"},
        {{0, 0}, "--device cpu"},
        {{0, 0}, "--device cpu"},
        {{3, 3}, "--device cpu,cpu --workers 2"},
    };
    std::map<std::string, std::string> reference;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const fs::path out = dir.path() / ("out" + std::to_string(i));
        const std::string what =
            runs[i].threads.label() + ", " + runs[i].flags + " (run " + std::to_string(i + 1) + ")";
        const auto r = runWith(runs[i].threads, "batch " + shellQuote(input) + " --decals " + shellQuote(scene) +
                                                    " -o " + shellQuote((out / "c.####.exr").string()) + " --preview " +
                                                    shellQuote((out / "p.####.png").string()) + " --frames 1-4 -q " +
                                                    runs[i].flags);
        ASSERT_EQ(r.exit_code, 0) << what << ": " << r.output;
        const auto files = filesUnder(out);
        if (i == 0) {
            ASSERT_EQ(files.size(), 8u);
            EXPECT_FALSE(files.at("c.0001.exr") == test::readFileBytes(FramePattern(input).path(1)));
            reference = files;
        } else {
            expectSameFiles(reference, files, what);
        }
    }
}

}  // namespace
}  // namespace decalcomp
