// Every input a fuzz target once crashed on (tests/fuzz/regressions/<target>/), and the checked-in
// seeds (tests/fuzz/seeds/<target>/), replayed through the same target function: the test fails
// when one throws anything but Error(Input) again, and under the sanitizer build when one makes
// ASan or UBSan report (docs/fuzzing.md "A crash becomes a regression test").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> savedInputs(const std::string& target) {
    std::vector<fs::path> files;
    for (const char* kind : {"regressions", "seeds"}) {
        const fs::path dir = fs::path(DECALCOMP_FUZZ_DIR) / kind / target;
        if (!fs::is_directory(dir)) continue;
        for (const fs::directory_entry& entry : fs::directory_iterator(dir))
            if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
    }
    return files;
}

std::string contents(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzRegressions : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzRegressions, SavedInputsReplayWithoutCrashing) {
    const FuzzTarget target = fuzzTargets().at(GetParam());
    for (const fs::path& file : savedInputs(GetParam())) {
        SCOPED_TRACE(file.string());
        const std::string bytes = contents(file);
        EXPECT_NO_THROW(target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    }
}

// Also the empty input, which every target must take.
TEST_P(FuzzRegressions, EmptyInputIsHarmless) {
    EXPECT_NO_THROW(fuzzTargets().at(GetParam())(nullptr, 0));
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzRegressions,
                         ::testing::Values("camera", "cryptomatte", "exr", "profile", "scene", "texture"),
                         [](const auto& test) { return test.param; });

// A folder of saved inputs must belong to a target, or its inputs would never be replayed.
TEST(FuzzRegressionFolders, NameKnownTargets) {
    for (const char* kind : {"regressions", "seeds"}) {
        const fs::path dir = fs::path(DECALCOMP_FUZZ_DIR) / kind;
        if (!fs::is_directory(dir)) continue;
        for (const fs::directory_entry& entry : fs::directory_iterator(dir))
            if (entry.is_directory()) {
                EXPECT_TRUE(fuzzTargets().count(entry.path().filename().string())) << entry.path();
            }
    }
}

}  // namespace
}  // namespace decalcomp::fuzz
