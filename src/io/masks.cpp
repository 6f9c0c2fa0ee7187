// evaluateMasks: object-id and Cryptomatte decal masks -> per-frame weight planes.
// Cryptomatte as specified by Psyop (v1.2): metadata cryptomatte/<key>/{name,hash,conversion,
// manifest,manif_file}; channels <name>00.r/g/b/a, <name>01..., each holding two (id, coverage)
// rank pairs; ids are MurmurHash3_32 of the names, stored as floats ("uint32_to_float32").
#include "decalcomp/masks.hpp"

#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/json_fields.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp {

// ---- MurmurHash3 (x86, 32-bit), written from the published description ----

namespace {

constexpr std::uint32_t rotateLeft(std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); }

// The per-block scramble, applied to every full 4-byte block and to the zero-padded tail.
constexpr std::uint32_t scramble(std::uint32_t k) {
    k *= 0xcc9e2d51u;
    k = rotateLeft(k, 15);
    k *= 0x1b873593u;
    return k;
}

// Final avalanche.
constexpr std::uint32_t finalMix(std::uint32_t h) {
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

}  // namespace

std::uint32_t murmurHash3_32(std::string_view data, std::uint32_t seed) {
    const auto byte = [&](std::size_t i) { return std::uint32_t(static_cast<unsigned char>(data[i])); };
    const std::size_t length = data.size();
    const std::size_t full = length / 4 * 4;
    std::uint32_t h = seed;
    for (std::size_t i = 0; i < full; i += 4) {
        // blocks are read little-endian whatever the host
        const std::uint32_t k = byte(i) | byte(i + 1) << 8 | byte(i + 2) << 16 | byte(i + 3) << 24;
        h ^= scramble(k);
        h = rotateLeft(h, 13);
        h = h * 5u + 0xe6546b64u;
    }
    std::uint32_t tail = 0;
    for (std::size_t i = length; i > full; --i) tail = tail << 8 | byte(i - 1);
    if (length > full) h ^= scramble(tail);
    h ^= std::uint32_t(length);  // the length modulo 2^32, as the algorithm defines it
    return finalMix(h);
}

std::uint32_t cryptomatteBitsFromHash(std::uint32_t hash) {
    const std::uint32_t exponent = std::clamp<std::uint32_t>((hash >> 23) & 0xffu, 1u, 254u);
    return (hash & 0x807fffffu) | exponent << 23;
}

