// Assembles the OpenCL program from the kernel files embedded at build time.
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {
namespace embedded {
extern const std::vector<std::pair<std::string_view, std::string_view>> kKernelFiles;
}

namespace {

// Headers first, in dependency order; every .cl after them. The OpenCL compiler sees one
// translation unit, so local #include lines are dropped.
constexpr std::string_view kOrder[] = {"shared_types.h", "matrix.h", "reconstruct.h", "texture_sample.h",
                                       "decal_kinds.h", "materials.h", "occlusion.h"};

std::string stripLocalIncludes(std::string_view text) {
    std::string out;
    std::istringstream in{std::string(text)};
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("#include \"", 0) == 0) line = "// " + line;
        out += line;
        out += '\n';
    }
    return out;
}

std::string readFromDisk(const std::string& dir, std::string_view name) {
    std::ifstream in(dir + "/" + std::string(name));
    if (!in) throw deviceError("DECALCOMP_KERNEL_DIR: cannot read " + dir + "/" + std::string(name));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

std::string programSource() {
    const char* dir = std::getenv("DECALCOMP_KERNEL_DIR");
    auto text = [&](std::string_view name, std::string_view embedded_text) {
        return dir ? readFromDisk(dir, name) : std::string(embedded_text);
    };
    std::string source;
    for (std::string_view header : kOrder)
        for (const auto& [name, content] : embedded::kKernelFiles)
            if (name == header) source += "// ---- " + std::string(name) + "\n" + stripLocalIncludes(text(name, content));
    for (const auto& [name, content] : embedded::kKernelFiles)
        if (name.ends_with(".cl")) source += "// ---- " + std::string(name) + "\n" + stripLocalIncludes(text(name, content));
    return source;
}

// DECALCOMP_CL_OPTIONS appends options (e.g. "-cl-nv-verbose" to see register use on NVIDIA).
std::string buildOptions() {
    std::string options = "-cl-std=CL1.2";
    if (const char* extra = std::getenv("DECALCOMP_CL_OPTIONS")) options += std::string(" ") + extra;
    return options;
}

}  // namespace decalcomp
