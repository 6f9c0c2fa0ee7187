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

}  // namespace decalcomp::test
