#pragma once
// Which EXR channels hold which G-buffer attribute (renderer profiles, docs/profiles.md), and the
// material channels added on request.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

struct ChannelRef {
    int part = -1;
    int channel = -1;
    int file = 0;  // index into the frame's files (always 0 for a single file)
};

struct MappingOptions {
    std::string profile = "auto";            // auto, or a profile name (built-in or from profile_files)
    std::vector<std::string> profile_files;  // --profile-file: user profiles, considered first
    std::string layer;                       // layer for "{layer}" patterns when a file has several
    // --channel albedo=a.R,a.G,a.B : explicit channels per attribute, in component order
    std::map<Attribute, std::vector<std::string>> explicit_channels;
    std::optional<DepthConvention> depth_convention;  // explicit wins over the profile default
    bool reversed_z = false;
    // --normals SPACE,ENCODING: explicit wins over the profile and the check against the geometry
    std::optional<NormalSpace> normal_space;
    std::optional<bool> normal_packed;  // n * 0.5 + 0.5
    // --add-channels ATTR[=VALUE],...: material channels to add when the input lacks them
    std::map<Attribute, float> add_channels;
};

// How several files make one frame: files[0, positional) are pooled and mapped through the profile
// (0 = every file); an attribute listed in pass_files is read from that file only (--pass).
struct FileRoles {
    int positional = 0;
    std::map<Attribute, int> pass_files;
};

struct ProfileCandidate {
    std::string name;
    double score = 0.0;
    std::vector<std::string> reasons;  // "depth", "albedo", "header BlenderMultiChannel", ...
    // Every attribute the profile names is found, depth (or position) and albedo among them: a
    // user profile that fits is chosen ahead of the built-ins (docs/profiles.md, "Detection").
    bool fits = false;
};

struct ChannelMapping {
    std::string profile;             // the profile that matched ("blender", "generic", ...)
    std::string layer;               // the layer "{layer}" stood for ("" when none)
    std::vector<std::string> notes;  // human-readable reasons, for `decalcomp info`
    std::vector<std::string> warnings;  // a guess that may be wrong (a colour file given as depth)
    std::vector<ProfileCandidate> candidates;  // every profile's detection score, best first
    std::map<Attribute, std::vector<ChannelRef>> attributes;  // components in order
    DepthConvention depth_convention = DepthConvention::Planar;
    bool depth_convention_explicit = false;  // from --depth, not a default
    bool reversed_z = false;
    NormalEncoding normals;                  // of the mapped normal channels
    bool normal_space_explicit = false;      // from --normals, not the profile: the check keeps it
    bool normal_encoding_explicit = false;
};

// --add-channels: adds channels for the attributes in options.add_channels (roughness, metallic,
// ao, emission) the mapping lacks, beside the albedo's channels in its file and part, named as the
// matched profile spells them, with the albedo's pixel type and every sample set to the given
// value, and maps them. Attributes the input has are left alone. Throws Error(Input) when a wanted
// name exists unmapped.
void addAttributeChannels(std::vector<ExrImage>& files, ChannelMapping& mapping, const MappingOptions& options);
// The value an added channel holds where no decal writes: roughness 0.5, ao 1, others 0.
float addedChannelDefault(Attribute attribute);

// Throws Error(Input) for unknown profiles, explicit channels that do not exist, ambiguous layers,
// a pass file without the attribute's channels.
ChannelMapping mapChannels(const ExrImage& image, const MappingOptions& options);
ChannelMapping mapChannels(const std::vector<ExrImage>& files, const MappingOptions& options,
                           const FileRoles& roles = {});

}  // namespace decalcomp
