// evaluateMasks: object-id and Cryptomatte decal masks -> per-frame weight planes.
// Cryptomatte channels <name>00.r/g/b/a (or .R/.G/.B/.A, or Nuke's .red/.green/.blue/.alpha),
// <name>01..., each hold two (id, coverage) rank pairs; the ids, names and manifests are in
// decalcomp/cryptomatte.hpp.
#include "decalcomp/masks.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp {

namespace {

using Files = std::vector<ExrImage>;

// How warnings name file `index`: its label when the caller gave one, else its path.
std::string shownName(const Files& files, const std::vector<std::string>& labels, std::size_t index) {
    if (index < labels.size() && !labels[index].empty()) return labels[index];
    return files.at(index).path;
}

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

// "FILE channel NAME" of the mapped object-id pass, for messages.
std::string idChannelName(const Files& files, const ChannelMapping& mapping, const std::vector<std::string>& labels) {
    const auto mapped = mapping.attributes.find(Attribute::ObjectId);
    if (mapped == mapping.attributes.end() || mapped->second.empty()) return "none mapped";
    const ChannelRef& ref = mapped->second.front();
    return fmt::format("{} channel {}", shownName(files, labels, std::size_t(ref.file)), channelOf(files, ref).qualified);
}

// The object-id plane and its checks, only when some mask uses ids.
void prepareIdPass(const Files& files, const ChannelMapping& mapping, const DecalScene& scene, const GBuffer& frame,
                   const Imath::Box2i& window, IdPass& pass, std::vector<std::string>* warnings,
                   const std::vector<std::string>& labels) {
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
    // Filtered id passes (averaged at edges) still work, rounded, but deserve a word. The text
    // does not depend on how many pixels, so a batch reports it once for all its frames.
    const bool fractional = std::any_of(pass.plane->samples.begin(), pass.plane->samples.end(), [](float v) {
        return std::isfinite(v) && std::abs(v - std::round(v)) > 1e-3f;
    });
    if (fractional && warnings)
        warnings->push_back(fmt::format("{}: channel {}: holds non-integer object ids, which are rounded to the "
                                        "nearest integer; check that the id pass is written unfiltered (one sample "
                                        "per pixel, no antialiasing)",
                                        shownName(files, labels, std::size_t(ref.file)), channel.qualified));
}

// Returns whether any pixel holds one of the mask's `ids` (true for a pure exclude mask).
bool applyIdMask(const DecalMask& mask, const Plane& ids, std::vector<float>& weights) {
    bool any_included = mask.include_ids.empty();
    for (std::size_t i = 0; i < weights.size(); ++i) {
        const float v = ids.samples[i];
        bool pass = false;
        if (std::isfinite(v) && std::abs(v) < 4.5e9f) {
            const long long id = std::llround(v);
            const bool included = mask.include_ids.empty() ||
                                  std::binary_search(mask.include_ids.begin(), mask.include_ids.end(), id);
            any_included |= included;
            const bool excluded = std::binary_search(mask.exclude_ids.begin(), mask.exclude_ids.end(), id);
            pass = included && !excluded;
        } else {
            pass = mask.include_ids.empty();  // no id: only a pure exclude mask lets it through
        }
        if (!pass) weights[i] = 0.0f;
    }
    return any_included;
}


// ---- Cryptomatte ----

// A Cryptomatte layer resolved against the files: metadata, manifest and rank planes.
struct ResolvedLayer {
    CryptomatteLayer meta;
    std::string shown;  // how warnings name its file
    CryptomatteManifest manifest;
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

// How writers name the four channels of a rank set: the specification's r/g/b/a, upper case, and
// Nuke's red/green/blue/alpha.
constexpr std::array<std::array<const char*, 4>, 3> kRankSuffixes = {
    {{"r", "g", "b", "a"}, {"R", "G", "B", "A"}, {"red", "green", "blue", "alpha"}}};

// The four channels of rank set `prefix` (e.g. "CryptoObject00."), in the first naming that has
// all four; empty when no naming has any (the sets have ended). Throws when one is incomplete.
std::vector<ChannelRef> rankChannels(const Files& files, const CryptomatteLayer& meta, const std::string& prefix) {
    std::vector<std::string> missing_in_best;
    std::size_t best_found = 0;
    for (const auto& suffixes : kRankSuffixes) {
        std::vector<ChannelRef> refs;
        std::vector<std::string> missing;
        for (const char* suffix : suffixes) {
            if (auto ref = findChannel(files, prefix + suffix)) refs.push_back(*ref);
            else missing.push_back(prefix + suffix);
        }
        if (missing.empty()) return refs;
        if (refs.size() > best_found) {
            best_found = refs.size();
            missing_in_best = missing;
        }
    }
    if (best_found == 0) return {};
    throw inputError(fmt::format("{}: Cryptomatte layer {}: missing channel(s) {} (each rank set needs four "
                                 "channels: .r/.g/.b/.a, .R/.G/.B/.A or .red/.green/.blue/.alpha)",
                                 meta.file, meta.name, fmt::join(missing_in_best, ", ")));
}

void checkHashAndConversion(const CryptomatteLayer& meta) {
    const std::string field = "cryptomatte/" + meta.key;
    if (!meta.hash.empty() && meta.hash != "MurmurHash3_32")
        throw inputError(fmt::format("{}: {}/hash: unsupported hash '{}' (supported: MurmurHash3_32)", meta.file,
                                     field, meta.hash));
    if (!meta.conversion.empty() && meta.conversion != "uint32_to_float32")
        throw inputError(fmt::format("{}: {}/conversion: unsupported conversion '{}' (supported: uint32_to_float32)",
                                     meta.file, field, meta.conversion));
}

// Metadata, manifest (its warnings go to `warnings`) and rank planes of one layer.
ResolvedLayer resolveLayer(const Files& files, const CryptomatteLayer& meta, const Imath::Box2i& window,
                           const std::string& shown, std::vector<std::string>* warnings) {
    checkHashAndConversion(meta);
    ResolvedLayer layer;
    layer.meta = meta;
    layer.shown = shown;
    layer.manifest = cryptomatteManifest(meta, shown);
    if (warnings) warnings->insert(warnings->end(), layer.manifest.warnings.begin(), layer.manifest.warnings.end());
    for (int level = 0; level < 100; ++level) {
        const std::vector<ChannelRef> refs = rankChannels(files, meta, fmt::format("{}{:02d}.", meta.name, level));
        if (refs.empty()) break;
        // Ids are 32-bit float bit patterns: HALF would destroy them, UINT is not the convention.
        for (int c : {0, 2}) {
            const ChannelRef& ref = refs[std::size_t(c)];
            const ExrChannel& channel = channelOf(files, ref);
            if (channel.type != SampleType::Float)
                throw inputError(fmt::format("{}: channel {}: {} cannot hold Cryptomatte ids (they are 32-bit float "
                                             "hashes; write the Cryptomatte channels as FLOAT)",
                                             files[std::size_t(ref.file)].path, channel.qualified,
                                             io::sampleTypeName(channel.type)));
        }
        layer.ranks.push_back(
            readChannelsOnWindow(files, refs, window, 0.0f, false, fmt::format("Cryptomatte {}", meta.name)));
    }
    if (layer.ranks.empty())
        throw inputError(fmt::format("{}: Cryptomatte layer {} (cryptomatte/{}/name) has no channels {}00.r, {}00.g, "
                                     "... (nor .R or .red)",
                                     meta.file, meta.name, meta.key, meta.name, meta.name));
    return layer;
}

bool idOccurs(const ResolvedLayer& layer, std::uint32_t bits) {
    for (const Plane& rank : layer.ranks)
        for (std::size_t i = 0; i < rank.samples.size(); i += 2) {
            std::uint32_t id;
            std::memcpy(&id, &rank.samples[i], sizeof id);
            if (id == bits && rank.samples[i + 1] != 0.0f) return true;
        }
    return false;
}

// The ids (float bit patterns) one `names` entry selects, and whether it selects anything here.
struct Selection {
    std::vector<std::uint32_t> ids;
    bool found = false;
};

// In order: an entry that is exactly a manifest name selects that name alone, whatever characters
// it has; an entry without wildcards is a name (escapes removed), taken from the manifest or else
// hashed; an entry with wildcards selects every manifest name it matches.
Selection selectEntry(const CryptomattePattern& pattern, const ResolvedLayer& layer) {
    const auto& names = layer.manifest.names;
    const auto listed = [&](const std::string& name) -> std::optional<Selection> {
        const auto it = names.find(name);
        if (it == names.end()) return std::nullopt;
        return Selection{{cryptomatteBitsFromHash(it->second)}, true};
    };
    if (auto exact = listed(pattern.text())) return *exact;
    if (!pattern.hasWildcards()) {
        if (auto name = listed(pattern.literal())) return *name;
        // Not in the manifest (or none): the name's own hash selects it wherever a pixel holds it.
        const std::uint32_t bits = cryptomatteBitsFromHash(murmurHash3_32(pattern.literal()));
        return Selection{{bits}, idOccurs(layer, bits)};
    }
    Selection s;
    for (const auto& [name, hash] : names)
        if (pattern.matches(name)) s.ids.push_back(cryptomatteBitsFromHash(hash));
    s.found = !s.ids.empty();
    return s;
}

// "names: A, B, C" (at most 20 of them), for warnings.
std::string manifestNames(const CryptomatteManifest& manifest) {
    std::vector<std::string> names;
    for (const auto& [name, hash] : manifest.names) names.push_back(name);
    if (names.size() <= 20) return fmt::format("names: {}", fmt::join(names, ", "));
    return fmt::format("{} names, e.g. {}", names.size(), fmt::join(names.begin(), names.begin() + 20, ", "));
}

// The warning for entry k of mask m that selects nothing: where, why, and what to check.
std::string nothingSelected(const DecalScene& scene, int m, std::size_t k, const CryptomattePattern& pattern,
                            const ResolvedLayer& layer) {
    const std::string what = fmt::format("{}: {}: mask.cryptomatte.names[{}]: '{}' matches nothing in {}", layer.shown,
                                         decalsUsing(scene, m), k, pattern.text(), layer.meta.name);
    const CryptomatteManifest& manifest = layer.manifest;
    if (!manifest.names.empty()) {
        if (pattern.hasWildcards())
            return fmt::format("{} ({}); check the pattern (names are case-sensitive; \\* \\? \\[ match those "
                               "characters literally)",
                               what, manifestNames(manifest));
        return fmt::format("{} (not in the manifest, and no pixel holds its hash; {}); check the spelling, or "
                           "whether the object is in view",
                           what, manifestNames(manifest));
    }
    const char* why = manifest.source == CryptomatteManifest::Source::None ? "the layer has no manifest"
                      : manifest.readable                                   ? "its manifest lists no names"
                                                                            : "its manifest could not be read";
    if (pattern.hasWildcards())
        return fmt::format("{} ({}, so wildcards have no names to match); give exact names, which select by their "
                           "hash (\\* \\? \\[ for those characters in a name)",
                           what, why);
    return fmt::format("{} (no pixel holds its hash, and {}); check the spelling, or whether the object is in view",
                       what, why);
}

void applyCryptomatteMask(const DecalScene& scene, int m, const ResolvedLayer& layer, std::vector<float>& weights,
                          std::vector<std::string>* warnings) {
    const DecalMask& mask = scene.masks[std::size_t(m)];
    std::vector<std::uint32_t> ids;  // float bit patterns of the selected ids, sorted below
    for (std::size_t k = 0; k < mask.cryptomatte_names.size(); ++k) {
        const std::string& entry = mask.cryptomatte_names[k];
        std::optional<CryptomattePattern> pattern;
        try {
            pattern.emplace(entry);
        } catch (const Error& e) {  // scenes are checked on load; masks built in code may not be
            throw inputError(fmt::format("{}: mask.cryptomatte.names[{}]: '{}' {}", decalsUsing(scene, m), k, entry,
                                         e.what()));
        }
        const Selection selection = selectEntry(*pattern, layer);
        ids.insert(ids.end(), selection.ids.begin(), selection.ids.end());
        if (!selection.found && warnings) warnings->push_back(nothingSelected(scene, m, k, *pattern, layer));
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
                   GBuffer& frame, std::vector<std::string>* warnings, const std::vector<std::string>& file_labels) {
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
    prepareIdPass(files, mapping, scene, frame, window, id_pass, warnings, file_labels);

    std::vector<CryptomatteLayer> layers;
    std::map<std::string, ResolvedLayer> resolved;  // by layer name + file
    bool any_cryptomatte = false;
    for (const DecalMask& mask : scene.masks) any_cryptomatte |= !mask.cryptomatte_layer.empty();
    if (any_cryptomatte) layers = cryptomatteLayers(files);

    std::vector<Plane> planes;
    for (int m = 0; m < int(scene.masks.size()); ++m) {
        const DecalMask& mask = scene.masks[std::size_t(m)];
        Plane plane{1, std::vector<float>(frame.pixelCount(), 1.0f)};
        if ((!mask.include_ids.empty() || !mask.exclude_ids.empty()) &&
            !applyIdMask(mask, *id_pass.plane, plane.samples) && warnings)
            warnings->push_back(fmt::format("{}: {}: mask.ids [{}]: no pixel holds these object ids, so the decal "
                                            "changes nothing; check the ids against the object-id pass ({})",
                                            shownName(files, file_labels, 0), decalsUsing(scene, m),
                                            fmt::join(mask.include_ids, ", "), idChannelName(files, mapping, file_labels)));
        if (!mask.cryptomatte_layer.empty()) {
            const CryptomatteLayer& meta =
                findLayer(layers, mask.cryptomatte_layer, mapping, label, decalsUsing(scene, m));
            const std::string key = meta.file + "\n" + meta.key;
            auto it = resolved.find(key);
            if (it == resolved.end()) {
                const std::string shown = shownName(files, file_labels, meta.file_index);
                it = resolved.emplace(key, resolveLayer(files, meta, window, shown, warnings)).first;
            }
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

void evaluateIdMasks(const DecalScene& scene, GBuffer& frame, const std::string& label) {
    frame.mask_weights.clear();
    for (int m = 0; m < int(scene.masks.size()); ++m) {
        const DecalMask& mask = scene.masks[std::size_t(m)];
        if (!mask.cryptomatte_layer.empty())
            throw inputError(fmt::format("{}: {} masks by Cryptomatte layer {}, which needs the EXR's Cryptomatte channels "
                                         "and manifest: composite the files instead of planes",
                                         label, decalsUsing(scene, m), mask.cryptomatte_layer));
        Plane plane{1, std::vector<float>(frame.pixelCount(), 1.0f)};
        if (!mask.include_ids.empty() || !mask.exclude_ids.empty()) {
            const auto ids = frame.planes.find(Attribute::ObjectId);
            if (ids == frame.planes.end() || ids->second.components != 1)
                throw inputError(fmt::format("{}: {} masks by object id (mask.ids / mask.exclude_ids) but there is "
                                             "no single-component object_id plane",
                                             label, decalsUsing(scene, m)));
            applyIdMask(mask, ids->second, plane.samples);
        }
        frame.mask_weights.push_back(std::move(plane));
    }
}

}  // namespace decalcomp
