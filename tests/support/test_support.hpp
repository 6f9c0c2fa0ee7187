#pragma once
// Small helpers shared by the tests: scratch folders, running the CLI, data paths.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"

namespace decalcomp::test {

std::string dataPath(const std::string& relative);  // path under the repository's data/

// An environment variable set (or, with nullptr, unset) for the object's life, then restored.
class ScopedEnv {
public:
    ScopedEnv(std::string name, const char* value);
    ~ScopedEnv();
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string name_;
    std::optional<std::string> old_;
};

// A fresh empty folder under the system temp dir, removed when the object dies.
class ScratchDir {
public:
    ScratchDir();
    ~ScratchDir();
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::filesystem::path path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

struct CommandResult {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};
// Runs a shell command line, capturing stdout+stderr.
CommandResult runCommand(const std::string& command_line);
// Runs the decalcomp CLI with the given arguments (already shell-quoted where needed).
CommandResult runCli(const std::string& arguments);
std::string shellQuote(const std::string& s);
// The message of the Error that `f` throws, expecting it of `kind`; a test failure (and "") when
// it throws none.
std::string errorMessage(ErrorKind kind, const std::function<void()>& f);
// Loads the scene file expecting an input error: one line that starts with the file's path and
// contains `expected` (a JSON path and what is wrong there).
void expectSceneError(const std::string& scene_path, const std::string& expected);

// An image of one part with these channel names and no samples: channel mapping reads only names.
ExrImage imageWithChannels(const std::vector<std::string>& names);

// Runs decalcomp-gbuffer-gen with `arguments`, writing `output` (and the camera sidecar `camera`
// when given, else the generator's default beside it).
CommandResult runGenerator(const std::string& arguments, const std::string& output, const std::string& camera = "");

// The channel whose qualified name ("albedo.R", "part.name") is `qualified`; throws when none.
const ExrChannel& channel(const ExrImage& image, const std::string& qualified);

// Every channel's qualified name, over all parts.
std::set<std::string> qualifiedNames(const ExrImage& image);

// How often `needle` occurs in `text` (overlapping occurrences count).
std::size_t occurrences(const std::string& text, const std::string& needle);

// An 8-bit RGB image read through OpenImageIO (a preview PNG).
struct Png {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    const std::uint8_t* at(int x, int y) const { return &rgb[(std::size_t(y) * width + x) * 3]; }
};
// Reads `path`'s first three channels; a failed check (and an empty image) when it cannot.
Png readPng(const std::string& path);

}  // namespace decalcomp::test
