#include "gbuffer_to_exr.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <Imath/half.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "decalcomp/error.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/synth_light.hpp"

namespace decalcomp::gen {

namespace {

// One pass: a source plane (interleaved floats) and the channels it becomes.
struct Pass {
    std::string part;                    // part name in multi-part files ("ViewLayer.Depth", "albedo")
    std::vector<std::string> channels;   // channel names inside the part ("Z"; "R", "G", "B")
    std::vector<std::string> flat;       // channel names in a single-part file, same order
    SampleType type = SampleType::Float;
    const std::vector<float>* samples = nullptr;
    int components = 0;
};

std::vector<unsigned char> encode(const Pass& pass, int component, std::size_t pixels) {
    const std::vector<float>& src = *pass.samples;
    std::vector<unsigned char> bytes;
    switch (pass.type) {
        case SampleType::Float:
            bytes.resize(pixels * 4);
            for (std::size_t i = 0; i < pixels; ++i) {
                const float v = src[i * pass.components + component];
                std::memcpy(bytes.data() + i * 4, &v, 4);
            }
            break;
        case SampleType::Half:
            bytes.resize(pixels * 2);
            for (std::size_t i = 0; i < pixels; ++i) {
                const std::uint16_t bits = Imath::half(src[i * pass.components + component]).bits();
                std::memcpy(bytes.data() + i * 2, &bits, 2);
            }
            break;
        case SampleType::Uint:
            bytes.resize(pixels * 4);
            for (std::size_t i = 0; i < pixels; ++i) {
                const float v = src[i * pass.components + component];
                const std::uint32_t u = v > 0.0f ? std::uint32_t(std::lround(v)) : 0u;
                std::memcpy(bytes.data() + i * 4, &u, 4);
            }
            break;
    }
    return bytes;
}

Imf::PixelType pixelType(SampleType type) {
    switch (type) {
        case SampleType::Uint: return Imf::UINT;
        case SampleType::Half: return Imf::HALF;
        case SampleType::Float: return Imf::FLOAT;
    }
    return Imf::FLOAT;
}

Imf::Header baseHeader(const GBuffer& g, const ExrLayoutOptions& options) {
    Imf::Header header(g.display_width > 0 ? g.display_width : g.width, g.display_height > 0 ? g.display_height : g.height);
    header.dataWindow() = Imath::Box2i({g.origin_x, g.origin_y}, {g.origin_x + g.width - 1, g.origin_y + g.height - 1});
    header.compression() = options.compression;
    header.insert("decalcomp:depthConvention",
                  Imf::StringAttribute(std::string(depthConventionName(g.depth_convention)) +
                                       (g.depth_convention == DepthConvention::Ndc && g.reversed_z ? " reversed-z" : "")));
    header.insert("decalcomp:generator", Imf::StringAttribute("decalcomp-gbuffer-gen"));
    if (options.header_camera) writeCameraToExrHeader(*options.header_camera, header);
    return header;
}

const std::vector<float>& planeSamples(const GBuffer& g, Attribute a, int components) {
    auto it = g.planes.find(a);
    if (it == g.planes.end() || it->second.components != components ||
        it->second.samples.size() != g.pixelCount() * std::size_t(components))
        throw outputError(fmt::format("G-buffer has no usable {} plane ({} component(s) expected)",
                                      attributeName(a), components));
    return it->second.samples;
}

// Camera-space normals (RenderMan's Nn): the rotation part of world_to_camera.
std::vector<float> cameraSpaceNormals(const GBuffer& g, const Camera& camera) {
    const std::vector<float>& world = planeSamples(g, Attribute::Normal, 3);
    const glm::dmat3 rotation(camera.world_to_camera);
    std::vector<float> out(world.size());
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        const glm::dvec3 n = rotation * glm::dvec3(world[i * 3], world[i * 3 + 1], world[i * 3 + 2]);
        for (int c = 0; c < 3; ++c) out[i * 3 + c] = float(n[c]);
    }
    return out;
}

std::vector<Pass> passesFor(const GBuffer& g, const std::vector<float>& beauty, const std::vector<float>& extra,
                            const ExrLayoutOptions& options) {
    const SampleType colour = options.half ? SampleType::Half : SampleType::Float;
    const bool has_depth = g.has(Attribute::Depth), has_position = g.has(Attribute::Position);
    std::vector<Pass> passes;
    auto add = [&](std::string part, std::vector<std::string> channels, std::vector<std::string> flat,
                   SampleType type, const std::vector<float>& samples, int components) {
        passes.push_back({std::move(part), std::move(channels), std::move(flat), type, &samples, components});
    };
    // Single-part names only (multi-part is for blender and generic naming).
    auto flat = [&](std::vector<std::string> names, SampleType type, const std::vector<float>& samples, int components) {
        add(names.front(), names, names, type, samples, components);
    };
    // One value written into several channels (Unreal's buffer visualisations are RGB).
    auto scalarAsRgb = [&](const std::string& pass, SampleType type, const std::vector<float>& samples) {
        for (const char* c : {"R", "G", "B"}) flat({pass + "." + c}, type, samples, 1);
    };

    switch (options.naming) {
        case Naming::Blender: {
            const std::string& l = options.layer;
            auto blender = [&](const std::string& pass, std::vector<std::string> channels, SampleType type,
                               const std::vector<float>& samples) {
                const std::string part = l + "." + pass;
                std::vector<std::string> flat_names;
                for (const std::string& c : channels) flat_names.push_back(part + "." + c);
                const int components = int(channels.size());
                add(part, std::move(channels), std::move(flat_names), type, samples, components);
            };
            blender("Combined", {"R", "G", "B", "A"}, colour, beauty);
            if (has_depth) blender("Depth", {"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1));
            blender("DiffCol", {"R", "G", "B"}, colour, planeSamples(g, Attribute::Albedo, 3));
            blender("Normal", {"X", "Y", "Z"}, colour, planeSamples(g, Attribute::Normal, 3));
            if (has_position)
                blender("Position", {"X", "Y", "Z"}, SampleType::Float, planeSamples(g, Attribute::Position, 3));
            blender("IndexOB", {"X"}, SampleType::Float, planeSamples(g, Attribute::ObjectId, 1));
        } break;
        case Naming::Generic:
            // Multi-part channel names are chosen so that "part.channel" is again a generic spelling.
            add("rgba", {"R", "G", "B", "A"}, {"R", "G", "B", "A"}, colour, beauty, 4);
            if (has_depth) add("depth", {"Z"}, {"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1), 1);
            add("albedo", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, colour,
                planeSamples(g, Attribute::Albedo, 3), 3);
            add("N", {"X", "Y", "Z"}, {"N.X", "N.Y", "N.Z"}, colour, planeSamples(g, Attribute::Normal, 3), 3);
            if (has_position)
                add("P", {"X", "Y", "Z"}, {"P.X", "P.Y", "P.Z"}, SampleType::Float,
                    planeSamples(g, Attribute::Position, 3), 3);
            add("id", {"V"}, {"id"}, SampleType::Uint, planeSamples(g, Attribute::ObjectId, 1), 1);
            add("roughness", {"V"}, {"roughness"}, colour, planeSamples(g, Attribute::Roughness, 1), 1);
            add("metallic", {"V"}, {"metallic"}, colour, planeSamples(g, Attribute::Metallic, 1), 1);
            break;
        case Naming::Arnold:
            flat({"R", "G", "B", "A"}, colour, beauty, 4);
            if (has_depth) flat({"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1), 1);
            flat({"diffuse_albedo.R", "diffuse_albedo.G", "diffuse_albedo.B"}, colour, planeSamples(g, Attribute::Albedo, 3), 3);
            flat({"N.X", "N.Y", "N.Z"}, colour, planeSamples(g, Attribute::Normal, 3), 3);
            if (has_position) flat({"P.X", "P.Y", "P.Z"}, SampleType::Float, planeSamples(g, Attribute::Position, 3), 3);
            flat({"ID"}, SampleType::Uint, planeSamples(g, Attribute::ObjectId, 1), 1);
            flat({"specular_roughness"}, colour, planeSamples(g, Attribute::Roughness, 1), 1);
            flat({"metalness"}, colour, planeSamples(g, Attribute::Metallic, 1), 1);
            break;
        case Naming::Karma:
            flat({"C.R", "C.G", "C.B", "C.A"}, colour, beauty, 4);
            if (has_depth) flat({"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1), 1);
            flat({"albedo.R", "albedo.G", "albedo.B"}, colour, planeSamples(g, Attribute::Albedo, 3), 3);
            flat({"N.R", "N.G", "N.B"}, colour, planeSamples(g, Attribute::Normal, 3), 3);
            if (has_position) flat({"P.R", "P.G", "P.B"}, SampleType::Float, planeSamples(g, Attribute::Position, 3), 3);
            flat({"id"}, SampleType::Float, planeSamples(g, Attribute::ObjectId, 1), 1);
            flat({"roughness"}, colour, planeSamples(g, Attribute::Roughness, 1), 1);
            flat({"metallic"}, colour, planeSamples(g, Attribute::Metallic, 1), 1);
            break;
        case Naming::RenderMan:
            flat({"Ci.r", "Ci.g", "Ci.b", "a"}, colour, beauty, 4);
            if (has_depth) flat({"z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1), 1);
            flat({"albedo.r", "albedo.g", "albedo.b"}, colour, planeSamples(g, Attribute::Albedo, 3), 3);
            flat({"Nn.x", "Nn.y", "Nn.z"}, colour, extra, 3);  // camera space
            if (has_position)
                flat({"__Pworld.x", "__Pworld.y", "__Pworld.z"}, SampleType::Float, planeSamples(g, Attribute::Position, 3), 3);
            flat({"id"}, SampleType::Float, planeSamples(g, Attribute::ObjectId, 1), 1);
            flat({"roughness"}, colour, planeSamples(g, Attribute::Roughness, 1), 1);
            flat({"metallic"}, colour, planeSamples(g, Attribute::Metallic, 1), 1);
            break;
        case Naming::Unreal:
            flat({"FinalImage.R", "FinalImage.G", "FinalImage.B", "FinalImage.A"}, colour, beauty, 4);
            if (has_depth) scalarAsRgb("SceneDepthWorldUnits", SampleType::Float, planeSamples(g, Attribute::Depth, 1));
            flat({"BaseColor.R", "BaseColor.G", "BaseColor.B"}, colour, planeSamples(g, Attribute::Albedo, 3), 3);
            flat({"WorldNormal.R", "WorldNormal.G", "WorldNormal.B"}, colour, planeSamples(g, Attribute::Normal, 3), 3);
            if (has_position)
                flat({"WorldPosition.R", "WorldPosition.G", "WorldPosition.B"}, SampleType::Float,
                     planeSamples(g, Attribute::Position, 3), 3);
            scalarAsRgb("CustomStencil", SampleType::Float, planeSamples(g, Attribute::ObjectId, 1));
            scalarAsRgb("Roughness", colour, planeSamples(g, Attribute::Roughness, 1));
            scalarAsRgb("Metallic", colour, planeSamples(g, Attribute::Metallic, 1));
            break;
    }
    return passes;
}

void addChannel(ExrPart& part, const std::string& name, const Pass& pass, int component, std::size_t pixels) {
    part.header.channels().insert(name, Imf::Channel(pixelType(pass.type)));
    ExrChannel channel;
    channel.name = name;
    channel.qualified = name;
    channel.type = pass.type;
    channel.bytes = encode(pass, component, pixels);
    part.channels.push_back(std::move(channel));
}

// The order readExr produces: OpenEXR keeps a part's channels sorted by name.
void sortChannels(ExrPart& part) {
    std::sort(part.channels.begin(), part.channels.end(),
              [](const ExrChannel& a, const ExrChannel& b) { return a.name < b.name; });
}

// The diffuse light passes in a renderer's naming: Blender divides them by DiffCol; Arnold and
// RenderMan store them multiplied by the albedo (their profiles' "light" model).
struct LightSamples {
    std::vector<float> direct, indirect;  // RGB, interleaved
};

bool lightMultiplied(Naming naming) { return naming == Naming::Arnold || naming == Naming::RenderMan; }

LightSamples lightSamples(const GBuffer& g, Naming naming) {
    if (naming != Naming::Blender && !lightMultiplied(naming))
        throw outputError("--light-passes is for blender, arnold and renderman naming");
    synth::LightPasses light = synth::lightPasses(g);
    if (lightMultiplied(naming)) {
        const Plane& albedo = g.planes.at(Attribute::Albedo);
        for (std::size_t i = 0; i < g.pixelCount(); ++i)
            for (int c = 0; c < 3; ++c) light.direct.at(i, c) *= albedo.at(i, c), light.indirect.at(i, c) *= albedo.at(i, c);
    }
    return {std::move(light.direct.samples), std::move(light.indirect.samples)};
}

void addLightPasses(std::vector<Pass>& passes, const LightSamples& light, const ExrLayoutOptions& options) {
    struct Names {
        std::string direct, indirect, components;
    };
    const Names names = options.naming == Naming::Blender ? Names{options.layer + ".DiffDir", options.layer + ".DiffInd", "RGB"}
                        : options.naming == Naming::Arnold ? Names{"diffuse_direct", "diffuse_indirect", "RGB"}
                                                           : Names{"directDiffuse", "indirectDiffuse", "rgb"};
    for (const auto& [part, samples] : {std::pair{names.direct, &light.direct}, std::pair{names.indirect, &light.indirect}}) {
        std::vector<std::string> channels, flat;
        for (char c : names.components) channels.push_back(std::string(1, c)), flat.push_back(part + "." + c);
        passes.push_back({part, channels, flat, SampleType::Float, samples, 3});
    }
}

}  // namespace

std::vector<float> beautyShade(const GBuffer& g) {
    planeSamples(g, Attribute::Albedo, 3);  // named errors for missing planes
    planeSamples(g, Attribute::Normal, 3);
    return synth::lightPasses(g).beauty.samples;
}

ExrImage gbufferToExr(const GBuffer& g, const ExrLayoutOptions& options) {
    if (g.width <= 0 || g.height <= 0) throw outputError("G-buffer is empty");
    if (options.multipart && options.naming != Naming::Blender && options.naming != Naming::Generic)
        throw outputError("multi-part output is for blender and generic naming");
    const std::vector<float> beauty = beautyShade(g);
    const std::vector<float> extra =
        options.naming == Naming::RenderMan ? cameraSpaceNormals(g, options.camera) : std::vector<float>();
    std::vector<Pass> passes = passesFor(g, beauty, extra, options);
    const LightSamples light = options.light_passes ? lightSamples(g, options.naming) : LightSamples{};
    if (options.light_passes) addLightPasses(passes, light, options);
    const std::size_t pixels = g.pixelCount();

    ExrImage image;
    if (options.multipart) {
        for (const Pass& pass : passes) {
            ExrPart part;
            part.header = baseHeader(g, options);
            part.header.setName(pass.part);
            part.header.setType(Imf::SCANLINEIMAGE);
            part.width = g.width;
            part.height = g.height;
            for (int c = 0; c < int(pass.channels.size()); ++c) {
                addChannel(part, pass.channels[c], pass, c, pixels);
                part.channels.back().qualified = pass.part + "." + pass.channels[c];
            }
            sortChannels(part);
            image.parts.push_back(std::move(part));
        }
    } else {
        ExrPart part;
        part.header = baseHeader(g, options);
        part.width = g.width;
        part.height = g.height;
        for (const Pass& pass : passes)
            for (int c = 0; c < int(pass.flat.size()); ++c) addChannel(part, pass.flat[c], pass, c, pixels);
        sortChannels(part);
        image.parts.push_back(std::move(part));
    }
    return image;
}

std::vector<std::pair<std::string, ExrImage>> gbufferToPassFiles(const GBuffer& g, const ExrLayoutOptions& options) {
    if (g.width <= 0 || g.height <= 0) throw outputError("G-buffer is empty");
    const SampleType colour = options.half ? SampleType::Half : SampleType::Float;
    const std::vector<float> beauty = beautyShade(g);
    std::vector<std::pair<std::string, Pass>> passes;
    auto add = [&](const std::string& key, std::vector<std::string> channels, SampleType type,
                   const std::vector<float>& samples) {
        const int components = int(channels.size());
        passes.push_back({key, Pass{key, channels, channels, type, &samples, components}});
    };
    add("beauty", {"R", "G", "B", "A"}, colour, beauty);
    if (g.has(Attribute::Depth)) add("depth", {"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1));
    add("albedo", {"R", "G", "B"}, colour, planeSamples(g, Attribute::Albedo, 3));
    add("normal", {"X", "Y", "Z"}, colour, planeSamples(g, Attribute::Normal, 3));
    if (g.has(Attribute::Position))
        add("position", {"X", "Y", "Z"}, SampleType::Float, planeSamples(g, Attribute::Position, 3));
    add("id", {"id"}, SampleType::Uint, planeSamples(g, Attribute::ObjectId, 1));
    add("roughness", {"Y"}, colour, planeSamples(g, Attribute::Roughness, 1));
    add("metallic", {"Y"}, colour, planeSamples(g, Attribute::Metallic, 1));

    std::vector<std::pair<std::string, ExrImage>> files;
    for (const auto& [key, pass] : passes) {
        ExrPart part;
        part.header = baseHeader(g, options);
        part.width = g.width;
        part.height = g.height;
        for (int c = 0; c < int(pass.flat.size()); ++c) addChannel(part, pass.flat[c], pass, c, g.pixelCount());
        sortChannels(part);
        ExrImage image;
        image.parts.push_back(std::move(part));
        files.emplace_back(key, std::move(image));
    }
    return files;
}

const char* namingName(Naming naming) {
    switch (naming) {
        case Naming::Blender: return "blender";
        case Naming::Generic: return "generic";
        case Naming::Arnold: return "arnold";
        case Naming::Karma: return "karma";
        case Naming::RenderMan: return "renderman";
        case Naming::Unreal: return "unreal";
    }
    return "?";
}

std::optional<Naming> namingFromName(const std::string& name) {
    for (Naming n : {Naming::Blender, Naming::Generic, Naming::Arnold, Naming::Karma, Naming::RenderMan, Naming::Unreal})
        if (name == namingName(n)) return n;
    return std::nullopt;
}

}  // namespace decalcomp::gen
