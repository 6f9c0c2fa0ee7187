// The fast pixel filter (PixelFilter::fast, docs/pixel-filter.md "Integrated evaluation"): pixels
// on one tangent plane take each decal once in closed form. The kernel against the scalar
// reference on PoCL, on random scenes of every kind and convention.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/reference.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

PixelFilter fastFilterFor(std::uint32_t seed) {
    const PixelFilter filters[] = {{PixelFilterType::BlackmanHarris, 3.0, true},
                                   {PixelFilterType::Gaussian, 2.0, true},
                                   {PixelFilterType::Box, 1.0, true}};
    return filters[seed % 3];
}

class FastFilteredRandomScenes : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(FastFilteredRandomScenes, KernelMatchesReference) {
    test::RandomFrame f = test::makeRandomFrame(GetParam());
    f.gbuffer.pixel_filter = fastFilterFor(GetParam());
    ASSERT_TRUE(f.gbuffer.pixel_filter.fast);
    const DecalScene decals = test::makeRandomDecals(f, GetParam(), 300);
    const test::Comparison c = test::expectFilteredKernelMatchesReference(f, decals);
    // the closed form is what was compared: the reference's taps give another result
    GBuffer stacked_frame = f.gbuffer;
    stacked_frame.pixel_filter.fast = false;
    const auto fast = reference::shade(f.gbuffer, f.camera, decals, test::roundingMargin(f.gbuffer));
    const auto stacked = reference::shade(stacked_frame, f.camera, decals, test::roundingMargin(f.gbuffer));
    std::size_t differing = 0;
    for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i)
        differing += std::abs(fast.albedo.at(i, 0) - stacked.albedo.at(i, 0)) > 1e-3f;
    EXPECT_GT(double(differing), 0.01 * double(f.gbuffer.pixelCount()));
    std::printf("%s %s %dx%d: %zu ambiguous (%.2f %%), max error %.3g over %zu compared, %zu differ from the taps\n",
                f.gbuffer.pixel_filter.spelling().c_str(), depthConventionName(f.gbuffer.depth_convention),
                f.gbuffer.width, f.gbuffer.height, c.ambiguous,
                100.0 * double(c.ambiguous) / double(f.gbuffer.pixelCount()), c.max_error, c.compared, differing);
}

INSTANTIATE_TEST_SUITE_P(Seeds, FastFilteredRandomScenes, ::testing::Values(1u, 2u, 3u, 4u));

}  // namespace
}  // namespace decalcomp
