// extractGBuffer / storeAttribute: mapped EXR channels (one file or several, any data windows)
// <-> float attribute planes over one G-buffer window.
#include "decalcomp/gbuffer_exr.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_pool.hpp"

namespace decalcomp {

namespace {

using Files = std::vector<const ExrImage*>;

std::string windowText(const Imath::Box2i& w) {
    return fmt::format("({},{})-({},{})", w.min.x, w.min.y, w.max.x, w.max.y);
}

const ExrImage& fileAt(const Files& files, const ChannelRef& ref, const std::string& label) {
    if (ref.file < 0 || ref.file >= int(files.size()))
        throw inputError(fmt::format("{}: channel reference to file {} of {}", label, ref.file, files.size()));
    return *files[ref.file];
}

const ExrChannel& channelAt(const Files& files, const ChannelRef& ref, const std::string& label) {
    const ExrImage& image = fileAt(files, ref, label);
    if (ref.part < 0 || ref.part >= int(image.parts.size()) || ref.channel < 0 ||
        ref.channel >= int(image.parts[ref.part].channels.size()))
        throw inputError(fmt::format("{}: {}: channel reference (part {}, channel {}) out of range", image.path, label,
                                     ref.part, ref.channel));
    return image.parts[ref.part].channels[ref.channel];
}

const Imf::Header& headerOf(const Files& files, const ChannelRef& ref) { return files[ref.file]->parts[ref.part].header; }

// The attribute whose data window becomes the G-buffer's: the one that says where geometry is.
std::optional<Attribute> referenceAttribute(const ChannelMapping& mapping) {
    for (Attribute a : {Attribute::Depth, Attribute::Position, Attribute::Albedo})
        if (auto it = mapping.attributes.find(a); it != mapping.attributes.end() && !it->second.empty()) return a;
    for (const auto& [attribute, refs] : mapping.attributes)
        if (!refs.empty()) return attribute;
    return std::nullopt;
}

FrameWindow windowOf(const Files& files, const ChannelMapping& mapping) {
    if (files.empty() || files.front()->parts.empty())
        throw inputError(fmt::format("{}: no image parts", files.empty() ? std::string("input") : files.front()->path));
    FrameWindow window;
    const auto reference = referenceAttribute(mapping);
    if (!reference) {
        const Imf::Header& header = files.front()->parts.front().header;
        window.data = header.dataWindow();
        window.display = header.displayWindow();
        window.owner = files.front()->path;
        return window;
    }
    const ChannelRef& ref = mapping.attributes.at(*reference).front();
    channelAt(files, ref, attributeName(*reference));
    window.data = headerOf(files, ref).dataWindow();
    window.display = headerOf(files, ref).displayWindow();
    window.owner = fmt::format("{} ({})", attributeName(*reference), files[ref.file]->path);
    // NDC is defined over the display window, so every pass must agree on it.
    for (const auto& [attribute, refs] : mapping.attributes)
        for (const ChannelRef& r : refs) {
            const ExrChannel& channel = channelAt(files, r, attributeName(attribute));
            const Imath::Box2i display = headerOf(files, r).displayWindow();
            if (display != window.display)
                throw inputError(fmt::format("{}: channel {}: display window {} differs from {} of {}",
                                             files[r.file]->path, channel.qualified, windowText(display),
                                             windowText(window.display), window.owner));
        }
    return window;
}

// Mapped channels must be full resolution, and float attributes need float samples.
void checkChannel(const Files& files, const ChannelRef& ref, bool allow_uint, const std::string& label) {
    const ExrChannel& channel = channelAt(files, ref, label);
    const std::string& path = files[ref.file]->path;
    if (channel.x_sampling != 1 || channel.y_sampling != 1)
        throw inputError(fmt::format("{}: channel {}: subsampled ({}x{}); {} needs full resolution", path,
                                     channel.qualified, channel.x_sampling, channel.y_sampling, label));
    if (channel.type == SampleType::Uint && !allow_uint)
        throw inputError(fmt::format("{}: channel {}: UINT is the wrong type for {} (expected HALF or FLOAT)", path,
                                     channel.qualified, label));
}

// Calls visit(frame_index, channel_index, x, y, count) for every run of `count` pixels from (x, y)
// along a row in the overlap of the frame's window and a channel's data window that lies in one
// chunk `part` decoded; indices are into each one's own row-major samples.
// Only rows [first_row, last_row] (absolute) when given.
template <typename Visit>
void forEachOverlapRun(const Imath::Box2i& window, const ExrPart& part, Visit visit, int first_row = INT_MIN,
                       int last_row = INT_MAX) {
    const Imath::Box2i dw = part.header.dataWindow();
    const std::size_t width = std::size_t(window.max.x - window.min.x + 1);
    const long long channel_width = (long long)dw.max.x - dw.min.x + 1;
    const int x0 = std::max(window.min.x, dw.min.x), x1 = std::min(window.max.x, dw.max.x);
    const int y0 = std::max({window.min.y, dw.min.y, first_row}), y1 = std::min({window.max.y, dw.max.y, last_row});
    const int tile = part.chunks.tile_width;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1;) {
            // a run ends at the row's end, or at a tile's right edge in tiled parts
            int end = x1 + 1;
            if (part.chunks.tiled) end = std::min(end, dw.min.x + ((x - dw.min.x) / tile + 1) * tile);
            if (part.isDecodedAt(x, y))
                visit(std::size_t(y - window.min.y) * width + std::size_t(x - window.min.x),
                      std::size_t((long long)(y - dw.min.y) * channel_width + (x - dw.min.x)), x, y, end - x);
            x = end;
        }
}

// The plane's components whose channels lie in one part: they share its data window and its
// decoded chunks, so they are copied in one pass over the part's rows.
struct PartComponents {
    const ExrPart* part = nullptr;
    std::vector<int> components;  // into the plane (and the refs)
};

std::vector<PartComponents> groupByPart(const std::vector<const ExrPart*>& parts) {
    std::vector<PartComponents> groups;
    for (int c = 0; c < int(parts.size()); ++c) {
        auto same =
            std::find_if(groups.begin(), groups.end(), [&](const PartComponents& g) { return g.part == parts[c]; });
        if (same == groups.end()) same = groups.insert(groups.end(), PartComponents{parts[c], {}});
        same->components.push_back(c);
    }
    return groups;
}

// `count` FLOAT samples of each channel into a plane of N components, channel k to component k:
// one pass over the output (the common case: every component of an attribute in one part).
template <int N>
void interleaveFloats(const std::array<const unsigned char*, 4>& from, std::size_t count, float* out) {
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < N; ++c) std::memcpy(out + k * N + c, from[c] + k * sizeof(float), sizeof(float));
}

