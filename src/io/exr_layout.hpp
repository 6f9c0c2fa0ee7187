#pragma once
// Sample layout and conversions shared by the EXR reader, writer and G-buffer code (internal).
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfPixelType.h>

#include <cstddef>
#include <string>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

std::size_t sampleSize(SampleType type);
Imf::PixelType pixelType(SampleType type);
SampleType sampleType(Imf::PixelType type);
const char* sampleTypeName(SampleType type);  // "UINT", "HALF", "FLOAT"

// Samples per row and rows of a channel over a data window, honouring its x/y sampling.
std::size_t sampledWidth(const Imath::Box2i& data_window, int x_sampling);
std::size_t sampledHeight(const Imath::Box2i& data_window, int y_sampling);
std::size_t channelByteCount(const Imath::Box2i& data_window, const ExrChannel& channel);

// A tightly packed frame-buffer slice over `channel.bytes`. OpenEXR wants a mutable pointer even
// for writing, hence the const_cast inside; the writer never lets it modify the bytes.
Imf::Slice channelSlice(const Imath::Box2i& data_window, const ExrChannel& channel);

// The mapping name of a channel (see ExrChannel::qualified).
std::string qualifiedChannelName(const std::string& part_name, bool multi_part,
                                 const std::string& channel_name);

// Sample i of a channel as float, and back (half rounds to nearest, uint rounds and clamps).
float sampleAsFloat(const ExrChannel& channel, std::size_t index);
void storeSample(ExrChannel& channel, std::size_t index, float value);

// Library messages can span lines; ours are one line.
std::string oneLine(const std::string& message);

}  // namespace decalcomp::io
