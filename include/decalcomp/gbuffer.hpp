#pragma once
// A frame's attribute planes in float, decoupled from the file they came from.
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/pixel_filter.hpp"

namespace decalcomp {

enum class Attribute {
    Depth, Albedo, Normal, Position, ObjectId, UV, Roughness, Metallic, AmbientOcclusion, Emission
};
constexpr std::array<Attribute, 10> kAllAttributes = {
    Attribute::Depth,    Attribute::Albedo,    Attribute::Normal,   Attribute::Position,         Attribute::ObjectId,
    Attribute::UV,       Attribute::Roughness, Attribute::Metallic, Attribute::AmbientOcclusion, Attribute::Emission};
const char* attributeName(Attribute a);             // "depth", "albedo", ...
std::optional<Attribute> attributeFromName(const std::string& name);
int attributeComponents(Attribute a);                // depth 1, albedo 3, normal 3, uv 2 ...

enum class DepthConvention { Planar, Radial, Ndc, Position };
const char* depthConventionName(DepthConvention c);  // "planar", "radial", "ndc", "position"
std::optional<DepthConvention> depthConventionFromName(const std::string& name);

// How the normal plane stores its vectors: in world or camera space (the camera's own axes,
// -Z forward, +Y up), signed or packed as n * 0.5 + 0.5.
enum class NormalSpace { World, Camera };
struct NormalEncoding {
    NormalSpace space = NormalSpace::World;
    bool packed = false;
};

// Interleaved float samples, `components` per pixel, rows top to bottom.
struct Plane {
    int components = 0;
    std::vector<float> samples;
    float& at(std::size_t pixel, int c) { return samples[pixel * components + c]; }
    float at(std::size_t pixel, int c) const { return samples[pixel * components + c]; }
};

struct GBuffer {
    int width = 0, height = 0;                  // data window size
    int origin_x = 0, origin_y = 0;             // data window min minus display window min
    int display_width = 0, display_height = 0;  // display window size (defines NDC)
    DepthConvention depth_convention = DepthConvention::Planar;
    bool reversed_z = false;                    // only for DepthConvention::Ndc
    NormalEncoding normal_encoding;             // of the Normal plane, as in the file
    PixelFilter pixel_filter;                   // the renderer's: decals are integrated over it
    bool uv_v_down = false;  // the UV pass counts v from the top (rest meshes count it from the bottom)
    std::map<Attribute, Plane> planes;
    // One single-component weight plane per DecalScene::masks entry, evaluated for this frame.
    std::vector<Plane> mask_weights;

    bool has(Attribute a) const { return planes.count(a) != 0; }
    std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
};

}  // namespace decalcomp