// One component's samples [first, first + count) of `channel` as floats into out[0], out[stride], ...
void readRun(const ExrChannel& channel, std::size_t first, std::size_t count, float* out, std::size_t stride) {
    if (channel.type == SampleType::Float) {
        const unsigned char* p = channel.bytes.data() + first * sizeof(float);
        for (std::size_t k = 0; k < count; ++k) std::memcpy(out + k * stride, p + k * sizeof(float), sizeof(float));
        return;
    }
    for (std::size_t k = 0; k < count; ++k) out[k * stride] = io::sampleAsFloat(channel, first + k);
}

Plane readOnWindow(const Files& files, const std::vector<ChannelRef>& refs, const Imath::Box2i& window, float fill,
                   bool allow_uint, const std::string& label) {
    const std::size_t width = std::size_t(window.max.x - window.min.x + 1);
    const std::size_t height = std::size_t(window.max.y - window.min.y + 1);
    Plane plane;
    plane.components = int(refs.size());
    std::vector<const ExrPart*> parts;
    std::vector<const ExrChannel*> channels;
    for (const ChannelRef& ref : refs) {
        checkChannel(files, ref, allow_uint, label);
        channels.push_back(&channelAt(files, ref, label));
        parts.push_back(&files[ref.file]->parts[ref.part]);
    }
    // Pixels in chunks that were not decoded keep `fill`: background, which no decal changes.
    plane.samples.assign(width * height * refs.size(), fill);
    const std::size_t stride = refs.size();
    for (const PartComponents& group : groupByPart(parts)) {
        const std::vector<int>& cs = group.components;
        // (cs holds ascending components: all of them when it holds as many)
        const bool whole_float = int(cs.size()) == plane.components && plane.components <= 4 &&
                                 std::all_of(cs.begin(), cs.end(), [&](int c) {
                                     return channels[std::size_t(c)]->type == SampleType::Float;
                                 });
        const auto copy = [&](std::size_t frame, std::size_t sample, int, int, int count) {
            float* out = plane.samples.data() + frame * stride;
            const std::size_t n = std::size_t(count);
            if (!whole_float) {
                for (int c : cs) readRun(*channels[std::size_t(c)], sample, n, out + c, stride);
                return;
            }
            std::array<const unsigned char*, 4> from{};
            for (int c : cs) from[std::size_t(c)] = channels[std::size_t(c)]->bytes.data() + sample * sizeof(float);
            if (plane.components == 1)
                std::memcpy(out, from[0], n * sizeof(float));
            else if (plane.components == 2)
                interleaveFloats<2>(from, n, out);
            else if (plane.components == 3)
                interleaveFloats<3>(from, n, out);
            else
                interleaveFloats<4>(from, n, out);
        };
        // In bands of rows on the codecs' pool, as part of reading the frame: pure memory traffic.
        constexpr int kBandRows = 32;
        const int bands = (window.max.y - window.min.y) / kBandRows + 1;
        io::runOnExrPool(io::PoolWork::Decode, std::size_t(bands), [&](std::size_t band) {
            const int first = window.min.y + int(band) * kBandRows;
            forEachOverlapRun(window, *group.part, copy, first, first + kBandRows - 1);
        });
    }
    return plane;
}

