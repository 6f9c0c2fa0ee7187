#pragma once
// Small synthetic EXRs with Cryptomatte layers for the mask tests: a generic-profile G-buffer
// (Z, albedo) of kW x kH pixels plus rank channels and cryptomatte/<key>/... metadata built here,
// and evaluateMasks run over them.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>

#include <Imath/half.h>
#include <array>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::test {

struct Channel {
    std::string name;
    Imf::PixelType type = Imf::FLOAT;
    std::vector<float> values;  // one per pixel (for ids: the float whose bits are the id)
};

constexpr int kW = 4, kH = 2;
constexpr std::size_t kPixels = std::size_t(kW) * kH;

// A generic-profile G-buffer (Z, albedo) plus `extra` channels and string header attributes;
// `header_hook` may add more to the header (a camera).
inline std::string writeSynthetic(const std::string& path, std::vector<Channel> extra,
                                  const std::map<std::string, std::string>& attributes,
                                  const std::function<void(Imf::Header&)>& header_hook = {}) {
    extra.push_back({"Z", Imf::FLOAT, std::vector<float>(kPixels, 5.0f)});
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B"})
        extra.push_back({c, Imf::FLOAT, std::vector<float>(kPixels, 0.5f)});
    Imf::Header header(kW, kH);
    for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
    if (header_hook) header_hook(header);
    std::vector<std::vector<char>> storage;
    Imf::FrameBuffer fb;
    for (const Channel& c : extra) {
        header.channels().insert(c.name, Imf::Channel(c.type));
        const std::size_t size = c.type == Imf::HALF ? 2 : 4;
        storage.emplace_back(kPixels * size);
        for (std::size_t i = 0; i < kPixels; ++i) {
            char* p = storage.back().data() + i * size;
            if (c.type == Imf::HALF) {
                const std::uint16_t bits = Imath::half(c.values[i]).bits();
                std::memcpy(p, &bits, 2);
            } else if (c.type == Imf::UINT) {
                const std::uint32_t u = std::uint32_t(c.values[i]);
                std::memcpy(p, &u, 4);
            } else {
                std::memcpy(p, &c.values[i], 4);
            }
        }
        fb.insert(c.name, Imf::Slice(c.type, storage.back().data(), size, size * kW));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(kH);
    return path;
}

inline float idOf(const std::string& name) { return cryptomatteFloatFromHash(murmurHash3_32(name)); }

inline std::string hexOf(const std::string& name) { return fmt::format("{:08x}", murmurHash3_32(name)); }

using RankSuffixes = std::array<const char*, 4>;
inline constexpr RankSuffixes kLowerSuffixes = {"r", "g", "b", "a"};
inline constexpr RankSuffixes kNukeSuffixes = {"red", "green", "blue", "alpha"};

// (name, coverage) pairs of each pixel, highest rank first.
using PixelIds = std::vector<std::vector<std::pair<std::string, float>>>;

// Rank channel sets <layer>00, <layer>01, ... holding `pixels` (kPixels entries, missing ones
// empty), enough sets for the pixel with the most names.
inline std::vector<Channel> rankLayer(const std::string& layer, const PixelIds& pixels,
                                      const RankSuffixes& suffixes = kLowerSuffixes) {
    std::size_t ranks = 2;
    for (const auto& pixel : pixels) ranks = std::max(ranks, (pixel.size() + 1) / 2 * 2);
    std::vector<Channel> c;
    for (std::size_t set = 0; set < ranks / 2; ++set)
        for (const char* suffix : suffixes)
            c.push_back({fmt::format("{}{:02d}.{}", layer, set, suffix), Imf::FLOAT, std::vector<float>(kPixels)});
    for (std::size_t p = 0; p < pixels.size() && p < kPixels; ++p)
        for (std::size_t rank = 0; rank < pixels[p].size(); ++rank) {
            c[rank * 2].values[p] = idOf(pixels[p][rank].first);
            c[rank * 2 + 1].values[p] = pixels[p][rank].second;
        }
    return c;
}

// Two rank levels (four ranks). Pixel 0: A 0.5, B 0.3, C 0.15, D 0.05; pixel 1: C 0.6, A 0.4;
// pixel 2: D 1; pixel 3 and the second row: nothing.
inline std::vector<Channel> twoRankLayer(const std::string& layer, Imf::PixelType id_type = Imf::FLOAT,
                                         const RankSuffixes& suffixes = kLowerSuffixes) {
    std::vector<Channel> c = rankLayer(
        layer, {{{"A", 0.5f}, {"B", 0.3f}, {"C", 0.15f}, {"D", 0.05f}}, {{"C", 0.6f}, {"A", 0.4f}}, {{"D", 1.0f}}},
        suffixes);
    c[0].type = c[2].type = c[4].type = c[6].type = id_type;
    return c;
}

inline std::map<std::string, std::string> layerMetadata(const std::string& layer, const std::string& manifest,
                                                        const std::string& key = "0a1b2c3") {
    std::map<std::string, std::string> m = {{"cryptomatte/" + key + "/name", layer},
                                            {"cryptomatte/" + key + "/hash", "MurmurHash3_32"},
                                            {"cryptomatte/" + key + "/conversion", "uint32_to_float32"}};
    if (!manifest.empty()) m["cryptomatte/" + key + "/manifest"] = manifest;
    return m;
}

// A manifest of `names` with their MurmurHash3 ids.
inline std::string manifestOf(const std::vector<std::string>& names) {
    nlohmann::json m = nlohmann::json::object();
    for (const std::string& name : names) m[name] = hexOf(name);
    return m.dump();
}

inline Decal maskedDecal(const std::string& name, int mask) {
    Decal d;
    d.name = name;
    d.mask = mask;
    return d;
}

struct Evaluated {
    std::vector<Plane> weights;
    std::vector<std::string> warnings;
    float at(std::size_t mask, std::size_t pixel) const { return weights.at(mask).samples.at(pixel); }
};

// Masks d0, d1, ... (decal i uses mask i) evaluated over the file at `path`.
inline Evaluated evaluate(const std::string& path, const std::vector<DecalMask>& masks,
                          const std::vector<std::string>& labels = {}) {
    const ExrImage image = readExr(path);
    const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    GBuffer frame = extractGBuffer(image, mapping);
    DecalScene scene;
    scene.masks = masks;
    for (std::size_t m = 0; m < masks.size(); ++m) scene.decals.push_back(maskedDecal(fmt::format("d{}", m), int(m)));
    Evaluated e;
    evaluateMasks({image}, mapping, scene, frame, &e.warnings, labels);
    e.weights = frame.mask_weights;
    return e;
}

inline DecalMask crypto(std::vector<std::string> names, std::string layer = "CryptoObject") {
    return DecalMask{{}, {}, std::move(layer), std::move(names)};
}

}  // namespace decalcomp::test
