#pragma once
// The fuzz targets (docs/fuzzing.md): each takes one input as libFuzzer hands it and drives a
// library entry point with it. Hostile input may give Error(Input), which a target swallows; any
// other exception escapes, and a crash is a crash: both are findings. The libFuzzer executables
// (libfuzzer_entry.cpp) and the regression test (tests/test_fuzz_regressions.cpp) call the same
// functions, so a saved crash replays exactly.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace decalcomp::fuzz {

using FuzzTarget = void (*)(const std::uint8_t* data, std::size_t size);

void fuzzScene(const std::uint8_t* data, std::size_t size);        // scene JSON (loadScene)
void fuzzCamera(const std::uint8_t* data, std::size_t size);       // camera sidecar and per-frame cameras
void fuzzProfile(const std::uint8_t* data, std::size_t size);      // profile file, then channel mapping
void fuzzCryptomatte(const std::uint8_t* data, std::size_t size);  // manifest and name patterns
void fuzzTexture(const std::uint8_t* data, std::size_t size);      // texture decoding (PNG, EXR)
void fuzzExr(const std::uint8_t* data, std::size_t size);          // EXR: header, mapping, G-buffer

// Every target by its name ("scene", "camera", ...), the name of its folder of seeds and
// regressions and of its executable (fuzz_<name>).
const std::map<std::string, FuzzTarget>& fuzzTargets();

}  // namespace decalcomp::fuzz