// Background where a pass has no data: NaN position (the position convention's background),
// +inf depth, 0 elsewhere.
float fillFor(Attribute attribute) {
    if (attribute == Attribute::Position) return std::numeric_limits<float>::quiet_NaN();
    if (attribute == Attribute::Depth) return std::numeric_limits<float>::infinity();
    return 0.0f;
}

GBuffer extract(const Files& files, const ChannelMapping& mapping) {
    const FrameWindow window = windowOf(files, mapping);
    GBuffer gbuffer;
    gbuffer.width = window.data.max.x - window.data.min.x + 1;
    gbuffer.height = window.data.max.y - window.data.min.y + 1;
    gbuffer.origin_x = window.data.min.x - window.display.min.x;
    gbuffer.origin_y = window.data.min.y - window.display.min.y;
    gbuffer.display_width = window.display.max.x - window.display.min.x + 1;
    gbuffer.display_height = window.display.max.y - window.display.min.y + 1;
    if (gbuffer.width <= 0 || gbuffer.height <= 0 || gbuffer.display_width <= 0 || gbuffer.display_height <= 0)
        throw inputError(fmt::format("{}: empty data or display window", window.owner));
    gbuffer.depth_convention = mapping.depth_convention;
    gbuffer.reversed_z = mapping.reversed_z;
    gbuffer.normal_encoding = mapping.normals;
    for (const auto& [attribute, refs] : mapping.attributes)
        gbuffer.planes[attribute] = readOnWindow(files, refs, window.data, fillFor(attribute),
                                                 attribute == Attribute::ObjectId, attributeName(attribute));
    return gbuffer;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::size_t store(const std::vector<ExrImage*>& files, const ChannelMapping& mapping, Attribute attribute,
                  const Plane& plane) {
    Files view(files.begin(), files.end());
    const std::string label = attributeName(attribute);
    auto found = mapping.attributes.find(attribute);
    if (found == mapping.attributes.end())
        throw outputError(fmt::format("{}: {}: attribute is not mapped to any channel", files.front()->path, label));
    const std::vector<ChannelRef>& refs = found->second;
    if (plane.components != int(refs.size()))
        throw outputError(fmt::format("{}: {}: plane has {} components, mapping has {} channels", files.front()->path,
                                      label, plane.components, refs.size()));
    const Imath::Box2i window = windowOf(view, mapping).data;
    const std::size_t width = std::size_t(window.max.x - window.min.x + 1);
    const std::size_t height = std::size_t(window.max.y - window.min.y + 1);
    if (plane.samples.size() != width * height * refs.size())
        throw outputError(fmt::format("{}: {}: plane has {} samples, the G-buffer window {} has {} pixels",
                                      files.front()->path, label, plane.samples.size(), windowText(window),
                                      width * height));
    std::size_t changed = 0;
    for (int c = 0; c < plane.components; ++c) {
        channelAt(view, refs[c], label);  // range check before taking a mutable reference
        ExrImage& image = *files[refs[c].file];
        ExrPart& part = image.parts[refs[c].part];
        ExrChannel& channel = part.channels[refs[c].channel];
        if (channel.x_sampling != 1 || channel.y_sampling != 1)
            throw outputError(fmt::format("{}: channel {}: subsampled", image.path, channel.qualified));
        // Untouched pixels keep their exact original bits, and the chunks holding none of the
        // changed ones are written back as the input's compressed bytes (ExrPart::changed).
        forEachOverlapRun(window, part, [&](std::size_t frame, std::size_t sample, int x, int y, int count) {
            std::size_t run_changed = 0;
            if (channel.type == SampleType::Float) {  // most G-buffers: compare and store the bits
                // (stored whether or not they differ: the same bits, and no branch to mispredict)
                unsigned char* p = channel.bytes.data() + sample * sizeof(float);
                const float* from = plane.samples.data() + frame * std::size_t(plane.components) + std::size_t(c);
                const std::size_t stride = std::size_t(plane.components);
                for (int k = 0; k < count; ++k, p += sizeof(float)) {
                    std::uint32_t before, after;
                    std::memcpy(&before, p, sizeof before);
                    std::memcpy(&after, from + std::size_t(k) * stride, sizeof after);
                    run_changed += before != after;
                    std::memcpy(p, &after, sizeof after);
                }
            } else {
                for (int k = 0; k < count; ++k) {
                    const float value = plane.at(frame + std::size_t(k), c);
                    const std::size_t at = sample + std::size_t(k);
                    const float before = io::sampleAsFloat(channel, at);
                    if (sameBits(value, before)) continue;
                    io::storeSample(channel, at, value);
                    // a half or uint sample may round back to its old bits
                    run_changed += !sameBits(io::sampleAsFloat(channel, at), before);
                }
            }
            if (run_changed) part.markChanged(x, y);  // a run lies in one chunk
            changed += run_changed;
        });
    }
    return changed;
}

}  // namespace

