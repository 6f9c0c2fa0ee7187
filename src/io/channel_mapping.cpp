// mapChannels: which EXR channels hold which G-buffer attribute, by renderer profile.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <set>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_io.hpp"

namespace decalcomp {

namespace {

using ChannelIndex = std::map<std::string, ChannelRef>;  // qualified name -> channel

ChannelIndex indexChannels(const ExrImage& image) {
    ChannelIndex index;
    for (int p = 0; p < int(image.parts.size()); ++p)
        for (int c = 0; c < int(image.parts[p].channels.size()); ++c)
            index.emplace(image.parts[p].channels[c].qualified, ChannelRef{p, c});  // first one wins
    return index;
}

// One way an attribute can be spelled: its channel names in component order.
using Spelling = std::vector<std::string>;

// The first spelling whose channels all exist, resolved to refs.
std::optional<std::pair<Spelling, std::vector<ChannelRef>>> firstPresent(const ChannelIndex& index,
                                                                          const std::vector<Spelling>& spellings) {
    for (const Spelling& spelling : spellings) {
        std::vector<ChannelRef> refs;
        for (const std::string& name : spelling) {
            auto it = index.find(name);
            if (it == index.end()) break;
            refs.push_back(it->second);
        }
        if (refs.size() == spelling.size()) return std::make_pair(spelling, refs);
    }
    return std::nullopt;
}

std::string joined(const std::vector<std::string>& names) { return fmt::format("{}", fmt::join(names, ", ")); }

// ---- Blender: "<ViewLayer>.<Pass>.<channel>", pass names as Cycles writes them ----

struct BlenderPass {
    Attribute attribute;
    std::vector<std::string> passes;        // older and newer Blender spellings
    std::vector<Spelling> channel_sets;     // channel suffixes in component order
};

const std::vector<BlenderPass>& blenderPasses() {
    static const std::vector<BlenderPass> table = {
        {Attribute::Depth, {"Depth"}, {{"Z"}}},
        {Attribute::Albedo, {"DiffCol", "Diffuse Color"}, {{"R", "G", "B"}}},
        {Attribute::Normal, {"Normal"}, {{"X", "Y", "Z"}}},
        {Attribute::Position, {"Position"}, {{"X", "Y", "Z"}}},
        {Attribute::ObjectId, {"IndexOB", "Object Index"}, {{"X"}}},
        {Attribute::UV, {"UV"}, {{"U", "V"}, {"X", "Y"}}},
        // Not built-in passes: shader AOVs, which Blender writes as value (X) or colour (R) passes.
        {Attribute::Roughness, {"Roughness", "roughness"}, {{"X"}, {"V"}, {"R"}}},
        {Attribute::Metallic, {"Metallic", "metallic"}, {{"X"}, {"V"}, {"R"}}},
    };
    return table;
}

struct BlenderName {
    std::string layer, pass, channel;
};

// The layer is everything before the last two dots, so layer names may contain dots.
std::optional<BlenderName> splitBlenderName(const std::string& name) {
    const auto last = name.rfind('.');
    if (last == std::string::npos || last == 0) return std::nullopt;
    const auto middle = name.rfind('.', last - 1);
    if (middle == std::string::npos || middle == 0) return std::nullopt;
    return BlenderName{name.substr(0, middle), name.substr(middle + 1, last - middle - 1), name.substr(last + 1)};
}

const BlenderPass* blenderPassFor(const BlenderName& name) {
    for (const BlenderPass& pass : blenderPasses())
        for (const std::string& spelling : pass.passes)
            if (spelling == name.pass)
                for (const Spelling& set : pass.channel_sets)
                    for (const std::string& channel : set)
                        if (channel == name.channel) return &pass;
    return nullptr;
}

// View layers holding at least one pass we know.
std::set<std::string> blenderLayers(const ChannelIndex& index) {
    std::set<std::string> layers;
    for (const auto& [name, ref] : index)
        if (auto parts = splitBlenderName(name); parts && blenderPassFor(*parts)) layers.insert(parts->layer);
    return layers;
}

bool looksLikeBlender(const ChannelIndex& index) {
    for (const auto& [name, ref] : index) {
        auto parts = splitBlenderName(name);
        const BlenderPass* pass = parts ? blenderPassFor(*parts) : nullptr;
        if (pass && (pass->attribute == Attribute::Depth || pass->attribute == Attribute::Albedo)) return true;
    }
    return false;
}

std::string pickBlenderLayer(const ChannelIndex& index, const MappingOptions& options, const std::string& file) {
    const std::set<std::string> layers = blenderLayers(index);
    const std::string found = layers.empty() ? "none found" : fmt::format("{}", fmt::join(layers, ", "));
    if (!options.layer.empty()) {
        if (!layers.count(options.layer))
            throw inputError(fmt::format("{}: view layer '{}' not found (layers: {})", file, options.layer, found));
        return options.layer;
    }
    if (layers.size() > 1)
        throw inputError(fmt::format("{}: several view layers ({}): choose one with --layer", file, found));
    return layers.empty() ? std::string() : *layers.begin();
}

std::vector<Spelling> blenderSpellings(const BlenderPass& pass, const std::string& layer) {
    std::vector<Spelling> spellings;
    for (const std::string& pass_name : pass.passes)
        for (const Spelling& set : pass.channel_sets) {
            Spelling names;
            for (const std::string& channel : set) names.push_back(layer + "." + pass_name + "." + channel);
            spellings.push_back(names);
        }
    return spellings;
}

void mapBlender(const ChannelIndex& index, const MappingOptions& options, const std::string& file,
                ChannelMapping& mapping) {
    const std::string layer = pickBlenderLayer(index, options, file);
    if (layer.empty()) {
        mapping.notes.push_back("blender: no view layer with known passes");
        return;
    }
    mapping.notes.push_back(fmt::format("blender view layer '{}'", layer));
    for (const BlenderPass& pass : blenderPasses())
        if (auto found = firstPresent(index, blenderSpellings(pass, layer))) {
            mapping.attributes[pass.attribute] = found->second;
            mapping.notes.push_back(
                fmt::format("{} <- {} (blender)", attributeName(pass.attribute), joined(found->first)));
        }
}

// ---- generic: short conventional names ----

struct GenericAttribute {
    Attribute attribute;
    std::vector<Spelling> spellings;
};

const std::vector<GenericAttribute>& genericAttributes() {
    static const std::vector<GenericAttribute> table = {
        {Attribute::Depth, {{"Z"}, {"depth.Z"}, {"depth.V"}, {"Depth.Z"}, {"depth"}}},
        {Attribute::Albedo, {{"albedo.R", "albedo.G", "albedo.B"}, {"diffuse.R", "diffuse.G", "diffuse.B"}}},
        {Attribute::Normal, {{"N.X", "N.Y", "N.Z"}, {"normal.X", "normal.Y", "normal.Z"}}},
        {Attribute::Position, {{"P.X", "P.Y", "P.Z"}, {"position.X", "position.Y", "position.Z"}}},
        {Attribute::ObjectId, {{"id"}, {"objectId"}, {"id.V"}}},
        {Attribute::UV, {{"uv.U", "uv.V"}, {"uv.X", "uv.Y"}}},
        {Attribute::Roughness, {{"roughness"}, {"roughness.V"}}},
        {Attribute::Metallic, {{"metallic"}, {"metallic.V"}}},
    };
    return table;
}

void mapGeneric(const ChannelIndex& index, ChannelMapping& mapping) {
    for (const GenericAttribute& entry : genericAttributes())
        if (auto found = firstPresent(index, entry.spellings)) {
            mapping.attributes[entry.attribute] = found->second;
            mapping.notes.push_back(
                fmt::format("{} <- {} (generic)", attributeName(entry.attribute), joined(found->first)));
        }
}

// ---- explicit --channel overrides ----

void applyExplicit(const ChannelIndex& index, const MappingOptions& options, const std::string& file,
                   ChannelMapping& mapping) {
    for (const auto& [attribute, names] : options.explicit_channels) {
        const char* label = attributeName(attribute);
        if (int(names.size()) != attributeComponents(attribute))
            throw inputError(fmt::format("{}: --channel {}: expected {} channel(s), got {}", file, label,
                                         attributeComponents(attribute), names.size()));
        std::vector<ChannelRef> refs;
        for (const std::string& name : names) {
            auto it = index.find(name);
            if (it == index.end())
                throw inputError(fmt::format("{}: --channel {}: no channel '{}'", file, label, name));
            refs.push_back(it->second);
        }
        mapping.attributes[attribute] = refs;
        mapping.notes.push_back(fmt::format("{} <- {} (explicit)", label, joined(names)));
    }
}

// Cycles' Depth pass is planar; without any depth pass the position pass stands in for it.
void chooseDepthConvention(const MappingOptions& options, ChannelMapping& mapping) {
    mapping.reversed_z = options.reversed_z;
    std::string why;
    if (options.depth_convention) {
        mapping.depth_convention = *options.depth_convention;
        why = "explicit";
    } else if (mapping.attributes.count(Attribute::Depth)) {
        mapping.depth_convention = DepthConvention::Planar;
        why = "default for a depth pass";
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

}  // namespace

ChannelMapping mapChannels(const ExrImage& image, const MappingOptions& options) {
    const ChannelIndex index = indexChannels(image);
    ChannelMapping mapping;
    if (options.profile == "auto") {
        mapping.profile = looksLikeBlender(index) ? "blender" : "generic";
        mapping.notes.push_back(fmt::format("profile {} (auto-detected)", mapping.profile));
    } else if (options.profile == "blender" || options.profile == "generic") {
        mapping.profile = options.profile;
        mapping.notes.push_back(fmt::format("profile {} (requested)", mapping.profile));
    } else {
        throw inputError(fmt::format("{}: unknown channel profile '{}' (expected auto, blender or generic)",
                                     image.path, options.profile));
    }

    if (mapping.profile == "blender")
        mapBlender(index, options, image.path, mapping);
    else
        mapGeneric(index, mapping);
    applyExplicit(index, options, image.path, mapping);
    chooseDepthConvention(options, mapping);
    return mapping;
}

}  // namespace decalcomp
