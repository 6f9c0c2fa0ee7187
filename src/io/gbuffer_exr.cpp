// extractGBuffer / storeAttribute: mapped EXR channels <-> float attribute planes.
#include <fmt/format.h>

#include <cstring>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_io.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp {

namespace {

std::string windowText(const Imath::Box2i& w) {
    return fmt::format("({},{})-({},{})", w.min.x, w.min.y, w.max.x, w.max.y);
}

const ExrChannel& channelAt(const ExrImage& image, const ChannelRef& ref, Attribute attribute) {
    if (ref.part < 0 || ref.part >= int(image.parts.size()) || ref.channel < 0 ||
        ref.channel >= int(image.parts[ref.part].channels.size()))
        throw inputError(fmt::format("{}: {}: channel reference (part {}, channel {}) out of range", image.path,
                                     attributeName(attribute), ref.part, ref.channel));
    return image.parts[ref.part].channels[ref.channel];
}

// The part whose windows define the G-buffer: the first mapped channel's, else the first part.
int referencePart(const ChannelMapping& mapping) {
    for (const auto& [attribute, refs] : mapping.attributes)
        if (!refs.empty()) return refs.front().part;
    return 0;
}

// Every mapped channel must cover the same pixels at full resolution, in a usable type.
void checkChannel(const ExrImage& image, const ChannelRef& ref, Attribute attribute, const Imath::Box2i& window,
                  const std::string& window_owner) {
    const ExrChannel& channel = channelAt(image, ref, attribute);
    const Imath::Box2i dw = image.parts[ref.part].header.dataWindow();
    if (dw != window)
        throw inputError(fmt::format("{}: channel {}: data window {} differs from {} of {}", image.path,
                                     channel.qualified, windowText(dw), windowText(window), window_owner));
    if (channel.x_sampling != 1 || channel.y_sampling != 1)
        throw inputError(fmt::format("{}: channel {}: subsampled ({}x{}); {} needs full resolution", image.path,
                                     channel.qualified, channel.x_sampling, channel.y_sampling,
                                     attributeName(attribute)));
    if (channel.type == SampleType::Uint && attribute != Attribute::ObjectId)
        throw inputError(fmt::format("{}: channel {}: UINT is the wrong type for {} (expected HALF or FLOAT)",
                                     image.path, channel.qualified, attributeName(attribute)));
}

Plane extractPlane(const ExrImage& image, const std::vector<ChannelRef>& refs, Attribute attribute,
                   std::size_t pixels) {
    Plane plane;
    plane.components = int(refs.size());
    plane.samples.resize(pixels * refs.size());
    for (int c = 0; c < plane.components; ++c) {
        const ExrChannel& channel = channelAt(image, refs[c], attribute);
        for (std::size_t i = 0; i < pixels; ++i) plane.at(i, c) = io::sampleAsFloat(channel, i);
    }
    return plane;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

GBuffer extractGBuffer(const ExrImage& image, const ChannelMapping& mapping) {
    if (image.parts.empty()) throw inputError(fmt::format("{}: no image parts", image.path));
    const int reference = referencePart(mapping);
    if (reference < 0 || reference >= int(image.parts.size()))
        throw inputError(fmt::format("{}: channel mapping refers to part {} of {}", image.path, reference,
                                     image.parts.size()));
    const Imf::Header& header = image.parts[reference].header;
    const Imath::Box2i window = header.dataWindow();
    const Imath::Box2i display = header.displayWindow();

    std::string window_owner = fmt::format("part {}", reference);
    for (const auto& [attribute, refs] : mapping.attributes) {
        for (const ChannelRef& ref : refs) {
            checkChannel(image, ref, attribute, window, window_owner);
            window_owner = "channel " + channelAt(image, ref, attribute).qualified;
        }
    }

    GBuffer gbuffer;
    gbuffer.width = window.max.x - window.min.x + 1;
    gbuffer.height = window.max.y - window.min.y + 1;
    gbuffer.origin_x = window.min.x - display.min.x;
    gbuffer.origin_y = window.min.y - display.min.y;
    gbuffer.display_width = display.max.x - display.min.x + 1;
    gbuffer.display_height = display.max.y - display.min.y + 1;
    gbuffer.depth_convention = mapping.depth_convention;
    gbuffer.reversed_z = mapping.reversed_z;
    for (const auto& [attribute, refs] : mapping.attributes)
        gbuffer.planes[attribute] = extractPlane(image, refs, attribute, gbuffer.pixelCount());
    return gbuffer;
}

void storeAttribute(ExrImage& image, const ChannelMapping& mapping, Attribute attribute, const Plane& plane) {
    auto found = mapping.attributes.find(attribute);
    if (found == mapping.attributes.end())
        throw outputError(fmt::format("{}: {}: attribute is not mapped to any channel", image.path,
                                      attributeName(attribute)));
    const std::vector<ChannelRef>& refs = found->second;
    if (plane.components != int(refs.size()))
        throw outputError(fmt::format("{}: {}: plane has {} components, mapping has {} channels", image.path,
                                      attributeName(attribute), plane.components, refs.size()));
    for (int c = 0; c < plane.components; ++c) {
        channelAt(image, refs[c], attribute);  // range check before taking a mutable reference
        ExrChannel& channel = image.parts[refs[c].part].channels[refs[c].channel];
        const std::size_t count = channel.bytes.size() / io::sampleSize(channel.type);
        if (plane.samples.size() != count * refs.size())
            throw outputError(fmt::format("{}: channel {}: plane has {} samples, channel has {} pixels",
                                          image.path, channel.qualified, plane.samples.size(), count));
        // Only changed pixels are re-encoded, so untouched ones keep their exact original bits.
        for (std::size_t i = 0; i < count; ++i) {
            const float value = plane.at(i, c);
            if (!sameBits(value, io::sampleAsFloat(channel, i))) io::storeSample(channel, i, value);
        }
    }
}

}  // namespace decalcomp