FrameWindow frameWindow(const std::vector<ExrImage>& files, const ChannelMapping& mapping) {
    Files view;
    for (const ExrImage& f : files) view.push_back(&f);
    return windowOf(view, mapping);
}

Plane readChannelsOnWindow(const std::vector<ExrImage>& files, const std::vector<ChannelRef>& refs,
                           const Imath::Box2i& window, float fill, bool allow_uint, const std::string& label) {
    Files view;
    for (const ExrImage& f : files) view.push_back(&f);
    return readOnWindow(view, refs, window, fill, allow_uint, label);
}

GBuffer extractGBuffer(const ExrImage& image, const ChannelMapping& mapping) { return extract({&image}, mapping); }

GBuffer extractGBuffer(const std::vector<ExrImage>& files, const ChannelMapping& mapping) {
    Files view;
    for (const ExrImage& f : files) view.push_back(&f);
    return extract(view, mapping);
}

std::size_t storeAttribute(ExrImage& image, const ChannelMapping& mapping, Attribute attribute, const Plane& plane) {
    return store({&image}, mapping, attribute, plane);
}

std::size_t storeAttribute(std::vector<ExrImage>& files, const ChannelMapping& mapping, Attribute attribute,
                           const Plane& plane) {
    std::vector<ExrImage*> view;
    for (ExrImage& f : files) view.push_back(&f);
    return store(view, mapping, attribute, plane);
}

}  // namespace decalcomp
