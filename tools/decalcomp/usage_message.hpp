#pragma once
// Command-line mistakes in decalcomp's one-line error form (docs/cli.md).
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace decalcomp::cli {

// The name in `names` closest to `word` by edit distance, when close enough to be a typo of it.
std::optional<std::string> nearestName(const std::string& word, const std::vector<std::string>& names);

// The message for a failed parse: the command, what is wrong, and where the options are listed;
// a misspelt command gets the nearest one.
std::string usageMessage(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv);

}  // namespace decalcomp::cli
