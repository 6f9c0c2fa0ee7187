#pragma once
// Random frames and decal scenes, and the kernel-vs-reference comparison, shared by the kernel
// tests (test_kernels, test_occlusion).
#include <cstdint>
#include <random>
#include <utility>

#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"

namespace decalcomp::test {

ComputeDevice& cpuDevice();  // PoCL's CPU device, opened once

// A random camera looking into a random analytic scene, in one of the depth conventions.
struct RandomFrame {
    GBuffer gbuffer;
    Camera camera;
    synth::Scene scene;
};
RandomFrame makeRandomFrame(std::uint32_t seed);

// Random premultiplied texels: alpha in [0,1], colour <= alpha.
Texture2D randomTexture(int width, int height, int depth, std::mt19937& rng, TextureShape shape = TextureShape::Flat);

// Hundreds of decals of every kind: scattered on surfaces plus the hard cases, all in one scene.
DecalScene makeRandomDecals(const RandomFrame& f, std::uint32_t seed, int count);

struct Comparison {
    std::size_t compared = 0, ambiguous = 0, mismatched = 0, changed = 0;
    double max_error = 0;
};
// Kernel output against the reference, skipping pixels the reference marks ambiguous.
Comparison compareWithReference(const GBuffer& input, const GBuffer& output, const reference::ShadeResult& ref,
                                double tolerance);

// How far float rounding can move a point, relative to its distance: hardware (ndc) depth loses
// precision with distance, so its reconstructed positions are far less exact.
double roundingMargin(const GBuffer& g);
// Tolerance: float vs double over hundreds of blends, bilinear weights and fade ramps drifts far
// less than this; hardware (ndc) depth reconstructs positions less exactly, so it gets more.
double albedoTolerance(const GBuffer& g);
// Share of pixels allowed within rounding of a decision (box face, texel edge, cube face).
double ambiguousShare(const GBuffer& g);

// Composites on PoCL and compares with the scalar reference at the frame's stated tolerance.
std::pair<GBuffer, Comparison> compositeAndCompare(const RandomFrame& f, const DecalScene& decals);

// The kernel against the reference on a frame under a pixel filter (taps or `:fast`): no pixel
// mismatched; ambiguous pixels within the point-sampled share dilated by the 3 px footprint (a
// decision within rounding anywhere in it: a face flush with a surface, a ramp steeper than
// rounding; measured up to 22 %, seed 3), and at most half; decals change at least 5 % of the
// pixels. Returns the comparison.
Comparison expectFilteredKernelMatchesReference(const RandomFrame& f, const DecalScene& decals);

// Composites binned and unbinned and counts the albedo samples whose bits differ.
std::size_t binnedUnbinnedDifferences(const RandomFrame& f, const DecalScene& decals);

}  // namespace decalcomp::test
