#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

const char* attributeName(Attribute a) {
    switch (a) {
        case Attribute::Depth: return "depth";
        case Attribute::Albedo: return "albedo";
        case Attribute::Normal: return "normal";
        case Attribute::Position: return "position";
        case Attribute::ObjectId: return "object_id";
        case Attribute::UV: return "uv";
        case Attribute::Roughness: return "roughness";
        case Attribute::Metallic: return "metallic";
        case Attribute::AmbientOcclusion: return "ao";
        case Attribute::Emission: return "emission";
    }
    return "?";
}

std::optional<Attribute> attributeFromName(const std::string& name) {
    for (Attribute a : kAllAttributes)
        if (name == attributeName(a)) return a;
    if (name == "id") return Attribute::ObjectId;
    return std::nullopt;
}

int attributeComponents(Attribute a) {
    switch (a) {
        case Attribute::Albedo:
        case Attribute::Normal:
        case Attribute::Position:
        case Attribute::Emission: return 3;
        case Attribute::UV: return 2;
        default: return 1;
    }
}

const char* depthConventionName(DepthConvention c) {
    switch (c) {
        case DepthConvention::Planar: return "planar";
        case DepthConvention::Radial: return "radial";
        case DepthConvention::Ndc: return "ndc";
        case DepthConvention::Position: return "position";
    }
    return "?";
}

std::optional<DepthConvention> depthConventionFromName(const std::string& name) {
    for (DepthConvention c : {DepthConvention::Planar, DepthConvention::Radial, DepthConvention::Ndc,
                              DepthConvention::Position})
        if (name == depthConventionName(c)) return c;
    return std::nullopt;
}

}  // namespace decalcomp
