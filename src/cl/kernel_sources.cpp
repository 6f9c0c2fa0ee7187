// The OpenCL program: the copy assembled and embedded at build time (cmake/AssembleKernels.cmake),
// or kernels/ read from disk and assembled by the same rules (DECALCOMP_KERNEL_DIR).
#include "cl/kernel_sources.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {
namespace embedded {
extern const std::string_view kProgramSource;
}

namespace {

constexpr std::string_view kInclude = "#include \"";

class Assembler {
public:
    Assembler(std::filesystem::path dir, std::string line_prefix)
        : dir_(std::move(dir)), prefix_(std::move(line_prefix)) {}

    // Appends `name` unless the program has it already.
    void add(const std::string& name, const std::string& included_from) {
        if (included_.insert(name).second) expand(name, included_from);
    }
    const std::string& text() const { return out_; }

private:
    void expand(const std::string& name, const std::string& included_from) {
        std::ifstream in(dir_ / name, std::ios::binary);
        if (!in)
            throw deviceError(
                fmt::format("{}: #include \"{}\": no such file in {}", included_from, name, dir_.string()));
        const std::string display = prefix_ + name;
        out_ += fmt::format("#line 1 \"{}\"\n", display);
        std::string line;
        for (int number = 1; std::getline(in, line); ++number) {
            if (!line.starts_with(kInclude)) {
                out_ += line + "\n";
                continue;
            }
            const std::size_t end = line.find('"', kInclude.size());
            if (end == std::string::npos || end == kInclude.size())
                throw deviceError(fmt::format("{}:{}: malformed #include", display, number));
            const std::string header = line.substr(kInclude.size(), end - kInclude.size());
            if (included_.contains(header)) {
                out_ += "// " + line + " (included above)\n";
                continue;
            }
            add(header, fmt::format("{}:{}", display, number));
            out_ += fmt::format("#line {} \"{}\"\n", number + 1, display);
        }
    }

    std::filesystem::path dir_;
    std::string prefix_;
    std::set<std::string> included_;
    std::string out_;
};

}  // namespace

std::string assembleProgram(const std::string& dir, const std::string& line_prefix) {
    std::vector<std::string> sources;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(dir, error))
        if (entry.path().extension() == ".cl") sources.push_back(entry.path().filename().string());
    if (sources.empty()) throw deviceError(fmt::format("{}: no *.cl files", dir));
    std::sort(sources.begin(), sources.end());
    Assembler assembler(dir, line_prefix);
    for (const std::string& name : sources) assembler.add(name, dir);
    return assembler.text();
}

std::string programSource() {
    if (const char* dir = std::getenv("DECALCOMP_KERNEL_DIR"))
        return assembleProgram(dir, (std::filesystem::path(dir) / "").string());
    return std::string(embedded::kProgramSource);
}

// Registers per work-item NVIDIA's compiler may give a program's kernels, measured on an H100 at
// 1080p with 1024 decals (docs/benchmarks.md "The shading programs' register cap" and "The point
// program's register cap"). Left to itself it gave the filter's shading 221 (taps 225), 9 warps
// per multiprocessor; at 128 (16 warps) `:fast` ran 27 % faster and the taps 38 %, although a few
// values spill. The point kernels took 96-153; at 64 (32 warps) they ran 16-34 % faster; 48
// spilled more than the warps gained.
constexpr int kPointRegisterCap = 64;
constexpr int kShadingRegisterCap = 128;

std::string registerCap(const std::string& device_extensions, ProgramKind program) {
    if (device_extensions.find("cl_nv_compiler_options") == std::string::npos) return "";
    const bool point = program == ProgramKind::Point;
    int cap = point ? kPointRegisterCap : kShadingRegisterCap;
    if (const char* forced = std::getenv(point ? "DECALCOMP_POINT_REGISTERS" : "DECALCOMP_SHADING_REGISTERS"))
        cap = std::atoi(forced);
    return cap > 0 ? fmt::format(" -cl-nv-maxrregcount={}", cap) : "";
}

bool cpuFlavour(const std::string& device_type) {
    constexpr const char* kVariable = "DECALCOMP_KERNEL_FLAVOUR";
    const char* forced = std::getenv(kVariable);
    if (!forced || !*forced) return device_type == "cpu";
    if (std::string_view(forced) == "cpu" || std::string_view(forced) == "gpu")
        return std::string_view(forced) == "cpu";
    throw Error(ErrorKind::Usage, fmt::format("{}={}: not a kernel flavour; cpu or gpu", kVariable, forced));
}

// DECALCOMP_CL_OPTIONS appends options (e.g. "-cl-nv-verbose" to see register use on NVIDIA).
std::string buildOptions(const std::string& device_type) {
    std::string options = "-cl-std=CL1.2";
    if (cpuFlavour(device_type)) options += " -DDC_CPU_DEVICE";  // (kernels/shared_types.h)
    if (const char* extra = std::getenv("DECALCOMP_CL_OPTIONS")) options += std::string(" ") + extra;
    return options;
}

}  // namespace decalcomp
