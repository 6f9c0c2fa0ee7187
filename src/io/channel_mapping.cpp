// mapChannels: which EXR channels hold which G-buffer attribute, by renderer profile (profiles as
// data, see decalcomp/profiles.hpp and docs/profiles.md).
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <optional>
#include <set>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/normal_check.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/profiles.hpp"

namespace decalcomp {

namespace {

using Files = std::vector<const ExrImage*>;

// qualified channel name -> channel, for the files a lookup may use.
struct ChannelIndex {
    std::map<std::string, ChannelRef> refs;
    std::vector<std::string> shadowed;  // names found again in a later file (the first one wins)
    std::vector<int> files;             // the files indexed
};

ChannelIndex indexFiles(const Files& files, const std::vector<int>& which) {
    ChannelIndex index;
    index.files = which;
    for (int f : which)
        for (int p = 0; p < int(files[f]->parts.size()); ++p)
            for (int c = 0; c < int(files[f]->parts[p].channels.size()); ++c) {
                const std::string& name = files[f]->parts[p].channels[c].qualified;
                const auto [it, inserted] = index.refs.emplace(name, ChannelRef{p, c, f});
                if (!inserted && it->second.file != f) index.shadowed.push_back(fmt::format("{} in {}", name, files[f]->path));
            }
    return index;
}

std::string joined(const std::vector<std::string>& names) { return fmt::format("{}", fmt::join(names, ", ")); }

// Glob with '*' and '?'.
bool globMatch(const std::string& pattern, const std::string& text) {
    std::size_t p = 0, t = 0, star = std::string::npos, mark = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            mark = t;
        } else if (star != std::string::npos) {
            p = star + 1;
            t = ++mark;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

constexpr const char* kLayer = "{layer}";

bool hasLayer(const std::string& pattern) { return pattern.find(kLayer) != std::string::npos; }

std::string withLayer(const std::string& pattern, const std::string& layer) {
    const auto at = pattern.find(kLayer);
    return at == std::string::npos ? pattern : pattern.substr(0, at) + layer + pattern.substr(at + 7);
}

// The layer a name gives a "{layer}" pattern, if it matches (the layer is never empty).
std::optional<std::string> layerOf(const std::string& pattern, const std::string& name) {
    const auto at = pattern.find(kLayer);
    if (at == std::string::npos) return std::nullopt;
    const std::string prefix = pattern.substr(0, at), suffix = pattern.substr(at + 7);
    if (name.size() <= prefix.size() + suffix.size()) return std::nullopt;
    if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
    if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return std::nullopt;
    return name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
}

bool spellingHasLayer(const ProfileSpelling& s) {
    return std::any_of(s.channels.begin(), s.channels.end(), hasLayer);
}

// The spelling's channels with `layer`, if every one exists.
std::optional<std::vector<ChannelRef>> resolve(const ChannelIndex& index, const ProfileSpelling& spelling,
                                               const std::string& layer, std::vector<std::string>* names = nullptr) {
    if (spellingHasLayer(spelling) && layer.empty()) return std::nullopt;
    std::vector<ChannelRef> refs;
    std::vector<std::string> resolved;
    for (const std::string& pattern : spelling.channels) {
        const std::string name = withLayer(pattern, layer);
        auto it = index.refs.find(name);
        if (it == index.refs.end()) return std::nullopt;
        refs.push_back(it->second);
        resolved.push_back(name);
    }
    if (names) *names = resolved;
    return refs;
}

struct Found {
    std::vector<ChannelRef> refs;
    std::vector<std::string> names;
    const ProfileSpelling* spelling = nullptr;
};

std::optional<Found> findAttribute(const ChannelIndex& index, const std::vector<ProfileSpelling>& spellings,
                                   const std::string& layer) {
    for (const ProfileSpelling& spelling : spellings) {
        Found found;
        if (auto refs = resolve(index, spelling, layer, &found.names)) {
            found.refs = *refs;
            found.spelling = &spelling;
            return found;
        }
    }
    return std::nullopt;
}

// Layers for which at least one of the profile's layered spellings exists completely.
std::set<std::string> profileLayers(const ChannelIndex& index, const ChannelProfile& profile) {
    std::set<std::string> layers;
    for (const auto& [attribute, spellings] : profile.attributes)
        for (const ProfileSpelling& spelling : spellings) {
            if (!spellingHasLayer(spelling)) continue;
            const std::string& pattern = *std::find_if(spelling.channels.begin(), spelling.channels.end(), hasLayer);
            for (const auto& [name, ref] : index.refs) {
                const auto layer = layerOf(pattern, name);
                if (layer && !layers.count(*layer) && resolve(index, spelling, *layer)) layers.insert(*layer);
            }
        }
    return layers;
}

bool detectRuleMatches(const Files& files, const ChannelIndex& index, const ProfileDetectRule& rule) {
    if (!rule.channel.empty()) {
        std::string glob = rule.channel;
        for (auto at = glob.find(kLayer); at != std::string::npos; at = glob.find(kLayer)) glob.replace(at, 7, "?*");
        for (const auto& [name, ref] : index.refs)
            if (globMatch(glob, name)) return true;
        return false;
    }
    for (int f : index.files)
        for (const ExrPart& part : files[f]->parts)
            for (auto it = part.header.begin(); it != part.header.end(); ++it) {
                if (!globMatch(rule.header, it.name())) continue;
                if (rule.value.empty()) return true;
                if (auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                    if (globMatch(rule.value, text->value())) return true;
            }
    return false;
}

// How well a profile describes the pooled files: its attributes found (depth and albedo weigh
// most) in its best layer, plus its detection rules.
ProfileCandidate scoreProfile(const Files& files, const ChannelIndex& index, const ChannelProfile& profile) {
    ProfileCandidate best{profile.name, -1.0, {}};
    std::set<std::string> layers = profileLayers(index, profile);
    if (layers.empty()) layers.insert("");
    for (const std::string& layer : layers) {
        ProfileCandidate c{profile.name, 0.0, {}};
        std::set<Attribute> found;
        for (const auto& [attribute, spellings] : profile.attributes)
            if (findAttribute(index, spellings, layer)) {
                c.score += attributeDetectionWeight(attribute);
                c.reasons.push_back(attributeName(attribute));
                found.insert(attribute);
            }
        c.fits = found.size() == profile.attributes.size() && found.count(Attribute::Albedo) &&
                 (found.count(Attribute::Depth) || found.count(Attribute::Position));
        if (!layer.empty() && !c.reasons.empty()) c.reasons.insert(c.reasons.begin(), fmt::format("layer '{}'", layer));
        if (c.score > best.score) best = c;
    }
    for (const ProfileDetectRule& rule : profile.detect)
        if (detectRuleMatches(files, index, rule)) {
            best.score += rule.weight;
            best.reasons.push_back(!rule.channel.empty()   ? fmt::format("channel {}", rule.channel)
                                   : rule.value.empty()    ? fmt::format("header {}", rule.header)
                                                           : fmt::format("header {} = {}", rule.header, rule.value));
        }
    return best;
}

std::string candidateText(const ProfileCandidate& c) {
    return c.reasons.empty() ? fmt::format("{} {:g}", c.name, c.score)
                             : fmt::format("{} {:g} ({})", c.name, c.score, joined(c.reasons));
}

const ChannelProfile& chooseProfile(const Files& files, const ChannelIndex& index,
                                    const std::vector<ChannelProfile>& profiles, const MappingOptions& options,
                                    ChannelMapping& mapping) {
    for (const ChannelProfile& profile : profiles) mapping.candidates.push_back(scoreProfile(files, index, profile));
    std::vector<std::string> known;
    for (const ChannelProfile& p : profiles) known.push_back(p.name);
    std::size_t chosen = 0;
    if (options.profile == "auto") {
        // A user profile that fits the input wins over the built-ins whatever their scores: it was
        // written for these files (a smaller one would otherwise lose to generic's many names).
        std::optional<std::size_t> user;
        for (std::size_t i = 0; i < profiles.size(); ++i)
            if (profiles[i].source != "built-in" && mapping.candidates[i].fits &&
                (!user || mapping.candidates[i].score > mapping.candidates[*user].score))
                user = i;
        if (user) {
            chosen = *user;
        } else {
            for (std::size_t i = 1; i < profiles.size(); ++i)  // ties go to the earlier profile
                if (mapping.candidates[i].score > mapping.candidates[chosen].score) chosen = i;
        }
        const ProfileCandidate& c = mapping.candidates[chosen];
        mapping.notes.push_back(fmt::format("profile {} (auto-detected, {}score {:g}{}{})", c.name,
                                            user ? "a user profile that finds every attribute it names, " : "",
                                            c.score, c.reasons.empty() ? "" : ": ", joined(c.reasons)));
    } else {
        const auto it = std::find(known.begin(), known.end(), options.profile);
        if (it == known.end())
            throw inputError(fmt::format("{}: unknown channel profile '{}' (known: auto, {})",
                                         files.empty() ? std::string("input") : files.front()->path, options.profile,
                                         joined(known)));
        chosen = std::size_t(it - known.begin());
        mapping.notes.push_back(fmt::format("profile {} (requested)", profiles[chosen].name));
    }
    if (profiles[chosen].source != "built-in")
        mapping.notes.push_back(fmt::format("profile {} from {}", profiles[chosen].name, profiles[chosen].source));
    std::vector<std::string> others;
    for (std::size_t i = 0; i < profiles.size(); ++i)
        if (i != chosen) others.push_back(candidateText(mapping.candidates[i]));
    if (!others.empty()) mapping.notes.push_back("other profiles: " + joined(others));
    mapping.profile = profiles[chosen].name;
    std::stable_sort(mapping.candidates.begin(), mapping.candidates.end(),
                     [](const ProfileCandidate& a, const ProfileCandidate& b) { return a.score > b.score; });
    return profiles[chosen];
}

std::string pickLayer(const ChannelIndex& index, const ChannelProfile& profile, const MappingOptions& options,
                      const std::string& file) {
    const std::set<std::string> layers = profileLayers(index, profile);
    const std::string found = layers.empty() ? "none found" : fmt::format("{}", fmt::join(layers, ", "));
    bool layered = false;
    for (const auto& [attribute, spellings] : profile.attributes)
        for (const ProfileSpelling& s : spellings) layered = layered || spellingHasLayer(s);
    if (!layered) return {};  // --layer means nothing to this profile's names
    if (!options.layer.empty()) {
        if (!layers.count(options.layer))
            throw inputError(fmt::format("{}: layer '{}' not found for profile {} (layers: {})", file, options.layer,
                                         profile.name, found));
        return options.layer;
    }
    if (layers.size() > 1)
        throw inputError(fmt::format("{}: several layers ({}) match profile {}: choose one with --layer", file, found,
                                     profile.name));
    return layers.empty() ? std::string() : *layers.begin();
}

void recordFound(ChannelMapping& mapping, Attribute attribute, const Found& found, const std::string& how,
                 const ChannelProfile* profile) {
    mapping.attributes[attribute] = found.refs;
    mapping.notes.push_back(fmt::format("{} <- {} ({})", attributeName(attribute), joined(found.names), how));
    if (attribute == Attribute::Normal && profile) {
        const std::string& space =
            found.spelling && !found.spelling->space.empty() ? found.spelling->space : profile->normal_space;
        mapping.normals.space = space == "camera" ? NormalSpace::Camera : NormalSpace::World;
        mapping.normals.packed = profile->normal_encoding == "packed";
    }
}

std::vector<ChannelRef> explicitRefs(const ChannelIndex& index, Attribute attribute, const std::vector<std::string>& names,
                                     const std::string& file) {
    const char* label = attributeName(attribute);
    if (int(names.size()) != attributeComponents(attribute))
        throw inputError(fmt::format("{}: --channel {}: expected {} channel(s), got {}", file, label,
                                     attributeComponents(attribute), names.size()));
    std::vector<ChannelRef> refs;
    for (const std::string& name : names) {
        auto it = index.refs.find(name);
        if (it == index.refs.end()) throw inputError(fmt::format("{}: --channel {}: no channel '{}'", file, label, name));
        refs.push_back(it->second);
    }
    return refs;
}

// ---- one file per pass (--pass ATTR=FILE) ----

// Component names a lone pass file may use, in preference order.
std::vector<std::vector<std::string>> bareComponentSets(int components) {
    switch (components) {
        case 1: return {{"Z"}, {"Y"}, {"V"}, {"R"}, {"X"}, {"z"}, {"y"}, {"r"}, {"x"}};
        case 2: return {{"U", "V"}, {"X", "Y"}, {"R", "G"}, {"u", "v"}, {"x", "y"}, {"s", "t"}};
        default: return {{"R", "G", "B"}, {"X", "Y", "Z"}, {"r", "g", "b"}, {"x", "y", "z"}};
    }
}

// A pass file's channels by their component names: "R,G,B" or "<layer>.R,G,B" when only one
// layer has them; a file of one channel gives it to a one-component attribute.
std::optional<Found> bareChannels(const ChannelIndex& index, Attribute attribute, const std::string& file) {
    const int n = attributeComponents(attribute);
    if (n == 1 && index.refs.size() == 1) {
        Found found;
        found.refs = {index.refs.begin()->second};
        found.names = {index.refs.begin()->first};
        return found;
    }
    std::set<std::string> prefixes = {""};
    for (const auto& [name, ref] : index.refs) {
        const auto dot = name.rfind('.');
        if (dot != std::string::npos && dot > 0) prefixes.insert(name.substr(0, dot + 1));
    }
    for (const auto& set : bareComponentSets(n)) {
        std::vector<Found> matches;
        for (const std::string& prefix : prefixes) {
            Found found;
            for (const std::string& component : set) {
                auto it = index.refs.find(prefix + component);
                if (it == index.refs.end()) break;
                found.refs.push_back(it->second);
                found.names.push_back(prefix + component);
            }
            if (int(found.refs.size()) == n) {
                if (prefix.empty()) return found;  // unprefixed names win
                matches.push_back(found);
            }
        }
        if (matches.size() == 1) return matches.front();
        if (matches.size() > 1) {
            std::vector<std::string> options;
            for (const Found& m : matches) options.push_back(joined(m.names));
            throw inputError(fmt::format("{}: {}: several channel sets could be it ({}): choose with --channel {}=...",
                                         file, attributeName(attribute), fmt::join(options, "; "), attributeName(attribute)));
        }
    }
    return std::nullopt;
}

bool isAlphaName(const std::string& name) {
    const std::string component = name.substr(name.rfind('.') + 1);
    return component == "A" || component == "a" || component == "alpha";
}

// A pass file with more (non-alpha) channels than the attribute takes is probably another pass:
// an RGB file given as depth yields "depth = R" and composites on nonsense surfaces.
std::optional<std::string> unusedChannelsWarning(const ChannelIndex& index, Attribute attribute, const Found& found,
                                                 const std::string& path) {
    std::vector<std::string> unused;
    for (const auto& [name, ref] : index.refs)
        if (!isAlphaName(name) && std::find(found.names.begin(), found.names.end(), name) == found.names.end())
            unused.push_back(name);
    if (unused.empty()) return std::nullopt;
    const std::string attribute_name = attributeName(attribute);
    return fmt::format("{}: --pass {}: took {} for {} but the file also has {}; if it is another pass, check the "
                       "--pass attribute, or name the channels with --channel {}=...",
                       path, attribute_name, joined(found.names), attribute_name, joined(unused), attribute_name);
}

void mapPassFile(const Files& files, int file, Attribute attribute, const ChannelProfile& chosen,
                 const std::vector<ChannelProfile>& profiles, const MappingOptions& options, ChannelMapping& mapping) {
    const ChannelIndex index = indexFiles(files, {file});
    const std::string& path = files[file]->path;
    if (auto it = options.explicit_channels.find(attribute); it != options.explicit_channels.end()) {
        Found found;
        found.refs = explicitRefs(index, attribute, it->second, path);
        found.names = it->second;
        recordFound(mapping, attribute, found, "explicit, --pass " + path, nullptr);
        return;
    }
    std::vector<const ChannelProfile*> order = {&chosen};
    for (const ChannelProfile& p : profiles)
        if (&p != &chosen) order.push_back(&p);
    for (const ChannelProfile* profile : order) {
        auto spellings = profile->attributes.find(attribute);
        if (spellings == profile->attributes.end()) continue;
        std::set<std::string> layers = profileLayers(index, *profile);
        if (!options.layer.empty() && layers.count(options.layer)) layers = {options.layer};
        if (layers.size() > 1) continue;  // ambiguous here; the bare rule or --channel decides
        const std::string layer = layers.empty() ? std::string() : *layers.begin();
        if (auto found = findAttribute(index, spellings->second, layer)) {
            recordFound(mapping, attribute, *found, fmt::format("--pass {}, profile {}", path, profile->name), profile);
            return;
        }
    }
    if (auto found = bareChannels(index, attribute, path)) {
        recordFound(mapping, attribute, *found, fmt::format("--pass {}, by component names", path), &chosen);
        if (auto warning = unusedChannelsWarning(index, attribute, *found, path)) mapping.warnings.push_back(*warning);
        return;
    }
    std::vector<std::string> names;
    for (const auto& [name, ref] : index.refs) names.push_back(name);
    throw inputError(fmt::format("{}: --pass {}: no {} channels found (channels: {}); name them with --channel {}=...",
                                 path, attributeName(attribute), attributeName(attribute),
                                 names.empty() ? std::string("none") : joined(names), attributeName(attribute)));
}

// A depth pass uses the profile's convention; without one the position pass stands in for it.
void chooseDepthConvention(const MappingOptions& options, const ChannelProfile& profile, ChannelMapping& mapping) {
    mapping.reversed_z = options.reversed_z;
    std::string why;
    if (options.depth_convention) {
        mapping.depth_convention = *options.depth_convention;
        mapping.depth_convention_explicit = true;
        why = "explicit";
    } else if (profile.depth_convention == DepthConvention::Position && mapping.attributes.count(Attribute::Position)) {
        mapping.depth_convention = DepthConvention::Position;
        why = fmt::format("profile {}'s default", profile.name);
    } else if (mapping.attributes.count(Attribute::Depth)) {
        mapping.depth_convention =
            profile.depth_convention == DepthConvention::Position ? DepthConvention::Planar : profile.depth_convention;
        why = fmt::format("profile {}'s default for a depth pass", profile.name);
    } else if (mapping.attributes.count(Attribute::Position)) {
        mapping.depth_convention = DepthConvention::Position;
        why = "no depth pass, using the position pass";
    } else {
        mapping.depth_convention = DepthConvention::Planar;
        why = "default; no depth or position pass";
    }
    mapping.notes.push_back(fmt::format("depth convention: {}{} ({})", depthConventionName(mapping.depth_convention),
                                        mapping.reversed_z ? ", reversed-Z" : "", why));
}

ChannelMapping mapFiles(const Files& files, const MappingOptions& options, const FileRoles& roles) {
    if (files.empty()) throw inputError("no input files");
    const int positional = roles.positional <= 0 ? int(files.size()) : std::min(roles.positional, int(files.size()));
    for (const auto& [attribute, file] : roles.pass_files)
        if (file < 0 || file >= int(files.size()))
            throw inputError(fmt::format("--pass {}: file index {} out of range", attributeName(attribute), file));
    std::vector<int> pooled;
    for (int f = 0; f < positional; ++f) pooled.push_back(f);
    const ChannelIndex index = indexFiles(files, pooled);
    const std::string& file = files.front()->path;
    const std::vector<ChannelProfile> profiles = profileSet(options.profile_files);

    ChannelMapping mapping;
    const ChannelProfile& profile = chooseProfile(files, index, profiles, options, mapping);
    for (const std::string& s : index.shadowed) mapping.notes.push_back("ignored (an earlier file has it): " + s);

    // Layers only matter when some pooled attribute is layered.
    mapping.layer = pickLayer(index, profile, options, file);
    if (!mapping.layer.empty()) mapping.notes.push_back(fmt::format("{} layer '{}'", profile.name, mapping.layer));
    else if (!options.layer.empty())
        mapping.notes.push_back(fmt::format("--layer {} ignored: profile {} has no layers", options.layer, profile.name));
    for (const auto& [attribute, spellings] : profile.attributes) {
        if (roles.pass_files.count(attribute)) continue;
        if (auto found = findAttribute(index, spellings, mapping.layer))
            recordFound(mapping, attribute, *found, profile.name, &profile);
    }
    if (mapping.attributes.empty() && profile.source == "built-in" && options.profile == "auto")
        mapping.notes.push_back(fmt::format("{}: no profile matched any channel", file));

    for (const auto& [attribute, names] : options.explicit_channels) {
        if (roles.pass_files.count(attribute)) continue;  // resolved inside the pass file
        Found found;
        found.refs = explicitRefs(index, attribute, names, file);
        found.names = names;
        recordFound(mapping, attribute, found, "explicit", nullptr);
    }
    for (const auto& [attribute, pass_file] : roles.pass_files)
        mapPassFile(files, pass_file, attribute, profile, profiles, options, mapping);
    if (options.normal_space) mapping.normals.space = *options.normal_space;
    if (options.normal_packed) mapping.normals.packed = *options.normal_packed;
    mapping.normal_space_explicit = options.normal_space.has_value();
    mapping.normal_encoding_explicit = options.normal_packed.has_value();
    if (mapping.attributes.count(Attribute::Normal) &&
        (mapping.normals.space != NormalSpace::World || mapping.normals.packed))
        mapping.notes.push_back(fmt::format("normal: {} space, {}", normalSpaceName(mapping.normals.space),
                                            mapping.normals.packed ? "packed" : "signed"));
    chooseDepthConvention(options, profile, mapping);
    return mapping;
}

}  // namespace

ChannelMapping mapChannels(const ExrImage& image, const MappingOptions& options) {
    return mapFiles({&image}, options, FileRoles{});
}

ChannelMapping mapChannels(const std::vector<ExrImage>& files, const MappingOptions& options, const FileRoles& roles) {
    Files view;
    for (const ExrImage& f : files) view.push_back(&f);
    return mapFiles(view, options, roles);
}

}  // namespace decalcomp
