#pragma once
// Small rendered sequences for the batch tests: the synthetic demo scene seen by a camera that
// moves a little every frame, written as generic-named EXRs (Z, albedo, P, a beauty RGBA layer)
// with the camera in each header, plus a decal scene with static and animated decals.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/batch.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/synth.hpp"
#include "images/image_codecs.hpp"
#include "support/test_support.hpp"

namespace decalcomp::test {

inline Camera sequenceCamera(int frame, int width, int height) {
    Camera c;
    c.world_to_camera = lookAt({1.0 + 0.15 * frame, -5.2, 3.0}, {0.2, 1.0, 0.8}, {0, 0, 1});
    c.projection = perspectiveProjection(0.87, double(width) / height, 0.1, 100.0);
    c.source = "test sequence camera";
    return c;
}

// The synthetic demo scene seen by sequenceCamera(frame), depth in `depth`'s convention.
inline GBuffer renderSequenceFrame(int frame, int width, int height, DepthConvention depth = DepthConvention::Planar) {
    synth::RenderOptions options;
    options.width = width;
    options.height = height;
    options.depth = depth;
    return synth::render(synth::demoScene(), sequenceCamera(frame, width, height), options);
}

// Float samples by channel name, for writeFloatExr.
using ChannelSamples = std::map<std::string, std::vector<float>>;

// A frame's passes as the generic profile names them: Z, albedo.RGB, P.XYZ.
inline ChannelSamples genericPasses(const GBuffer& g) {
    ChannelSamples channels;
    const Plane& depth = g.planes.at(Attribute::Depth);
    const Plane& albedo = g.planes.at(Attribute::Albedo);
    const Plane& position = g.planes.at(Attribute::Position);
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        channels["Z"].push_back(depth.at(i, 0));
        for (int c = 0; c < 3; ++c) {
            channels[std::string("albedo.") + "RGB"[c]].push_back(albedo.at(i, c));
            channels[std::string("P.") + "XYZ"[c]].push_back(position.at(i, c));
        }
    }
    return channels;
}

// A single-part ZIP-compressed EXR of float channels, with `camera` in its header when given.
inline void writeFloatExr(const std::string& path, int width, int height, const ChannelSamples& channels,
                          const std::optional<Camera>& camera = std::nullopt) {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    if (camera) writeCameraToExrHeader(*camera, header);
    Imf::FrameBuffer fb;
    for (const auto& [channel, samples] : channels) {
        header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
        // OutputFile only reads the slices.
        fb.insert(channel, Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(samples.data())),
                                      sizeof(float), sizeof(float) * std::size_t(width)));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(height);
}

// frame.####.exr under `dir` for each frame; returns the pattern.
inline std::string writeSequence(const std::filesystem::path& dir, const std::vector<int>& frames, int width = 64,
                                 int height = 48, const std::string& name = "frame.####.exr",
                                 bool header_camera = true) {
    std::filesystem::create_directories(dir);
    const FramePattern pattern((dir / name).string());
    for (int f : frames) {
        const GBuffer g = renderSequenceFrame(f, width, height);
        ChannelSamples channels = genericPasses(g);
        const Plane& albedo = g.planes.at(Attribute::Albedo);
        for (std::size_t i = 0; i < g.pixelCount(); ++i) {
            for (int c = 0; c < 3; ++c)
                channels[std::string(1, "RGB"[c])].push_back(0.5f * albedo.at(i, c) + 0.01f * float(f));
            channels["A"].push_back(1.0f);
        }
        writeFloatExr(pattern.path(f), width, height, channels,
                      header_camera ? std::optional<Camera>(sequenceCamera(f, width, height)) : std::nullopt);
    }
    return (dir / name).string();
}

