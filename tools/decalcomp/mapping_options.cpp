#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "commands.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/profiles.hpp"

namespace decalcomp::cli {

void addMappingOptions(CLI::App& command, MappingOptions& options, std::vector<std::string>& channel_flags,
                       std::string& depth_flag, bool writes) {
    command.add_option("--profile", options.profile,
                       "Channel naming profile: auto, or a profile name (built-in: generic, blender, arnold, "
                       "renderman, unreal, vray; or one from --profile-file)")
        ->default_str("auto");
    command.add_option("--profile-file", options.profile_files,
                       "JSON file of renderer profiles to consider ahead of the built-ins (repeatable; "
                       "docs/profiles.md)");
    command.add_option("--layer", options.layer, "View layer to read when the file has several (Blender)");
    command.add_option("--channel", channel_flags,
                       "Explicit channels for an attribute, e.g. albedo=diffuse.R,diffuse.G,diffuse.B (repeatable)");
    command.add_option("--depth", depth_flag, "Depth convention: planar, radial, ndc, position (default: profile's)")
        ->check(CLI::IsMember({"planar", "radial", "ndc", "position"}));
    command.add_flag("--reversed-z", options.reversed_z, "ndc depth is reversed (1 at the near plane)");
    command
        .add_option_function<std::string>(
            "--normals",
            [&options](const std::string& value) {
                const auto comma = value.find(',');
                options.normal_space = value.substr(0, comma) == "camera" ? NormalSpace::Camera : NormalSpace::World;
                if (comma != std::string::npos)  // without it, the encoding stays the profile's (or checked)
                    options.normal_packed = value.substr(comma + 1) != "signed";  // packed, or its alias unsigned
            },
            "Normal pass space and encoding: world|camera[,signed|packed] (default: the profile's, checked "
            "against the depth pass)")
        ->check(CLI::IsMember({"world", "camera", "world,signed", "world,packed", "world,unsigned", "camera,signed",
                               "camera,packed", "camera,unsigned"}));
    if (!writes) return;
    command.add_option_function<std::vector<std::string>>(
        "--add-channels",
        [&options](const std::vector<std::string>& items) {
            for (const std::string& item : items) {
                const auto eq = item.find('=');
                const std::string name = item.substr(0, eq);
                const auto attribute = attributeFromName(name);
                if (!attribute || !(*attribute == Attribute::Roughness || *attribute == Attribute::Metallic ||
                                    *attribute == Attribute::AmbientOcclusion || *attribute == Attribute::Emission))
                    throw CLI::ValidationError("--add-channels",
                                               item + ": expected roughness, metallic, ao or emission[=VALUE]");
                float value = addedChannelDefault(*attribute);
                if (eq != std::string::npos) {
                    try {
                        value = std::stof(item.substr(eq + 1));
                    } catch (const std::exception&) {
                        throw CLI::ValidationError("--add-channels", item + ": VALUE is not a number");
                    }
                }
                options.add_channels[*attribute] = value;
            }
        },
        "Add channels the input lacks so decals can write them: roughness, metallic, ao, emission, each "
        "optionally =VALUE where no decal writes (defaults 0.5, 0, 1, 0); comma-separated")
        ->delimiter(',');
}

void finishMappingOptions(MappingOptions& options, const std::vector<std::string>& channel_flags,
                          const std::string& depth_flag) {
    if (options.profile != "auto") {
        std::vector<std::string> known = {"auto"};
        for (const ChannelProfile& p : profileSet(options.profile_files)) known.push_back(p.name);
        if (std::find(known.begin(), known.end(), options.profile) == known.end())
            throw Error(ErrorKind::Usage, fmt::format("--profile {}: unknown profile (known: {})", options.profile,
                                                      fmt::join(known, ", ")));
    }
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

void addPassOptions(CLI::App& command, std::vector<std::string>& pass_flags) {
    command.add_option("--pass", pass_flags,
                       "Read one attribute from its own file, e.g. depth=depth.exr or albedo=albedo.exr "
                       "(repeatable; docs/cli.md)");
}

std::map<Attribute, std::string> parsePassFlags(const std::vector<std::string>& pass_flags) {
    std::map<Attribute, std::string> passes;
    for (const std::string& flag : pass_flags) {
        const auto eq = flag.find('=');
        if (eq == std::string::npos || eq + 1 == flag.size())
            throw Error(ErrorKind::Usage, fmt::format("--pass {}: expected ATTRIBUTE=FILE", flag));
        const auto attribute = attributeFromName(flag.substr(0, eq));
        if (!attribute)
            throw Error(ErrorKind::Usage, fmt::format("--pass {}: unknown attribute '{}'", flag, flag.substr(0, eq)));
        if (passes.count(*attribute))
            throw Error(ErrorKind::Usage, fmt::format("--pass {}: {} given twice", flag, attributeName(*attribute)));
        passes[*attribute] = flag.substr(eq + 1);
    }
    return passes;
}

}  // namespace decalcomp::cli
