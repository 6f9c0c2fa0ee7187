// Scratch files for the fuzz targets.
#include "fuzz/fuzz_support.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace decalcomp::fuzz {

namespace fs = std::filesystem;

namespace {

fs::path makeScratchDir() {
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path dir = base / ("decalcomp-fuzz-" + std::to_string(::getpid()));
    fs::remove_all(dir, ec);
    fs::create_directories(dir);
    return dir;
}

// A hostile header may claim any size up to the memory cap, and the checks admit what the cap
// allows: with the machine's memory as the cap, inputs that decode to gigabytes are legal and
// cost seconds each. 16 MiB keeps every path (the cap's refusal included) at fuzzing speed. An
// explicit DECALCOMP_MAX_MEMORY wins.
void capInputMemory() {
    static const bool once = [] { return ::setenv("DECALCOMP_MAX_MEMORY", "16M", /*overwrite=*/0) == 0; }();
    (void)once;
}

}  // namespace

const fs::path& scratchDir() {
    // Never destroyed, so the exit handler can still read it.
    static const fs::path* const dir = [] {
        const fs::path* made = new fs::path(makeScratchDir());
        std::atexit([] {
            std::error_code ec;
            fs::remove_all(scratchDir(), ec);
        });
        return made;
    }();
    return *dir;
}

std::string writeScratchFile(const std::string& relative, std::string_view bytes) {
    capInputMemory();
    const fs::path path = scratchDir() / relative;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("fuzz: cannot write the scratch file " + path.string());
    return path.string();
}

}  // namespace decalcomp::fuzz
