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

#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
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

// Found by the exr target: a header with duplicated attributes that OpenEXR's core reader skips
// and its C++ reader takes, so the size checks saw 16x16 and the reader allocated gigabytes. Both
// must be refused at once, whatever the memory limit.
TEST(FuzzFindings, HeadersTheTwoOpenExrReadersReadDifferentlyAreRefused) {
    for (const char* name : {"duplicated-data-window-16M-wide-dwaa.exr", "duplicated-data-window-250M-wide.exr"}) {
        const std::string path = (fs::path(DECALCOMP_FUZZ_DIR) / "regressions" / "exr" / name).string();
        SCOPED_TRACE(path);
        try {
            (void)readExr(path);
            ADD_FAILURE() << "read without an error";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Input);
            const std::string message = e.what();
            EXPECT_NE(message.find(path + ": header: "), std::string::npos) << message;
            EXPECT_NE(message.find("Duplicate copy of required attribute"), std::string::npos) << message;
        }
    }
}

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
