#include "io/exr_layout.hpp"

#include <Imath/half.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace decalcomp::io {

std::size_t sampleSize(SampleType type) { return type == SampleType::Half ? 2 : 4; }

Imf::PixelType pixelType(SampleType type) {
    switch (type) {
        case SampleType::Uint: return Imf::UINT;
        case SampleType::Half: return Imf::HALF;
        case SampleType::Float: return Imf::FLOAT;
    }
    return Imf::FLOAT;
}

SampleType sampleType(Imf::PixelType type) {
    switch (type) {
        case Imf::UINT: return SampleType::Uint;
        case Imf::HALF: return SampleType::Half;
        default: return SampleType::Float;
    }
}

const char* sampleTypeName(SampleType type) {
    switch (type) {
        case SampleType::Uint: return "UINT";
        case SampleType::Half: return "HALF";
        case SampleType::Float: return "FLOAT";
    }
    return "?";
}

namespace {

// Floor division that stays correct for negative window coordinates.
long long floorDiv(long long a, long long b) { return a / b - ((a % b != 0) && ((a < 0) != (b < 0))); }

// Number of multiples of `sampling` in [lo, hi]: the positions OpenEXR stores samples at.
std::size_t sampledCount(int lo, int hi, int sampling) {
    if (sampling < 1 || hi < lo) return 0;
    return std::size_t(floorDiv(hi, sampling) - floorDiv(static_cast<long long>(lo) - 1, sampling));
}

}  // namespace

std::size_t sampledWidth(const Imath::Box2i& dw, int x_sampling) {
    return sampledCount(dw.min.x, dw.max.x, x_sampling);
}

std::size_t sampledHeight(const Imath::Box2i& dw, int y_sampling) {
    return sampledCount(dw.min.y, dw.max.y, y_sampling);
}

std::size_t channelByteCount(const Imath::Box2i& dw, const ExrChannel& channel) {
    return sampledWidth(dw, channel.x_sampling) * sampledHeight(dw, channel.y_sampling) *
           sampleSize(channel.type);
}

Imf::Slice channelSlice(const Imath::Box2i& dw, const ExrChannel& channel) {
    const std::size_t x_stride = sampleSize(channel.type);
    const std::size_t y_stride = x_stride * sampledWidth(dw, channel.x_sampling);
    // Slice::Make computes the origin-shifted base pointer without overflowing.
    return Imf::Slice::Make(pixelType(channel.type), channel.bytes.data(), dw, x_stride, y_stride,
                            channel.x_sampling, channel.y_sampling);
}

std::string qualifiedChannelName(const std::string& part_name, bool multi_part,
                                 const std::string& channel_name) {
    if (!multi_part || part_name.empty() || channel_name.find('.') != std::string::npos)
        return channel_name;
    return part_name + "." + channel_name;
}

float sampleAsFloat(const ExrChannel& channel, std::size_t index) {
    const unsigned char* p = channel.bytes.data() + index * sampleSize(channel.type);
    switch (channel.type) {
        case SampleType::Half: {
            std::uint16_t bits;
            std::memcpy(&bits, p, sizeof bits);
            Imath::half h;
            h.setBits(bits);
            return float(h);
        }
        case SampleType::Float: {
            float f;
            std::memcpy(&f, p, sizeof f);
            return f;
        }
        case SampleType::Uint: {
            std::uint32_t u;
            std::memcpy(&u, p, sizeof u);
            return float(u);
        }
    }
    return 0.0f;
}

namespace {

std::uint32_t roundToUint(float value) {
    if (!(value > 0.0f)) return 0;  // NaN and negatives
    if (value >= 4294967295.0f) return 4294967295u;
    return std::uint32_t(std::llround(double(value)));
}

}  // namespace

void storeSample(ExrChannel& channel, std::size_t index, float value) {
    unsigned char* p = channel.bytes.data() + index * sampleSize(channel.type);
    switch (channel.type) {
        case SampleType::Half: {
            const std::uint16_t bits = Imath::half(value).bits();
            std::memcpy(p, &bits, sizeof bits);
            return;
        }
        case SampleType::Float: std::memcpy(p, &value, sizeof value); return;
        case SampleType::Uint: {
            const std::uint32_t u = roundToUint(value);
            std::memcpy(p, &u, sizeof u);
            return;
        }
    }
}

std::string oneLine(const std::string& message) {
    std::string out;
    out.reserve(message.size());
    for (char c : message) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += c;
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

}  // namespace decalcomp::io
