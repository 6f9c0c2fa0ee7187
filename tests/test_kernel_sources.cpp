// Kernel program assembly: the build-time copy (cmake/AssembleKernels.cmake) and the run-time one
// (DECALCOMP_KERNEL_DIR, src/cl/kernel_sources.cpp) follow the same rules, and build logs name
// the real kernels/ file and line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cl/kernel_sources.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;

// Sets DECALCOMP_KERNEL_DIR (or unsets it) for the object's lifetime.
class KernelDirEnv {
public:
    explicit KernelDirEnv(const std::optional<std::string>& dir) {
        if (const char* old = std::getenv("DECALCOMP_KERNEL_DIR")) old_ = old;
        if (dir)
            ::setenv("DECALCOMP_KERNEL_DIR", dir->c_str(), 1);
        else
            ::unsetenv("DECALCOMP_KERNEL_DIR");
    }
    ~KernelDirEnv() {
        if (old_)
            ::setenv("DECALCOMP_KERNEL_DIR", old_->c_str(), 1);
        else
            ::unsetenv("DECALCOMP_KERNEL_DIR");
    }
    KernelDirEnv(const KernelDirEnv&) = delete;
    KernelDirEnv& operator=(const KernelDirEnv&) = delete;

private:
    std::optional<std::string> old_;
};

void writeFile(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

TEST(KernelSources, EmbeddedProgramEqualsRunTimeAssemblyOfKernels) {
    const KernelDirEnv env(std::nullopt);
    EXPECT_EQ(programSource(), assembleProgram(DECALCOMP_KERNEL_SOURCE_DIR, "kernels/"))
        << "cmake/AssembleKernels.cmake and src/cl/kernel_sources.cpp assemble differently";
}

TEST(KernelSources, EveryKernelFileOnceWithNoIncludeLeft) {
    const KernelDirEnv env(std::nullopt);
    const std::vector<std::string> program = lines(programSource());
    for (const auto& entry : fs::directory_iterator(DECALCOMP_KERNEL_SOURCE_DIR)) {
        const std::string marker = "#line 1 \"kernels/" + entry.path().filename().string() + "\"";
        EXPECT_EQ(std::count(program.begin(), program.end(), marker), 1) << marker;
    }
    for (const std::string& line : program) EXPECT_FALSE(line.starts_with("#include \"")) << line;
}

TEST(KernelSources, IncludesResolvedOnceInDependencyOrderWithLineMarkers) {
    const test::ScratchDir dir;
    writeFile(dir.path() / "a.cl", "#include \"b.h\"\nkernel a\n#include \"c.h\"\n");
    writeFile(dir.path() / "b.h", "#include \"c.h\"\nb\n");
    writeFile(dir.path() / "c.h", "#include \"c.h\"\nc");  // includes itself, no final newline
    writeFile(dir.path() / "d.cl", "#include \"b.h\"\nkernel d\n");
    EXPECT_EQ(assembleProgram(dir.path().string(), "k/"),
              "#line 1 \"k/a.cl\"\n"
              "#line 1 \"k/b.h\"\n"
              "#line 1 \"k/c.h\"\n"
              "// #include \"c.h\" (included above)\n"
              "c\n"
              "#line 2 \"k/b.h\"\n"
              "b\n"
              "#line 2 \"k/a.cl\"\n"
              "kernel a\n"
              "// #include \"c.h\" (included above)\n"
              "#line 1 \"k/d.cl\"\n"
              "// #include \"b.h\" (included above)\n"
              "kernel d\n");
}

TEST(KernelSources, MissingIncludeNamesFileAndLine) {
    const std::string message = test::errorMessage(
        ErrorKind::Device, [] { assembleProgram(DECALCOMP_KERNEL_FIXTURES "/missing_include", "fixture/"); });
    EXPECT_NE(message.find("fixture/broken.cl:3: #include \"absent.h\""), std::string::npos) << message;
}

// A kernel error's build log points at the kernels/ file and line it is in, through the
// DECALCOMP_KERNEL_DIR path (the embedded program carries the same #line markers).
TEST(KernelSources, BuildLogNamesKernelFileAndLine) {
    const test::ScratchDir dir;
    fs::copy(DECALCOMP_KERNEL_SOURCE_DIR, dir.path(), fs::copy_options::recursive);
    std::vector<std::string> materials;
    {
        std::ifstream in(dir.path() / "materials.h");
        for (std::string line; std::getline(in, line);) materials.push_back(line);
    }
    constexpr int kErrorLine = 9;  // after the includes, at file scope
    materials.insert(materials.begin() + (kErrorLine - 1), "__constant int dc_injected = dc_no_such_identifier;");
    std::string text;
    for (const std::string& line : materials) text += line + "\n";
    writeFile(dir.path() / "materials.h", text);

    const KernelDirEnv env(dir.path().string());
    ComputeDevice device("cpu");
    const std::string message = test::errorMessage(ErrorKind::Device, [&] { device.program(); });
    EXPECT_NE(message.find("materials.h:" + std::to_string(kErrorLine) + ":"), std::string::npos) << message;
    EXPECT_NE(message.find("dc_no_such_identifier"), std::string::npos) << message;
}

// The programs' register caps: on NVIDIA's compiler only (its option would fail elsewhere), 64 for
// the point program and 128 for the shading programs by default, each overridden by its variable,
// 0 for none.
TEST(KernelSources, RegisterCapsOnlyWhereTheCompilerTakesThem) {
    ASSERT_EQ(0, unsetenv("DECALCOMP_POINT_REGISTERS"));
    ASSERT_EQ(0, unsetenv("DECALCOMP_SHADING_REGISTERS"));
    const std::string nvidia = "cl_khr_fp64 cl_nv_compiler_options cl_nv_device_attribute_query";
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Point), " -cl-nv-maxrregcount=64");
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Shading), " -cl-nv-maxrregcount=128");
    for (const ProgramKind kind : {ProgramKind::Point, ProgramKind::Shading}) {
        EXPECT_EQ(registerCap("cl_khr_fp64 cl_khr_icd", kind), "");
        EXPECT_EQ(registerCap("", kind), "");
    }
    ASSERT_EQ(0, setenv("DECALCOMP_SHADING_REGISTERS", "96", 1));
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Shading), " -cl-nv-maxrregcount=96");
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Point), " -cl-nv-maxrregcount=64");
    EXPECT_EQ(registerCap("cl_khr_fp64", ProgramKind::Shading), "");
    ASSERT_EQ(0, setenv("DECALCOMP_POINT_REGISTERS", "0", 1));
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Point), "");
    EXPECT_EQ(registerCap(nvidia, ProgramKind::Shading), " -cl-nv-maxrregcount=96");
    ASSERT_EQ(0, unsetenv("DECALCOMP_POINT_REGISTERS"));
    ASSERT_EQ(0, unsetenv("DECALCOMP_SHADING_REGISTERS"));
}

}  // namespace
}  // namespace decalcomp
