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
    Imf::Header header(g.width, g.height);
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

std::vector<Pass> passesFor(const GBuffer& g, const std::vector<float>& beauty, const ExrLayoutOptions& options) {
    const SampleType colour = options.half ? SampleType::Half : SampleType::Float;
    const bool has_depth = g.has(Attribute::Depth), has_position = g.has(Attribute::Position);
    std::vector<Pass> passes;
    auto add = [&](std::string part, std::vector<std::string> channels, std::vector<std::string> flat,
                   SampleType type, const std::vector<float>& samples, int components) {
        passes.push_back({std::move(part), std::move(channels), std::move(flat), type, &samples, components});
    };

    if (options.naming == Naming::Blender) {
        const std::string& l = options.layer;
        auto blender = [&](const std::string& pass, std::vector<std::string> channels, SampleType type,
                           const std::vector<float>& samples) {
            const std::string part = l + "." + pass;
            std::vector<std::string> flat;
            for (const std::string& c : channels) flat.push_back(part + "." + c);
            const int components = int(channels.size());
            add(part, std::move(channels), std::move(flat), type, samples, components);
        };
        blender("Combined", {"R", "G", "B", "A"}, colour, beauty);
        if (has_depth) blender("Depth", {"Z"}, SampleType::Float, planeSamples(g, Attribute::Depth, 1));
        blender("DiffCol", {"R", "G", "B"}, colour, planeSamples(g, Attribute::Albedo, 3));
        blender("Normal", {"X", "Y", "Z"}, colour, planeSamples(g, Attribute::Normal, 3));
        if (has_position)
            blender("Position", {"X", "Y", "Z"}, SampleType::Float, planeSamples(g, Attribute::Position, 3));
        blender("IndexOB", {"X"}, SampleType::Float, planeSamples(g, Attribute::ObjectId, 1));
    } else {
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

}  // namespace

std::vector<float> beautyShade(const GBuffer& g) {
    const std::vector<float>& albedo = planeSamples(g, Attribute::Albedo, 3);
    const std::vector<float>& normal = planeSamples(g, Attribute::Normal, 3);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.4f, -0.6f, 0.7f));
    const float ambient = 0.25f, direct = 0.9f;
    std::vector<float> rgba(g.pixelCount() * 4, 0.0f);
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        const glm::vec3 n(normal[i * 3], normal[i * 3 + 1], normal[i * 3 + 2]);
        if (!(glm::dot(n, n) > 0.25f)) continue;  // background
        const float light = ambient + direct * std::max(0.0f, glm::dot(n, sun));
        for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = albedo[i * 3 + c] * light;
        rgba[i * 4 + 3] = 1.0f;
    }
    return rgba;
}

ExrImage gbufferToExr(const GBuffer& g, const ExrLayoutOptions& options) {
    if (g.width <= 0 || g.height <= 0) throw outputError("G-buffer is empty");
    const std::vector<float> beauty = beautyShade(g);
    const std::vector<Pass> passes = passesFor(g, beauty, options);
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

}  // namespace decalcomp::gen
