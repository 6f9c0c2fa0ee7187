#pragma once
// What the fuzz targets share: a scratch folder in memory for the library calls that take paths,
// and the rule that hostile input may fail only with Error(Input).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "decalcomp/error.hpp"

namespace decalcomp::fuzz {

// This process's scratch folder: /dev/shm/decalcomp-fuzz-PID (else under the temp folder), made
// on first use and removed at exit. The library reads paths, not buffers, so each input is written
// here first; tmpfs keeps that to a few microseconds.
const std::filesystem::path& scratchDir();

// Writes the bytes to `relative` under scratchDir() (replacing it) and returns the full path.
std::string writeScratchFile(const std::string& relative, std::string_view bytes);

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// Runs `step`; Error(Input) is the expected answer to hostile input and is swallowed, anything
// else propagates. Returns whether the step succeeded.
template <class Step>
bool inputErrorsAllowed(Step&& step) {
    try {
        step();
        return true;
    } catch (const Error& e) {
        if (e.kind() != ErrorKind::Input) throw;
        return false;
    }
}

}  // namespace decalcomp::fuzz
