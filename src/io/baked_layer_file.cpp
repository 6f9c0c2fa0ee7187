// The baked layer file of bake-mode texture-space decals (bake.hpp, docs/texture-space.md "Bake
// mode"): an EXR of float RGBA (albedo), orm.RGBA and emission.RGBA, premultiplied as baked, with
// the rest mesh's fingerprint in its header; and the albedo as an 8-bit PNG for painting programs.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "decalcomp/bake.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/temporary_files.hpp"
#include "decalcomp/textures.hpp"
#include "images/image_codecs.hpp"

namespace decalcomp {

namespace {

constexpr const char* kMeshAttribute = "decalcomp/bake_mesh";
constexpr const char* kDecalAttribute = "decalcomp/bake_decal";

std::string fingerprintText(std::uint64_t fingerprint) { return fmt::format("{:016x}", fingerprint); }

// Writes through a temporary renamed by the caller; removes it when writing fails.
void writeImage(const std::string& temporary, const std::string& final_path, images::ImageToWrite image) {
    const images::Codecs& codecs = images::imageCodecs(ErrorKind::Output, final_path);
    const std::string opening_name = createTemporary(temporary, final_path);
    // The same bake gives the same bytes (a pipeline may cache on them): no capture date, which
    // OpenImageIO's EXR writer would otherwise stamp with the current time.
    image.attributes.emplace_back("DateTime", "");
    if (const std::string why = codecs.write(opening_name, image); !why.empty()) {
        discardTemporary(temporary);
        throw outputError(fmt::format("{}: cannot write the baked layer: {}", final_path, why));
    }
}

}  // namespace

BakedLayers readBakedLayers(const std::string& path, const RestMesh& mesh) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw inputError(fmt::format("{}: baked layer file not found (write it with decalcomp bake)", path));
    std::string failure;
    const auto in = images::imageCodecs(ErrorKind::Input, path).open(path, /*straight_alpha=*/false, failure);
    if (!in) throw inputError(fmt::format("{}: not a readable image ({})", path, failure));
    const images::ImageHeader& spec = in->header();
    if (spec.format != "openexr")
        throw inputError(fmt::format("{}: a baked layer file is an EXR written by decalcomp bake", path));
    const std::string fingerprint = in->stringAttribute(kMeshAttribute);
    if (fingerprint.empty())
        throw inputError(fmt::format("{}: no {} attribute: not a decalcomp bake (write it with decalcomp bake)", path,
                                     kMeshAttribute));
    if (fingerprint != fingerprintText(restMeshFingerprint(mesh)))
        throw inputError(fmt::format("{}: baked for another mesh than {} (its UVs or rest positions differ); re-run "
                                     "decalcomp bake with this mesh",
                                     path, mesh.source));
    if (spec.width != spec.height || spec.width < 1 || spec.depth != 1)
        throw inputError(fmt::format("{}: a bake is a square layer, this is {}x{}", path, spec.width, spec.height));
    std::map<std::string, int> channel;
    for (int c = 0; c < spec.channels && c < int(spec.channel_names.size()); ++c) channel[spec.channel_names[c]] = c;
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.channels));
    if (const std::string why = in->read(images::Sample::Float, pixels.data()); !why.empty())
        throw inputError(fmt::format("{}: cannot read the baked layer: {}", path, why));
    auto layer = [&](const std::string& prefix) -> std::optional<Texture2D> {
        int index[4];
        const char* names[4] = {"R", "G", "B", "A"};
        for (int k = 0; k < 4; ++k) {
            const auto it = channel.find(prefix + names[k]);
            if (it == channel.end()) return std::nullopt;
            index[k] = it->second;
        }
        Texture2D t;
        t.source = path;
        t.width = spec.width;
        t.height = spec.height;
        t.texels.resize(std::size_t(spec.width) * std::size_t(spec.height));
        for (std::size_t i = 0; i < t.texels.size(); ++i)
            for (int k = 0; k < 4; ++k) t.texels[i][k] = pixels[i * std::size_t(spec.channels) + std::size_t(index[k])];
        return t;
    };
    BakedLayers out;
    out.width = spec.width;
    out.height = spec.height;
    auto albedo = layer("");
    if (!albedo) throw inputError(fmt::format("{}: no R, G, B, A channels (the albedo layer of a bake)", path));
    out.albedo = std::move(*albedo);
    out.orm = layer("orm.");
    out.emission = layer("emission.");
    return out;
}

void writeBakedLayers(const BakedLayers& layers, const RestMesh& mesh, const std::string& decal_name,
                      const std::string& exr, const std::string& png) {
    std::vector<std::pair<const Texture2D*, std::string>> parts = {{&layers.albedo, ""}};
    if (layers.orm) parts.emplace_back(&*layers.orm, "orm.");
    if (layers.emission) parts.emplace_back(&*layers.emission, "emission.");
    const int channels = int(parts.size()) * 4;
    images::ImageToWrite layer_file;
    layer_file.format = "openexr";
    layer_file.width = layers.width;
    layer_file.height = layers.height;
    layer_file.channels = channels;
    layer_file.sample = images::Sample::Float;
    for (const auto& [texture, prefix] : parts)
        for (const char* c : {"R", "G", "B", "A"}) layer_file.channel_names.push_back(prefix + c);
    layer_file.alpha_channel = 3;
    layer_file.attributes = {{"compression", "zip"},
                             {kMeshAttribute, fingerprintText(restMeshFingerprint(mesh))},
                             {kDecalAttribute, decal_name}};
    const std::size_t texels = std::size_t(layers.width) * std::size_t(layers.height);
    std::vector<float> pixels(texels * std::size_t(channels));
    for (std::size_t i = 0; i < texels; ++i)
        for (std::size_t p = 0; p < parts.size(); ++p)
            for (int k = 0; k < 4; ++k) pixels[i * std::size_t(channels) + p * 4 + std::size_t(k)] = parts[p].first->texels[i][k];
    std::vector<std::pair<std::string, std::string>> written;
    try {
        written.emplace_back(temporaryPathFor(exr), exr);
        layer_file.pixels = pixels.data();
        writeImage(written.back().first, exr, layer_file);
        if (!png.empty()) {
            // straight sRGB colour over the coverage, what painting programs expect of a PNG
            std::vector<unsigned char> bytes(texels * 4);
            for (std::size_t i = 0; i < texels; ++i) {
                const glm::vec4& t = layers.albedo.texels[i];
                for (int k = 0; k < 3; ++k) {
                    const float straight = t.w > 0.0f ? t[k] / t.w : 0.0f;
                    bytes[i * 4 + std::size_t(k)] = linearToSrgbByte(straight);
                }
                bytes[i * 4 + 3] = (unsigned char)std::lround(std::clamp(t.w, 0.0f, 1.0f) * 255.0f);
            }
            images::ImageToWrite painting = images::png8(layers.width, layers.height, 4, bytes.data());
            painting.straight_alpha = true;
            written.emplace_back(temporaryPathFor(png), png);
            writeImage(written.back().first, png, painting);
        }
    } catch (...) {
        for (std::size_t k = 0; k + 1 < written.size(); ++k) discardTemporary(written[k].first);
        throw;
    }
    commitTemporaries(written);
}

}  // namespace decalcomp
