#pragma once
// The decalcomp subcommands. Each registers its options on the CLI11 app and returns the
// function to run; main.cpp maps decalcomp::Error kinds to exit codes (docs/cli.md).
#include <CLI/CLI.hpp>
#include <functional>

#include "decalcomp/exr_io.hpp"

namespace decalcomp::cli {

using Command = std::function<void()>;

Command addCompositeCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addDevicesCommand(CLI::App& app);

// --profile, --layer, --channel, --depth, --reversed-z: shared by composite and info.
void addMappingOptions(CLI::App& command, MappingOptions& options, std::vector<std::string>& channel_flags,
                       std::string& depth_flag);
// Validates and folds the raw flags into options; throws Error(Usage) naming the flag.
void finishMappingOptions(MappingOptions& options, const std::vector<std::string>& channel_flags,
                          const std::string& depth_flag);

}  // namespace decalcomp::cli
