#include "support/truth_score.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace decalcomp::test {

const std::vector<float>* findFloatChannel(const ExrImage& image, const std::string& name, std::vector<float>& storage) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            if (c.qualified == name && c.type == SampleType::Float) {
                storage.resize(c.bytes.size() / sizeof(float));
                std::memcpy(storage.data(), c.bytes.data(), c.bytes.size());
                return &storage;
            }
    return nullptr;
}

Score scoreAgainstTruth(const ExrImage& result, const ExrImage& truth, const std::string& mask_channel) {
    std::vector<float> mask, a, b;
    EXPECT_NE(findFloatChannel(truth, mask_channel, mask), nullptr) << mask_channel;
    double squared = 0;
    Score score;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.DiffCol.") + c;
        EXPECT_NE(findFloatChannel(result, name, a), nullptr) << name;
        EXPECT_NE(findFloatChannel(truth, name, b), nullptr) << name;
        for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i] > 0.5f) {
                squared += double(a[i] - b[i]) * double(a[i] - b[i]);
                ++score.pixels;
            }
    }
    score.psnr = 10.0 * std::log10(double(score.pixels) / std::max(squared, 1e-30));
    return score;
}

MixedPixelTest::MixedPixelTest(const ExrImage& g) : width(g.parts.at(0).width) {
    EXPECT_NE(findFloatChannel(g, "ViewLayer.Normal.X", nx), nullptr);
    EXPECT_NE(findFloatChannel(g, "ViewLayer.Normal.Y", ny), nullptr);
    EXPECT_NE(findFloatChannel(g, "ViewLayer.Normal.Z", nz), nullptr);
    EXPECT_NE(findFloatChannel(g, "ViewLayer.Depth.Z", z), nullptr);
}

bool MixedPixelTest::operator()(std::size_t i) const {
    const long x = long(i % std::size_t(width));
    for (const long d : {-1L, 1L, -long(width), long(width)}) {
        if ((d == -1 && x == 0) || (d == 1 && x + 1 == width)) continue;  // no wrap to the next row
        const long j = long(i) + d;
        if (j >= 0 && j < long(z.size()) && std::abs(z[std::size_t(j)] - z[i]) > 0.02f * z[i]) return true;
    }
    return std::sqrt(double(nx[i]) * nx[i] + double(ny[i]) * ny[i] + double(nz[i]) * nz[i]) < 0.995;
}

MixedPixels compareMixedPixels(const std::string& gbuffer_path, const ExrImage& filtered, const ExrImage& point,
                               const ExrImage& truth, double tolerance) {
    const MixedPixelTest mixed(readExr(gbuffer_path));
    std::vector<float> mask, f[3], p[3], t[3];
    EXPECT_NE(findFloatChannel(truth, "ViewLayer.DecalMask.X", mask), nullptr);
    const char* channel[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        const std::string name = std::string("ViewLayer.DiffCol.") + channel[c];
        findFloatChannel(filtered, name, f[c]);
        findFloatChannel(point, name, p[c]);
        findFloatChannel(truth, name, t[c]);
    }
    MixedPixels m;
    double filtered_squared = 0, point_squared = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!(mask[i] > 0.5f) || !mixed(i)) continue;
        ++m.pixels;
        double ef = 0, ep = 0;
        for (int c = 0; c < 3; ++c) {
            ef = std::max(ef, double(std::abs(f[c][i] - t[c][i])));
            ep = std::max(ep, double(std::abs(p[c][i] - t[c][i])));
            filtered_squared += double(f[c][i] - t[c][i]) * double(f[c][i] - t[c][i]);
            point_squared += double(p[c][i] - t[c][i]) * double(p[c][i] - t[c][i]);
        }
        if (ef > ep + tolerance) ++m.worse;
        if (ef - ep > m.worst_excess) {
            m.worst_excess = ef - ep;
            m.worst_x = int(i % std::size_t(mixed.width));
            m.worst_y = int(i / std::size_t(mixed.width));
        }
    }
    m.filtered_psnr = 10.0 * std::log10(3.0 * double(m.pixels) / std::max(filtered_squared, 1e-30));
    m.point_psnr = 10.0 * std::log10(3.0 * double(m.pixels) / std::max(point_squared, 1e-30));
    return m;
}

}  // namespace decalcomp::test
