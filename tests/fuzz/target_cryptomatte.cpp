// Cryptomatte manifests and name patterns. The input is lines of text: a manifest (JSON), the layer
// a mask asks for ("CryptoObject"), then the names it selects ("Wall*", "Box"). They go into a
// small in-memory frame with two Cryptomatte layers (one with that manifest, one keyed by hash
// alone), whose rank channels hold the manifest's ids and the names' hashes, and the mask is
// evaluated over it (evaluateMasks: layer lookup, manifest parsing, matching, coverage).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/masks.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace {

constexpr int kSide = 4;  // the frame is kSide x kSide pixels
constexpr int kPixels = kSide * kSide;

std::vector<std::string> lines(std::string_view text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        out.emplace_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

void addFloatChannel(ExrPart& part, const std::string& name, const std::vector<float>& samples) {
    part.header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    ExrChannel channel;
    channel.name = channel.qualified = name;
    channel.type = SampleType::Float;
    channel.bytes.resize(samples.size() * sizeof(float));
    std::memcpy(channel.bytes.data(), samples.data(), channel.bytes.size());
    part.channels.push_back(std::move(channel));
}

float idFloat(std::uint32_t hash) { return cryptomatteFloatFromHash(hash); }

// Two ranks (00, 01) of `layer`, cycling through `ids` so every id covers some pixels.
void addLayer(ExrPart& part, const std::string& key, const std::string& layer, const std::string& manifest,
              const std::vector<std::uint32_t>& ids) {
    const std::string prefix = "cryptomatte/" + key + "/";
    part.header.insert(prefix + "name", Imf::StringAttribute(layer));
    part.header.insert(prefix + "hash", Imf::StringAttribute("MurmurHash3_32"));
    part.header.insert(prefix + "conversion", Imf::StringAttribute("uint32_to_float32"));
    if (!manifest.empty()) part.header.insert(prefix + "manifest", Imf::StringAttribute(manifest));
    for (int rank = 0; rank < 2; ++rank) {
        std::vector<float> r(kPixels), g(kPixels), b(kPixels), a(kPixels);
        for (int i = 0; i < kPixels; ++i) {
            const std::size_t n = ids.size();
            r[i] = n ? idFloat(ids[(std::size_t(i) + std::size_t(rank) * 2) % n]) : 0.0f;
            g[i] = rank == 0 ? 0.5f : 0.125f;
            b[i] = n ? idFloat(ids[(std::size_t(i) + std::size_t(rank) * 2 + 1) % n]) : 0.0f;
            a[i] = rank == 0 ? 0.25f : 0.125f;
        }
        const std::string channels = layer + (rank == 0 ? "00." : "01.");
        addFloatChannel(part, channels + "r", r);
        addFloatChannel(part, channels + "g", g);
        addFloatChannel(part, channels + "b", b);
        addFloatChannel(part, channels + "a", a);
    }
}

// The manifest's hashes (none when it does not parse) and the names' own hashes.
std::vector<std::uint32_t> idsFor(const std::string& manifest, const std::vector<std::string>& names) {
    std::vector<std::uint32_t> ids;
    CryptomatteLayer probe;
    probe.file = "fuzz.exr";
    probe.key = "probe";
    probe.manifest = manifest;
    inputErrorsAllowed([&] {
        for (const auto& [name, hash] : cryptomatteManifest(probe).names) ids.push_back(hash);
    });
    for (const std::string& name : names) ids.push_back(murmurHash3_32(name));
    return ids;
}

}  // namespace

void fuzzCryptomatte(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> input = lines(asText(data, size));
    const std::string manifest = input[0];
    const std::string layer = input.size() > 1 ? input[1] : "CryptoObject";
    const std::vector<std::string> names(input.begin() + std::min<std::ptrdiff_t>(2, std::ptrdiff_t(input.size())),
                                         input.end());
    const std::vector<std::uint32_t> ids = idsFor(manifest, names);

    ExrImage image;
    image.path = "fuzz.exr";
    ExrPart part;
    part.header = Imf::Header(kSide, kSide);
    part.width = part.height = kSide;
    addFloatChannel(part, "ViewLayer.Depth.Z", std::vector<float>(kPixels, 2.0f));
    addLayer(part, "542cafa", "ViewLayer.CryptoObject", manifest, ids);
    addLayer(part, "fc0bd4e", "ViewLayer.CryptoMaterial", "", ids);
    image.parts.push_back(std::move(part));

    DecalScene scene;
    DecalMask mask;
    mask.cryptomatte_layer = layer;
    mask.cryptomatte_names = names;
    scene.masks.push_back(mask);
    Decal decal;
    decal.name = "masked";
    decal.mask = 0;
    scene.decals.push_back(decal);

    // The channel layout is the same for every input, so its mapping and G-buffer are too.
    static const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    static const GBuffer depth_only = extractGBuffer(image, mapping);
    GBuffer frame = depth_only;
    std::vector<std::string> warnings;
    inputErrorsAllowed([&] { evaluateMasks(image, mapping, scene, frame, &warnings); });
}

}  // namespace decalcomp::fuzz
