#pragma once
// The decalcomp subcommands. Each registers its options on the CLI11 app and returns the
// function to run; main.cpp maps decalcomp::Error kinds to exit codes (docs/cli.md).
#include <CLI/CLI.hpp>
#include <functional>
#include <map>

#include "decalcomp/beauty.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp::cli {

using Command = std::function<void()>;

Command addCompositeCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addDevicesCommand(CLI::App& app);
Command addBatchCommand(CLI::App& app);  // cmd_batch.cpp
Command addBakeCommand(CLI::App& app);   // cmd_bake.cpp

// --profile, --profile-file, --layer, --channel, --depth, --reversed-z, --normals: shared by
// composite, batch and info; --add-channels only where something is written (`writes`).
void addMappingOptions(CLI::App& command, MappingOptions& options, std::vector<std::string>& channel_flags,
                       std::string& depth_flag, bool writes = true);
// Validates and folds the raw flags into options; throws Error(Usage) naming the flag.
void finishMappingOptions(MappingOptions& options, const std::vector<std::string>& channel_flags,
                          const std::string& depth_flag);

// --pixel-filter TYPE:WIDTH|none|auto: shared by composite and batch.
void addPixelFilterOption(CLI::App& command, std::optional<PixelFilter>& filter, bool& fast);
// --uv-origin auto|bottom|top (texture-space decals): shared by composite and batch.
void addUvOriginOption(CLI::App& command, std::optional<bool>& uv_v_down);
// --ocio FILE: the OpenColorIO config of the scene's colour spaces (docs/colour.md).
void addOcioOption(CLI::App& command, std::string& ocio_config);

// --beauty auto|on|off and --relight: shared by composite and batch.
void addBeautyOptions(CLI::App& command, BeautyOptions& options);

// --pass ATTR=FILE (repeatable): one attribute from its own file. Shared by composite and info.
void addPassOptions(CLI::App& command, std::vector<std::string>& pass_flags);
// Throws Error(Usage) naming the flag.
std::map<Attribute, std::string> parsePassFlags(const std::vector<std::string>& pass_flags);

}  // namespace decalcomp::cli
