#pragma once
// Renderer channel-naming profiles as data: which EXR channel names hold which G-buffer attribute.
// The built-in profiles are JSON files (src/io/profiles/*.json) embedded into the library at build
// time; users add their own with --profile-file (docs/profiles.md describes the format).
#include <map>
#include <string>
#include <vector>

#include "decalcomp/beauty.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// One way an attribute can be spelled: channel-name patterns in component order. A pattern may
// contain "{layer}", which stands for a non-empty layer name (Blender's view layer) chosen once
// per file.
struct ProfileSpelling {
    std::vector<std::string> channels;
    std::string space;  // "world" or "camera" (normals); empty = the profile's default
};

// Evidence for a renderer beyond the attribute names: a header attribute (name glob, optional
// glob on its string value) or a channel (glob; "{layer}" matches any non-empty text).
struct ProfileDetectRule {
    std::string header;
    std::string value;
    std::string channel;
    double weight = 1.0;
};

struct ChannelProfile {
    std::string name;
    std::string description;
    std::string source;  // "built-in" or the file it was read from
    std::vector<ProfileDetectRule> detect;
    std::map<Attribute, std::vector<ProfileSpelling>> attributes;  // spellings in preference order
    DepthConvention depth_convention = DepthConvention::Planar;
    std::string normal_space = "world";     // world | camera
    std::string normal_encoding = "signed"; // signed ([-1,1]) | unsigned (n * 0.5 + 0.5)
    BeautyModel beauty;                     // its light passes ("beauty"; none declared: not rebuilt)
    PixelFilter pixel_filter;               // the renderer's default pixel filter ("pixel_filter")
};

// Score an attribute adds to a profile when all of its channels are found (docs/profiles.md).
double attributeDetectionWeight(Attribute attribute);

// The built-in profiles, in tie-break order: generic, blender, arnold, renderman, unreal, vray.
const std::vector<ChannelProfile>& builtinProfiles();

// Parses one profile object. Throws Error(Input) naming `source` and the JSON path of a bad field
// ("my.json: attributes.albedo[1]: expected 3 channel patterns, got 2").
ChannelProfile parseProfile(const std::string& json_text, const std::string& source);

// A profile file holds one profile object, an array of them, or {"profiles": [...]}.
std::vector<ChannelProfile> loadProfileFile(const std::string& path);

// The profiles a mapping considers: those of `files` (in order; a later file's profile replaces an
// earlier one of the same name) ahead of the built-ins, a user profile replacing a built-in of
// the same name. Throws Error(Input) for unreadable or invalid files.
std::vector<ChannelProfile> profileSet(const std::vector<std::string>& files);

// Expands one channel pattern with a component group: "{layer}.DiffCol.{R,G,B}" ->
// {"{layer}.DiffCol.R", "{layer}.DiffCol.G", "{layer}.DiffCol.B"}; without a group, itself.
std::vector<std::string> expandChannelPattern(const std::string& pattern);

}  // namespace decalcomp
