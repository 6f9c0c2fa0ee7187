// --beauty and --relight, shared by composite and batch (docs/cli.md "Beauty").
#include "commands.hpp"
#include "decalcomp/beauty.hpp"

namespace decalcomp::cli {

void addBeautyOptions(CLI::App& command, BeautyOptions& options) {
    command
        .add_option_function<std::string>(
            "--beauty", [&options](const std::string& value) { options.mode = *beautyModeFromName(value); },
            "Rebuild the beauty from the light passes: auto (when the profile's passes are there), on (they "
            "must be), off")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->default_str("auto");
    command.add_flag("--relight", options.relight,
                     "Approximate normal decals in the rebuilt beauty: scale the direct diffuse light by a Lambert fit "
                     "with the new and the old normal (docs/profiles.md \"Relight\")");
}

}  // namespace decalcomp::cli
