#pragma once
// Scoring composited frames against a renderer's truth (data/*/README sections): PSNR of DiffCol.
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::test {

// The FLOAT channel `name` (qualified) copied into `storage`; nullptr when the image has none.
const std::vector<float>* findFloatChannel(const ExrImage& image, const std::string& name, std::vector<float>& storage);

struct Score {
    double psnr = 0;
    std::size_t pixels = 0;  // channel samples scored (3 per pixel)
};

// PSNR (peak 1) of DiffCol R,G,B over the pixels where the truth's mask channel > 0.5.
Score scoreAgainstTruth(const ExrImage& result, const ExrImage& truth,
                        const std::string& mask_channel = "ViewLayer.DecalMask.X");

}  // namespace decalcomp::test