// A 4x4 opaque RGBA8 PNG of one colour.
inline void writeSolidPng(const std::string& path, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    std::vector<std::uint8_t> px;
    for (int i = 0; i < 16; ++i) px.insert(px.end(), {r, g, b, 255});
    EXPECT_EQ(images::imageCodecs(ErrorKind::Output, path).write(path, images::png8(4, 4, 4, px.data())), "") << path;
}

// A static decal on the floor, one that lives frames 3-6 with fades, and one keyframed across
// the floor from frame 1 to 8.
inline std::string writeSequenceScene(const std::filesystem::path& dir) {
    writeSolidPng((dir / "red.png").string(), 230, 20, 20);
    writeSolidPng((dir / "green.png").string(), 20, 230, 20);
    const std::string path = (dir / "scene.json").string();
    std::ofstream(path) << R"({
  "textures": {"red": "red.png", "green": "green.png"},
  "decals": [
    {"name": "static", "texture": "red", "translate": [0.5, 0.0, 0.0], "scale": [1.0, 1.0, 0.5]},
    {"name": "flash", "texture": "green", "translate": [-0.5, -0.5, 0.0], "scale": [0.8, 0.8, 0.5],
     "frames": [3, 6], "fade_in": 1, "fade_out": 1},
    {"name": "mover", "texture": "green",
     "keyframes": [{"frame": 1, "translate": [-1.5, -1.0, 0.0], "rotate_deg": [0, 0, 0], "scale": [0.6, 0.6, 0.5]},
                   {"frame": 8, "translate": [1.5, -1.0, 0.0], "rotate_deg": [0, 0, 90], "scale": [0.6, 0.6, 0.5]}]}
  ]
})";
    return path;
}

// One static red decal on the floor (2 x 2 units) and nothing animated, so a frame composites
// the same with or without a frame number. `affects` is the decal's "affects" JSON, if any.
inline std::string writeStaticScene(const std::filesystem::path& dir, const std::string& affects = "") {
    writeSolidPng((dir / "red.png").string(), 230, 20, 20);
    const std::string path = (dir / "static_scene.json").string();
    std::ofstream(path) << R"({"textures": {"red": "red.png"}, "decals": [{"name": "static", "texture": "red", )"
                        << R"("translate": [0.5, 0.0, 0.0], "scale": [2.0, 2.0, 0.5])"
                        << (affects.empty() ? "" : ", \"affects\": " + affects) << "}]}";
    return path;
}

// What one frame's output must be: the input with the scene at that frame composited into its
// albedo, computed here without the batch code.
// `camera` defaults to the header's.
inline ExrImage expectedFrame(const std::string& input, const DecalScene& scene, int frame, ComputeDevice& device,
                              std::optional<Camera> camera = std::nullopt) {
    ExrImage image = readExr(input);
    const DecalScene at = sceneAtFrame(scene, frame);
    if (at.decals.empty()) return image;
    const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    GBuffer g = extractGBuffer(image, mapping);
    if (!camera) camera = cameraFromExrHeader(image.parts.at(0).header, input);
    Compositor compositor(device);
    compositor.setScene(at);
    compositor.composite(g, *camera);
    storeAttribute(image, mapping, Attribute::Albedo, g.planes.at(Attribute::Albedo));
    return image;
}

// Every channel's samples of both images, for exact comparison ("" when equal, else the first
// difference).
inline std::string pixelDifference(const ExrImage& a, const ExrImage& b) {
    if (a.parts.size() != b.parts.size()) return "part count differs";
    for (std::size_t p = 0; p < a.parts.size(); ++p) {
        if (a.parts[p].channels.size() != b.parts[p].channels.size()) return "channel count differs";
        for (std::size_t c = 0; c < a.parts[p].channels.size(); ++c)
            if (a.parts[p].channels[c].name != b.parts[p].channels[c].name ||
                a.parts[p].channels[c].bytes != b.parts[p].channels[c].bytes)
                return "channel " + a.parts[p].channels[c].name + " differs";
    }
    return "";
}

inline std::string readFileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace decalcomp::test
