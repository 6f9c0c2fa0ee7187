#pragma once
// Scoring composited frames against a renderer's truth (data/*/README sections): PSNR of DiffCol.
#include <cstddef>
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

// A Blender G-buffer's mixed pixel (a silhouette or crease the pixel filter averaged): its normal
// (nx, ny, nz) is shorter than 0.995, or its depth z jumps by more than 2 % to a 4-neighbour.
struct MixedPixelTest {
    std::vector<float> nx, ny, nz, z;
    int width = 0;
    explicit MixedPixelTest(const ExrImage& gbuffer);  // ViewLayer.Normal.XYZ and ViewLayer.Depth.Z
    bool operator()(std::size_t pixel) const;
};

struct MixedPixels {
    std::size_t pixels = 0, worse = 0;
    double filtered_psnr = 0, point_psnr = 0;
    double worst_excess = 0;  // the largest (filtered - point-sampled) channel error
    int worst_x = -1, worst_y = -1;
};

// Over the decal pixels (truth DecalMask > 0.5) that are mixed in the G-buffer at `gbuffer_path`:
// PSNR of the filtered and the point-sampled DiffCol against the truth, and how many the filtered
// result gets worse than the point-sampled one by more than `tolerance` (largest channel error).
MixedPixels compareMixedPixels(const std::string& gbuffer_path, const ExrImage& filtered, const ExrImage& point,
                               const ExrImage& truth, double tolerance);

}  // namespace decalcomp::test
