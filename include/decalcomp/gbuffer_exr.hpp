#pragma once
// Mapped EXR channels <-> G-buffer planes: the frame's pixel window, reading channels as float
// planes and storing planes back into the channels in their own sample types.
#include <Imath/ImathBox.h>

#include <string>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// The pixels a G-buffer covers, in absolute EXR coordinates: the data window of the depth pass
// (else position, else albedo, else the first mapped attribute), and the display window all
// mapped parts share. Throws Error(Input) when mapped parts have different display windows.
struct FrameWindow {
    Imath::Box2i data, display;
    std::string owner;  // "depth (in.exr)", for messages
};
FrameWindow frameWindow(const std::vector<ExrImage>& files, const ChannelMapping& mapping);

// Reads channels as one interleaved float plane over `window`; pixels outside a channel's own data
// window get `fill`. Throws Error(Input) for subsampled channels, and for UINT channels unless
// allow_uint (ID-like data).
Plane readChannelsOnWindow(const std::vector<ExrImage>& files, const std::vector<ChannelRef>& refs,
                           const Imath::Box2i& window, float fill, bool allow_uint, const std::string& label);

// Converts the mapped channels to float planes over frameWindow(). A pass whose data window differs
// (crop, overscan) is resampled onto it: pixels it does not cover get background (position NaN,
// other attributes 0). Throws Error(Input) naming the file and channel for subsampled channels,
// UINT where a float attribute is expected (ObjectId accepts all types), display windows that differ.
GBuffer extractGBuffer(const ExrImage& image, const ChannelMapping& mapping);
GBuffer extractGBuffer(const std::vector<ExrImage>& files, const ChannelMapping& mapping);

// Writes a float plane (over frameWindow()) back into the attribute's mapped channels, converting
// to each channel's own sample type; channel pixels outside the G-buffer window are left alone.
// Pixels whose float value equals the original conversion stay bit-exact. Returns how many
// samples changed.
std::size_t storeAttribute(ExrImage& image, const ChannelMapping& mapping, Attribute attribute,
                           const Plane& plane);
std::size_t storeAttribute(std::vector<ExrImage>& files, const ChannelMapping& mapping, Attribute attribute,
                    const Plane& plane);

}  // namespace decalcomp
