#include <fmt/format.h>

#include "commands.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::cli {

void addMappingOptions(CLI::App& command, MappingOptions& options, std::vector<std::string>& channel_flags,
                       std::string& depth_flag) {
    command.add_option("--profile", options.profile, "Channel naming profile: auto, blender, generic")
        ->check(CLI::IsMember({"auto", "blender", "generic"}))
        ->default_str("auto");
    command.add_option("--layer", options.layer, "View layer to read when the file has several (Blender)");
    command.add_option("--channel", channel_flags,
                       "Explicit channels for an attribute, e.g. albedo=diffuse.R,diffuse.G,diffuse.B (repeatable)");
    command.add_option("--depth", depth_flag, "Depth convention: planar, radial, ndc, position (default: profile's)")
        ->check(CLI::IsMember({"planar", "radial", "ndc", "position"}));
    command.add_flag("--reversed-z", options.reversed_z, "ndc depth is reversed (1 at the near plane)");
}

void finishMappingOptions(MappingOptions& options, const std::vector<std::string>& channel_flags,
                          const std::string& depth_flag) {
    if (!depth_flag.empty()) options.depth_convention = depthConventionFromName(depth_flag);
    for (const std::string& flag : channel_flags) {
        const auto eq = flag.find('=');
        if (eq == std::string::npos)
            throw Error(ErrorKind::Usage, fmt::format("--channel {}: expected ATTRIBUTE=CHANNEL[,CHANNEL...]", flag));
        const auto attribute = attributeFromName(flag.substr(0, eq));
        if (!attribute)
            throw Error(ErrorKind::Usage, fmt::format("--channel {}: unknown attribute '{}'", flag, flag.substr(0, eq)));
        std::vector<std::string> names;
        std::string rest = flag.substr(eq + 1);
        for (std::size_t start = 0;;) {
            const auto comma = rest.find(',', start);
            names.push_back(rest.substr(start, comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (int(names.size()) != attributeComponents(*attribute))
            throw Error(ErrorKind::Usage, fmt::format("--channel {}: {} needs {} channel(s), got {}", flag,
                                                      attributeName(*attribute), attributeComponents(*attribute),
                                                      names.size()));
        options.explicit_channels[*attribute] = names;
    }
}

}  // namespace decalcomp::cli