float cryptomatteFloatFromHash(std::uint32_t hash) {
    const std::uint32_t bits = cryptomatteBitsFromHash(hash);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// ---- Cryptomatte metadata and manifests ----

namespace fs = std::filesystem;
using json = nlohmann::json;

std::vector<CryptomatteLayer> cryptomatteLayers(const std::vector<ExrImage>& files) {
    std::vector<CryptomatteLayer> layers;
    for (const ExrImage& image : files) {
        std::map<std::string, CryptomatteLayer> by_key;  // one file's layers, by key
        for (const ExrPart& part : image.parts)
            for (auto it = part.header.begin(); it != part.header.end(); ++it) {
                const std::string name = it.name();
                if (!name.starts_with("cryptomatte/")) continue;
                const auto slash = name.find('/', 12);
                if (slash == std::string::npos) continue;
                const auto* value = dynamic_cast<const Imf::StringAttribute*>(&it.attribute());
                if (!value) continue;
                const std::string key = name.substr(12, slash - 12), field = name.substr(slash + 1);
                CryptomatteLayer& layer = by_key[key];
                layer.file = image.path;
                layer.key = key;
                if (field == "name") layer.name = value->value();
                else if (field == "hash") layer.hash = value->value();
                else if (field == "conversion") layer.conversion = value->value();
                else if (field == "manifest") layer.manifest = value->value();
                else if (field == "manif_file") layer.manif_file = value->value();
            }
        for (auto& [key, layer] : by_key)
            if (!layer.name.empty()) layers.push_back(std::move(layer));
    }
    return layers;
}

namespace {

std::optional<std::uint32_t> parseHex(const std::string& s) {
    if (s.empty() || s.size() > 8) return std::nullopt;
    std::uint32_t v = 0;
    for (char c : s) {
        int d;
        if (c >= '0' && c <= '9') d = c - '0';
        else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
        else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
        else return std::nullopt;
        v = v << 4 | std::uint32_t(d);
    }
    return v;
}

}  // namespace

std::map<std::string, std::uint32_t> cryptomatteManifest(const CryptomatteLayer& layer) {
    std::map<std::string, std::uint32_t> manifest;
    std::string text, where;
    const std::string field = "cryptomatte/" + layer.key + "/manifest";
    if (!layer.manifest.empty()) {
        text = layer.manifest;
        where = fmt::format("{}: {}", layer.file, field);
    } else if (!layer.manif_file.empty()) {
        fs::path sidecar(layer.manif_file);
        if (sidecar.is_relative()) sidecar = fs::path(layer.file).parent_path() / sidecar;
        std::ifstream in(sidecar, std::ios::binary);
        std::stringstream buffer;
        buffer << in.rdbuf();
        if (!in)
            throw inputError(fmt::format("{}: cryptomatte/{}/manif_file: cannot read the manifest '{}'", layer.file,
                                         layer.key, sidecar.string()));
        text = buffer.str();
        where = fmt::format("{}: cryptomatte/{}/manif_file: {}", layer.file, layer.key, sidecar.string());
    } else {
        return manifest;
    }
    const json parsed = parseJsonText(text, where);
    const JsonField root(parsed, where);
    root.requireObject("a JSON object mapping names to hexadecimal hashes");
    for (const auto& [name, value] : root.members()) {
        const auto hash = value.value().is_string() ? parseHex(value.value().get<std::string>()) : std::nullopt;
        if (!hash) value.fail(fmt::format("expected a hash of 8 hexadecimal digits, got {}", value.value().dump()));
        manifest[name] = *hash;
    }
    return manifest;
}

// ---- evaluation ----

namespace {

using Files = std::vector<ExrImage>;

// "decal 'a'", "decals 'a', 'b' and 3 more": who uses a mask, for messages.
std::string decalsUsing(const DecalScene& scene, int mask) {
    std::vector<std::string> names;
    for (const Decal& d : scene.decals)
        if (d.mask == mask) names.push_back("'" + d.name + "'");
    if (names.empty()) return fmt::format("mask {}", mask);
    if (names.size() == 1) return "decal " + names.front();
    const std::size_t shown = std::min<std::size_t>(names.size(), 3);
    std::string text = fmt::format("decals {}", fmt::join(names.begin(), names.begin() + std::ptrdiff_t(shown), ", "));
    if (names.size() > shown) text += fmt::format(" and {} more", names.size() - shown);
    return text;
}

const ExrChannel& channelOf(const Files& files, const ChannelRef& ref) {
    return files.at(std::size_t(ref.file)).parts.at(std::size_t(ref.part)).channels.at(std::size_t(ref.channel));
}

// The largest integer n such that every integer in [-n, n] survives the channel type -> float.
double exactIntegerLimit(SampleType type) {
    switch (type) {
        case SampleType::Half: return 2048.0;
        case SampleType::Float:
        case SampleType::Uint: return 16777216.0;  // UINT samples become float planes
    }
    return 0.0;
}

struct IdPass {
    const Plane* plane = nullptr;
    Plane storage;
};

// The object-id plane and its checks, only when some mask uses ids.
void prepareIdPass(const Files& files, const ChannelMapping& mapping, const DecalScene& scene, const GBuffer& frame,
                   const Imath::Box2i& window, IdPass& pass, std::vector<std::string>* warnings) {
    const std::string& label = files.front().path;
    int first_user = -1;
    for (int m = 0; m < int(scene.masks.size()); ++m)
        if (!scene.masks[m].include_ids.empty() || !scene.masks[m].exclude_ids.empty()) {
            first_user = m;
            break;
        }
    if (first_user < 0) return;
    const auto mapped = mapping.attributes.find(Attribute::ObjectId);
    if (mapped == mapping.attributes.end() || mapped->second.size() != 1)
        throw inputError(fmt::format("{}: {} masks by object id (mask.ids / mask.exclude_ids) but the file has no "
                                     "object-id pass (profile {}; Blender: <ViewLayer>.IndexOB.X); map one with "
                                     "--channel object_id=CHANNEL",
                                     label, decalsUsing(scene, first_user), mapping.profile));
    const ChannelRef ref = mapped->second.front();
    const ExrChannel& channel = channelOf(files, ref);
    const std::string& file = files.at(std::size_t(ref.file)).path;

    // Every id a decal asks for must be representable by the channel's sample type.
    const double limit = exactIntegerLimit(channel.type);
    for (int m = 0; m < int(scene.masks.size()); ++m)
        for (const std::vector<int>* list : {&scene.masks[m].include_ids, &scene.masks[m].exclude_ids})
            for (int id : *list) {
                if (channel.type == SampleType::Uint && id < 0)
                    throw inputError(fmt::format("{}: channel {}: UINT cannot hold the negative id {} that {} lists",
                                                 file, channel.qualified, id, decalsUsing(scene, m)));
                if (std::abs(double(id)) > limit)
                    throw inputError(fmt::format("{}: channel {}: {} holds whole numbers exactly only up to {}, so it "
                                                 "cannot hold the id {} that {} lists (write the id pass as {})",
                                                 file, channel.qualified, io::sampleTypeName(channel.type), limit, id,
                                                 decalsUsing(scene, m),
                                                 channel.type == SampleType::Half ? "FLOAT" : "FLOAT with ids < 2^24"));
            }

    if (auto it = frame.planes.find(Attribute::ObjectId); it != frame.planes.end() && it->second.components == 1) {
        pass.plane = &it->second;
    } else {
        pass.storage = readChannelsOnWindow(files, {ref}, window, 0.0f, true, attributeName(Attribute::ObjectId));
        pass.plane = &pass.storage;
    }
    // Filtered id passes (averaged at edges) still work, rounded, but deserve a word.
    std::size_t fractional = 0;
    for (float v : pass.plane->samples)
        if (std::isfinite(v) && std::abs(v - std::round(v)) > 1e-3f) ++fractional;
    if (fractional > 0 && warnings)
        warnings->push_back(fmt::format("{}: channel {}: {} pixels hold non-integer object ids (a filtered id "
                                        "pass?); they are rounded to the nearest integer",
                                        file, channel.qualified, fractional));
}

void applyIdMask(const DecalMask& mask, const Plane& ids, std::vector<float>& weights) {
    for (std::size_t i = 0; i < weights.size(); ++i) {
        const float v = ids.samples[i];
        bool pass = false;
        if (std::isfinite(v) && std::abs(v) < 4.5e9f) {
            const long long id = std::llround(v);
            const bool included = mask.include_ids.empty() ||
                                  std::binary_search(mask.include_ids.begin(), mask.include_ids.end(), id);
            const bool excluded = std::binary_search(mask.exclude_ids.begin(), mask.exclude_ids.end(), id);
            pass = included && !excluded;
        } else {
            pass = mask.include_ids.empty();  // no id: only a pure exclude mask lets it through
        }
        if (!pass) weights[i] = 0.0f;
    }
}

// A Cryptomatte layer resolved against the files: metadata, manifest and rank planes.
struct ResolvedLayer {
    CryptomatteLayer meta;
    std::map<std::string, std::uint32_t> manifest;
    std::vector<Plane> ranks;  // per channel set NN: 4 components (id, coverage, id, coverage)
};

std::string layerList(const std::vector<CryptomatteLayer>& layers) {
    if (layers.empty()) return "the input has no Cryptomatte metadata (cryptomatte/<key>/name)";
    std::vector<std::string> names;
    for (const auto& l : layers) names.push_back(l.name);
    return fmt::format("layers present: {}", fmt::join(names, ", "));
}

// Exact name first; else a name ending in "." + requested (Blender prefixes the view layer), the
// mapped view layer winning when several view layers have one.
const CryptomatteLayer& findLayer(const std::vector<CryptomatteLayer>& layers, const std::string& requested,
                                  const ChannelMapping& mapping, const std::string& label, const std::string& users) {
    std::vector<const CryptomatteLayer*> matches;
    for (const auto& l : layers)
        if (l.name == requested) matches.push_back(&l);
    if (matches.empty())
        for (const auto& l : layers)
            if (l.name.size() > requested.size() + 1 && l.name.ends_with("." + requested)) matches.push_back(&l);
    if (matches.size() > 1 && !mapping.layer.empty()) {
        std::vector<const CryptomatteLayer*> same_view;
        for (const auto* l : matches)
            if (l->name == mapping.layer + "." + requested) same_view.push_back(l);
        if (!same_view.empty()) matches = same_view;
    }
    // The same layer described by several files (one per pass file) is one layer.
    if (matches.size() > 1 && std::all_of(matches.begin(), matches.end(),
                                          [&](const auto* l) { return l->name == matches.front()->name; }))
        matches.resize(1);
    if (matches.empty())
        throw inputError(fmt::format("{}: {}: unknown Cryptomatte layer '{}' ({})", label, users, requested,
                                     layerList(layers)));
    if (matches.size() > 1) {
        std::vector<std::string> names;
        for (const auto* l : matches) names.push_back(l->name);
        throw inputError(fmt::format("{}: {}: Cryptomatte layer '{}' is ambiguous ({}); give the full name or "
                                     "choose the view layer with --layer",
                                     label, users, requested, fmt::join(names, ", ")));
    }
    return *matches.front();
}

// The channel `wanted` anywhere in the files: by mapping name, by its name in its part, or as
// part name + "." + channel name (multi-part files that split the layer prefix off).
std::optional<ChannelRef> findChannel(const Files& files, const std::string& wanted) {
    for (int f = 0; f < int(files.size()); ++f)
        for (int p = 0; p < int(files[f].parts.size()); ++p) {
            const ExrPart& part = files[f].parts[p];
            const std::string part_name = part.header.hasName() ? part.header.name() : std::string();
            for (int c = 0; c < int(part.channels.size()); ++c) {
                const ExrChannel& ch = part.channels[c];
                if (ch.qualified == wanted || ch.name == wanted ||
                    (!part_name.empty() && part_name + "." + ch.name == wanted))
                    return ChannelRef{p, c, f};
            }
        }
    return std::nullopt;
}

ResolvedLayer resolveLayer(const Files& files, const CryptomatteLayer& meta, const Imath::Box2i& window) {
    const std::string field = "cryptomatte/" + meta.key;
    if (!meta.hash.empty() && meta.hash != "MurmurHash3_32")
        throw inputError(fmt::format("{}: {}/hash: unsupported hash '{}' (supported: MurmurHash3_32)", meta.file,
                                     field, meta.hash));
    if (!meta.conversion.empty() && meta.conversion != "uint32_to_float32")
        throw inputError(fmt::format("{}: {}/conversion: unsupported conversion '{}' (supported: uint32_to_float32)",
                                     meta.file, field, meta.conversion));
    ResolvedLayer layer;
    layer.meta = meta;
    layer.manifest = cryptomatteManifest(meta);
    for (int level = 0; level < 100; ++level) {
        const std::string prefix = fmt::format("{}{:02d}.", meta.name, level);
        std::vector<ChannelRef> refs;
        std::vector<std::string> missing;
        for (const char* suffixes : {"rgba", "RGBA"}) {
            refs.clear();
            missing.clear();
            for (int c = 0; c < 4; ++c) {
                const std::string name = prefix + suffixes[c];
                if (auto ref = findChannel(files, name)) refs.push_back(*ref);
                else missing.push_back(name);
            }
            if (missing.empty() || missing.size() < 4) break;
        }
        if (missing.size() == 4) break;  // no more rank channel sets
        if (!missing.empty())
            throw inputError(fmt::format("{}: Cryptomatte layer {}: missing channel(s) {}", meta.file, meta.name,
                                         fmt::join(missing, ", ")));
        // Ids are 32-bit float bit patterns: HALF would destroy them, UINT is not the convention.
        for (int c : {0, 2}) {
            const ExrChannel& channel = channelOf(files, refs[std::size_t(c)]);
            if (channel.type != SampleType::Float)
                throw inputError(fmt::format("{}: channel {}: {} cannot hold Cryptomatte ids (they are 32-bit float "
                                             "hashes; write the Cryptomatte channels as FLOAT)",
                                             files[std::size_t(refs[std::size_t(c)].file)].path, channel.qualified,
                                             io::sampleTypeName(channel.type)));
        }
        layer.ranks.push_back(
            readChannelsOnWindow(files, refs, window, 0.0f, false, fmt::format("Cryptomatte {}", meta.name)));
    }
    if (layer.ranks.empty())
        throw inputError(fmt::format("{}: Cryptomatte layer {} ({}/name) has no channels {}00.r, {}00.g, ...",
                                     meta.file, meta.name, field, meta.name, meta.name));
    return layer;
}

bool hasWildcard(const std::string& pattern) { return pattern.find_first_of("*?[") != std::string::npos; }

bool idOccurs(const ResolvedLayer& layer, std::uint32_t bits) {
    for (const Plane& rank : layer.ranks)
        for (std::size_t i = 0; i < rank.samples.size(); i += 2) {
            std::uint32_t id;
            std::memcpy(&id, &rank.samples[i], sizeof id);
            if (id == bits && rank.samples[i + 1] != 0.0f) return true;
        }
    return false;
}

void applyCryptomatteMask(const DecalScene& scene, int m, const ResolvedLayer& layer, std::vector<float>& weights,
                          std::vector<std::string>* warnings) {
    const DecalMask& mask = scene.masks[std::size_t(m)];
    std::vector<std::uint32_t> ids;  // float bit patterns of the selected ids, sorted below
    for (std::size_t k = 0; k < mask.cryptomatte_names.size(); ++k) {
        const std::string& pattern = mask.cryptomatte_names[k];
        bool matched = false;
        for (const auto& [name, hash] : layer.manifest)
            if (name == pattern || ::fnmatch(pattern.c_str(), name.c_str(), 0) == 0) {
                ids.push_back(cryptomatteBitsFromHash(hash));
                matched = true;
            }
        if (!matched && !hasWildcard(pattern)) {
            // Not in the manifest (or none): the name's own hash still selects it if it is there.
            const std::uint32_t bits = cryptomatteBitsFromHash(murmurHash3_32(pattern));
            ids.push_back(bits);
            matched = idOccurs(layer, bits);
        }
        if (!matched && warnings) {
            std::vector<std::string> names;
            for (const auto& [name, hash] : layer.manifest) names.push_back(name);
            std::string known = layer.manifest.empty() ? std::string("the layer has no manifest")
                                                       : fmt::format("names: {}", fmt::join(names, ", "));
            if (names.size() > 20) known = fmt::format("{} names, e.g. {}", names.size(),
                                                       fmt::join(names.begin(), names.begin() + 20, ", "));
            warnings->push_back(fmt::format("{}: mask.cryptomatte.names[{}]: '{}' matches nothing in {} ({})",
                                            decalsUsing(scene, m), k, pattern, layer.meta.name, known));
        }
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (std::size_t i = 0; i < weights.size(); ++i) {
        double coverage = 0.0;
        for (const Plane& rank : layer.ranks)
            for (int pair = 0; pair < 2; ++pair) {
                std::uint32_t id;
                std::memcpy(&id, &rank.samples[i * 4 + std::size_t(pair) * 2], sizeof id);
                const float c = rank.samples[i * 4 + std::size_t(pair) * 2 + 1];
                if (std::isfinite(c) && std::binary_search(ids.begin(), ids.end(), id)) coverage += c;
            }
        weights[i] *= float(std::clamp(coverage, 0.0, 1.0));
    }
}

}  // namespace

void evaluateMasks(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const DecalScene& scene,
                   GBuffer& frame, std::vector<std::string>* warnings) {
    frame.mask_weights.clear();
    if (scene.masks.empty()) return;
    if (files.empty()) throw inputError("decal masks: no input files");
    const std::string& label = files.front().path;
    const Imath::Box2i window = frameWindow(files, mapping).data;
    if (window.max.x - window.min.x + 1 != frame.width || window.max.y - window.min.y + 1 != frame.height)
        throw inputError(fmt::format("{}: decal masks: the G-buffer is {}x{} but the mapping's window is {}x{}", label,
                                     frame.width, frame.height, window.max.x - window.min.x + 1,
                                     window.max.y - window.min.y + 1));

    IdPass id_pass;
    prepareIdPass(files, mapping, scene, frame, window, id_pass, warnings);

    std::vector<CryptomatteLayer> layers;
    std::map<std::string, ResolvedLayer> resolved;  // by layer name + file
    bool any_cryptomatte = false;
    for (const DecalMask& mask : scene.masks) any_cryptomatte |= !mask.cryptomatte_layer.empty();
    if (any_cryptomatte) layers = cryptomatteLayers(files);

    std::vector<Plane> planes;
    for (int m = 0; m < int(scene.masks.size()); ++m) {
        const DecalMask& mask = scene.masks[std::size_t(m)];
        Plane plane{1, std::vector<float>(frame.pixelCount(), 1.0f)};
        if (!mask.include_ids.empty() || !mask.exclude_ids.empty()) applyIdMask(mask, *id_pass.plane, plane.samples);
        if (!mask.cryptomatte_layer.empty()) {
            const CryptomatteLayer& meta =
                findLayer(layers, mask.cryptomatte_layer, mapping, label, decalsUsing(scene, m));
            const std::string key = meta.file + "\n" + meta.key;
            auto it = resolved.find(key);
            if (it == resolved.end()) it = resolved.emplace(key, resolveLayer(files, meta, window)).first;
            applyCryptomatteMask(scene, m, it->second, plane.samples, warnings);
        }
        planes.push_back(std::move(plane));
    }
    frame.mask_weights = std::move(planes);
}

void evaluateMasks(const ExrImage& image, const ChannelMapping& mapping, const DecalScene& scene, GBuffer& frame,
                   std::vector<std::string>* warnings) {
    evaluateMasks(std::vector<ExrImage>{image}, mapping, scene, frame, warnings);
}

}  // namespace decalcomp
