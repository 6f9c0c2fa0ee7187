// --add-channels: material channels the input lacks, added on request so decals can write them.
#include <OpenEXR/ImfChannelList.h>
#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/profiles.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp {

namespace {

// A channel's stored name in `part` that reads back as `qualified` (multi-part files prefix the
// part's name to names without a dot), or nullopt when none does.
std::optional<std::string> storedName(const ExrImage& image, const ExrPart& part, const std::string& qualified) {
    const bool multi = image.parts.size() > 1;
    const std::string part_name = part.header.hasName() ? part.header.name() : "";
    for (std::string candidate : {qualified, multi && qualified.rfind(part_name + ".", 0) == 0
                                                 ? qualified.substr(part_name.size() + 1)
                                                 : qualified})
        if (io::qualifiedChannelName(part_name, multi, candidate) == qualified) return candidate;
    return std::nullopt;
}

bool taken(const ExrImage& image, const ExrPart& part, const std::string& stored, const std::string& qualified) {
    for (const ExrPart& p : image.parts)
        for (const ExrChannel& c : p.channels)
            if (c.qualified == qualified || (&p == &part && c.name == stored)) return true;
    return false;
}

// Stored names for the new channels: the first of the matched profile's spellings that reads back
// as itself in this part (so the file maps the same way when read again), else a generic name with
// the albedo channel's layer prefix ("Layer." of "Layer.Pass.C").
std::vector<std::string> newChannelNames(const ExrImage& image, const ExrPart& part, const ChannelMapping& mapping,
                                         const MappingOptions& options, const std::string& albedo_channel,
                                         Attribute attribute) {
    for (const ChannelProfile& profile : profileSet(options.profile_files)) {
        if (profile.name != mapping.profile || !profile.attributes.count(attribute)) continue;
        for (const ProfileSpelling& spelling : profile.attributes.at(attribute)) {
            std::vector<std::string> names;
            for (std::string name : spelling.channels) {
                if (const auto at = name.find("{layer}"); at != std::string::npos) name.replace(at, 7, mapping.layer);
                const auto stored = storedName(image, part, name);
                if (!stored || name.find('{') != std::string::npos || taken(image, part, *stored, name)) break;
                names.push_back(*stored);
            }
            if (names.size() == spelling.channels.size()) return names;
        }
    }
    std::string prefix;
    const auto last = albedo_channel.rfind('.');
    if (last != std::string::npos && last > 0) {
        const auto pass = albedo_channel.rfind('.', last - 1);
        if (pass != std::string::npos) prefix = albedo_channel.substr(0, pass + 1);
    }
    if (attribute == Attribute::Emission) return {prefix + "emission.R", prefix + "emission.G", prefix + "emission.B"};
    return {prefix + attributeName(attribute)};
}

}  // namespace

float addedChannelDefault(Attribute attribute) {
    switch (attribute) {
        case Attribute::Roughness: return 0.5f;
        case Attribute::AmbientOcclusion: return 1.0f;
        default: return 0.0f;  // metallic, emission
    }
}

void addAttributeChannels(std::vector<ExrImage>& files, ChannelMapping& mapping, const MappingOptions& options) {
    const std::map<Attribute, float>& requested = options.add_channels;
    if (requested.empty()) return;
    const auto albedo = mapping.attributes.find(Attribute::Albedo);
    if (albedo == mapping.attributes.end() || albedo->second.empty())
        throw inputError(fmt::format("{}: --add-channels: no albedo channels to put new channels beside",
                                     files.empty() ? std::string("input") : files.front().path));
    const ChannelRef anchor = albedo->second.front();
    ExrImage& image = files.at(std::size_t(anchor.file));
    ExrPart& part = image.parts.at(std::size_t(anchor.part));
    const ExrChannel& albedo_channel = part.channels.at(std::size_t(anchor.channel));
    for (const auto& [attribute, value] : requested) {
        if (mapping.attributes.count(attribute)) continue;  // the input has it: nothing to add
        std::vector<ChannelRef> refs;
        for (const std::string& name :
             newChannelNames(image, part, mapping, options, albedo_channel.name, attribute)) {
            if (part.header.channels().findChannel(name))
                throw inputError(fmt::format("{}: --add-channels {}: channel {} exists but is not mapped as {}; map it "
                                             "with --channel",
                                             image.path, attributeName(attribute), name, attributeName(attribute)));
            ExrChannel channel;
            channel.name = name;
            channel.qualified = io::qualifiedChannelName(part.header.hasName() ? part.header.name() : "",
                                                         image.parts.size() > 1, name);
            channel.type = albedo_channel.type == SampleType::Uint ? SampleType::Half : albedo_channel.type;
            channel.bytes.resize(io::channelByteCount(part.header.dataWindow(), channel));
            const std::size_t samples = channel.bytes.size() / io::sampleSize(channel.type);
            for (std::size_t i = 0; i < samples; ++i) io::storeSample(channel, i, value);
            part.header.channels().insert(name, Imf::Channel(io::pixelType(channel.type)));
            part.channels.push_back(std::move(channel));
            image.copy_unchanged_chunks = false;  // every chunk of the part gains the channel
            refs.push_back({anchor.part, int(part.channels.size()) - 1, anchor.file});
        }
        mapping.attributes[attribute] = refs;
        mapping.notes.push_back(fmt::format("{} added as new channels ({} where no decal writes)", attributeName(attribute),
                                            value));
    }
}

}  // namespace decalcomp
