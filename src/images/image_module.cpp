// Finds and loads decalcomp-images.so (image_codecs.hpp) on first use.
#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "images/image_codecs.hpp"
#include "images/image_module_paths.hpp"

namespace decalcomp::images {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleName = "decalcomp-images.so";

// The folder of the executable or shared object this code was linked into.
fs::path ownFolder() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&imageCodecs), &info) == 0 || !info.dli_fname) return {};
    std::error_code ec;
    const fs::path self = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path() : self.parent_path();
}

// Where the module may be, in order: $DECALCOMP_IMAGE_MODULE alone when set; else beside this
// binary (the Python package), under its folder (an installed libdecalcomp.so), in the library
// folder next to its own (an installed decalcomp), the configured install's, the build tree's.
std::vector<fs::path> candidates() {
    if (const char* given = std::getenv("DECALCOMP_IMAGE_MODULE"); given && *given) return {given};
    std::vector<fs::path> paths;
    if (const fs::path own = ownFolder(); !own.empty()) {
        paths.push_back(own / kModuleName);
        paths.push_back(own / "decalcomp" / kModuleName);
        paths.push_back(own / ".." / kDecalcompLibDir / "decalcomp" / kModuleName);
    }
    paths.push_back(fs::path(kDecalcompInstalledModuleDir) / kModuleName);
    paths.push_back(fs::path(kDecalcompBuildModuleDir) / kModuleName);
    return paths;
}

struct Loaded {
    const Codecs* codecs = nullptr;
    std::string failure;  // why it could not be loaded
};

Loaded load() {
    std::string tried;
    for (const fs::path& candidate : candidates()) {
        const fs::path path = candidate.lexically_normal();
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) {
            tried += (tried.empty() ? "" : ", ") + path.string();
            continue;
        }
        // Never unloaded: OpenImageIO keeps threads and caches until the process ends.
        void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!module) return {nullptr, fmt::format("{}: {}", path.string(), dlerror())};
        auto version = reinterpret_cast<int (*)()>(dlsym(module, "decalcomp_image_codecs_version"));
        auto codecs = reinterpret_cast<const Codecs* (*)()>(dlsym(module, "decalcomp_image_codecs"));
        if (!version || !codecs || version() != kCodecsVersion)
            return {nullptr, fmt::format("{}: not the module of this decalcomp (version {}, expected {})",
                                         path.string(), version ? version() : -1, kCodecsVersion)};
        return {codecs(), ""};
    }
    return {nullptr, fmt::format("{} not found (looked for {}; DECALCOMP_IMAGE_MODULE names it)", kModuleName, tried)};
}

}  // namespace

const Codecs& imageCodecs(ErrorKind kind, const std::string& needed_for) {
    static std::once_flag once;
    static Loaded loaded;
    std::call_once(once, [] { loaded = load(); });
    if (!loaded.codecs)
        throw Error(kind, fmt::format("{}: cannot load OpenImageIO's module: {}", needed_for, loaded.failure));
    return *loaded.codecs;
}

}  // namespace decalcomp::images
