#pragma once
// OpenEXR files kept whole: every part, header and channel, so a frame can be written back with
// the same layout, pixel types, compression and metadata, and only decal-affected channels change.
#include <OpenEXR/ImfHeader.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

enum class SampleType { Uint, Half, Float };

struct ExrChannel {
    std::string name;       // as stored in its part
    std::string qualified;  // name used for mapping: part name + "." + name in multi-part files
                            // when the name has no '.' of its own, else the name itself
    SampleType type = SampleType::Float;
    int x_sampling = 1, y_sampling = 1;
    std::vector<unsigned char> bytes;  // raw samples over the part's data window, rows top-down
};

struct ExrPart {
    Imf::Header header;  // kept as read: compression, windows, tiling, every attribute
    int width = 0, height = 0;  // data window size
    std::vector<ExrChannel> channels;
};

struct ExrImage {
    std::string path;
    std::vector<ExrPart> parts;
};

// Reads scanline or tiled, single- or multi-part files. Deep parts are refused.
// Throws Error(Input) naming the file ("in.exr: not an OpenEXR file", "...: deep parts unsupported").
ExrImage readExr(const std::string& path);

// Writes all parts with their original headers to `path` through a temporary file in the same
// folder, renamed into place only when complete. Throws Error(Output) naming the file.
void writeExrAtomic(const ExrImage& image, const std::string& path);

// The two halves of writeExrAtomic, for several outputs that should appear together: writes the
// temporary beside `path` and returns its name (Error(Output) on failure, nothing left behind);
// commitExrTemporary renames it into place, discardExrTemporary removes it.
std::string writeExrTemporary(const ExrImage& image, const std::string& path);
void commitExrTemporary(const std::string& temporary, const std::string& path);
void discardExrTemporary(const std::string& temporary) noexcept;

// ---- channel mapping (renderer profiles, docs/profiles.md) ----

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
    std::optional<std::string> normal_space;     // world | camera
    std::optional<std::string> normal_encoding;  // signed | unsigned
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
};

struct ChannelMapping {
    std::string profile;             // the profile that matched ("blender", "generic", ...)
    std::string layer;               // the layer "{layer}" stood for ("" when none)
    std::vector<std::string> notes;  // human-readable reasons, for `decalcomp info`
    std::vector<ProfileCandidate> candidates;  // every profile's detection score, best first
    std::map<Attribute, std::vector<ChannelRef>> attributes;  // components in order
    DepthConvention depth_convention = DepthConvention::Planar;
    bool depth_convention_explicit = false;  // from --depth, not a default
    bool reversed_z = false;
    std::string normal_space = "world";      // of the mapped normal channels: world | camera
    std::string normal_encoding = "signed";  // signed | unsigned (n * 0.5 + 0.5)
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

// The pixels a G-buffer covers, in absolute EXR coordinates: the data window of the depth pass
// (else position, else albedo, else the first mapped attribute), and the display window all
// mapped parts share. Throws Error(Input) when mapped parts have different display windows.
struct FrameWindow {
    Imath::Box2i data, display;
    std::string owner;  // "depth (in.exr)", for messages
};
FrameWindow frameWindow(const std::vector<ExrImage>& files, const ChannelMapping& mapping);

// Reads channels as one interleaved float plane over `window`; pixels outside a channel's own data
// window get `fill`. Throws Error(Input) for subsampled channels, and for UINT channels unless
// allow_uint (ID-like data).
Plane readChannelsOnWindow(const std::vector<ExrImage>& files, const std::vector<ChannelRef>& refs,
                           const Imath::Box2i& window, float fill, bool allow_uint, const std::string& label);

// Converts the mapped channels to float planes over frameWindow(). A pass whose data window differs
// (crop, overscan) is resampled onto it: pixels it does not cover get background (position NaN,
// other attributes 0). Throws Error(Input) naming the file and channel for subsampled channels,
// UINT where a float attribute is expected (ObjectId accepts all types), display windows that differ.
GBuffer extractGBuffer(const ExrImage& image, const ChannelMapping& mapping);
GBuffer extractGBuffer(const std::vector<ExrImage>& files, const ChannelMapping& mapping);

// Writes a float plane (over frameWindow()) back into the attribute's mapped channels, converting
// to each channel's own sample type; channel pixels outside the G-buffer window are left alone.
// Pixels whose float value equals the original conversion stay bit-exact.
void storeAttribute(ExrImage& image, const ChannelMapping& mapping, Attribute attribute,
                    const Plane& plane);
void storeAttribute(std::vector<ExrImage>& files, const ChannelMapping& mapping, Attribute attribute,
                    const Plane& plane);

// ---- cameras in EXR headers ----

// Reads the standard worldToCamera / worldToNDC attributes (RenderMan conventions: left-handed
// camera looking down +Z, row-vector Imath storage, NDC x right and y down in [0,1] over the
// display window) and converts them to decalcomp's conventions. Returns nullopt when absent;
// throws Error(Input) when present but singular or inconsistent.
std::optional<Camera> cameraFromExrHeader(const Imf::Header& header, const std::string& file);
// The inverse, for the generator and round-trip tests.
void writeCameraToExrHeader(const Camera& camera, Imf::Header& header);

}  // namespace decalcomp
