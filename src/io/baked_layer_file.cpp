// The baked layer file of bake-mode texture-space decals (bake.hpp, docs/texture-space.md "Bake
// mode"): an EXR of float RGBA (albedo), orm.RGBA and emission.RGBA, premultiplied as baked, with
// the rest mesh's fingerprint in its header; and the albedo as an 8-bit PNG for painting programs.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "decalcomp/bake.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/temporary_files.hpp"
#include "decalcomp/textures.hpp"

namespace decalcomp {

namespace {

constexpr const char* kMeshAttribute = "decalcomp/bake_mesh";
constexpr const char* kDecalAttribute = "decalcomp/bake_decal";

std::string fingerprintText(std::uint64_t fingerprint) { return fmt::format("{:016x}", fingerprint); }

// Writes through a temporary renamed by the caller; removes it when writing fails.
void writeImage(const std::string& temporary, const std::string& final_path, const char* format,
                const OIIO::ImageSpec& image_spec, OIIO::TypeDesc type, const void* data) {
    const std::string opening_name = createTemporary(temporary, final_path);
    // The same bake gives the same bytes (a pipeline may cache on them): no capture date, which
    // OpenImageIO's EXR writer would otherwise stamp with the current time.
    OIIO::ImageSpec spec = image_spec;
    spec.attribute("DateTime", "");
    auto out = OIIO::ImageOutput::create(format);
    if (!out || !out->open(opening_name, spec) || !out->write_image(type, data) || !out->close()) {
        const std::string why = out ? out->geterror() : OIIO::geterror();
        discardTemporary(temporary);
        throw outputError(fmt::format("{}: cannot write the baked layer: {}", final_path, why));
    }
}

}  // namespace

BakedLayers readBakedLayers(const std::string& path, const RestMesh& mesh) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw inputError(fmt::format("{}: baked layer file not found (write it with decalcomp bake)", path));
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw inputError(fmt::format("{}: not a readable image ({})", path, OIIO::geterror()));
    const OIIO::ImageSpec spec = in->spec();
    if (in->format_name() != std::string("openexr"))
        throw inputError(fmt::format("{}: a baked layer file is an EXR written by decalcomp bake", path));
    const std::string fingerprint = spec.get_string_attribute(kMeshAttribute);
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
    for (int c = 0; c < spec.nchannels; ++c) channel[spec.channel_name(c)] = c;
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
        throw inputError(fmt::format("{}: cannot read the baked layer: {}", path, in->geterror()));
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
            for (int k = 0; k < 4; ++k) t.texels[i][k] = pixels[i * std::size_t(spec.nchannels) + std::size_t(index[k])];
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
    OIIO::ImageSpec spec(layers.width, layers.height, channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (const auto& [texture, prefix] : parts)
        for (const char* c : {"R", "G", "B", "A"}) spec.channelnames.push_back(prefix + c);
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute(kMeshAttribute, fingerprintText(restMeshFingerprint(mesh)));
    spec.attribute(kDecalAttribute, decal_name);
    const std::size_t texels = std::size_t(layers.width) * std::size_t(layers.height);
    std::vector<float> pixels(texels * std::size_t(channels));
    for (std::size_t i = 0; i < texels; ++i)
        for (std::size_t p = 0; p < parts.size(); ++p)
            for (int k = 0; k < 4; ++k) pixels[i * std::size_t(channels) + p * 4 + std::size_t(k)] = parts[p].first->texels[i][k];
    std::vector<std::pair<std::string, std::string>> written;
    try {
        written.emplace_back(temporaryPathFor(exr), exr);
        writeImage(written.back().first, exr, "openexr", spec, OIIO::TypeDesc::FLOAT, pixels.data());
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
            OIIO::ImageSpec png_spec(layers.width, layers.height, 4, OIIO::TypeDesc::UINT8);
            png_spec.attribute("oiio:UnassociatedAlpha", 1);
            written.emplace_back(temporaryPathFor(png), png);
            writeImage(written.back().first, png, "png", png_spec, OIIO::TypeDesc::UINT8, bytes.data());
        }
    } catch (...) {
        for (std::size_t k = 0; k + 1 < written.size(); ++k) discardTemporary(written[k].first);
        throw;
    }
    commitTemporaries(written);
}

}  // namespace decalcomp
