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

// ---- channel mapping (renderer profiles) ----

struct ChannelRef {
    int part = -1;
    int channel = -1;
};

struct MappingOptions {
    std::string profile = "auto";  // auto | blender | generic
    std::string layer;             // Blender view layer to use when a file has several
    // --channel albedo=a.R,a.G,a.B : explicit channels per attribute, in component order
    std::map<Attribute, std::vector<std::string>> explicit_channels;
    std::optional<DepthConvention> depth_convention;  // explicit wins over the profile default
    bool reversed_z = false;
};

struct ChannelMapping {
    std::string profile;             // the profile that matched ("blender", "generic")
    std::vector<std::string> notes;  // human-readable reasons, for `decalcomp info`
    std::map<Attribute, std::vector<ChannelRef>> attributes;  // components in order
    DepthConvention depth_convention = DepthConvention::Planar;
    bool reversed_z = false;
};

// Throws Error(Input) for unknown profiles, explicit channels that do not exist, ambiguous layers.
ChannelMapping mapChannels(const ExrImage& image, const MappingOptions& options);

// Converts the mapped channels to float planes. Throws Error(Input) naming the file and channel
// when mapped channels have different data windows, subsampling, or the UINT type where a float
// attribute is expected (ObjectId accepts all types).
GBuffer extractGBuffer(const ExrImage& image, const ChannelMapping& mapping);

// Writes a float plane back into the attribute's mapped channels, converting to each channel's
// own sample type. Pixels whose float value equals the original conversion stay bit-exact.
void storeAttribute(ExrImage& image, const ChannelMapping& mapping, Attribute attribute,
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
