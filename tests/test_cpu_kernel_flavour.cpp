// CPU devices build the kernels with DC_CPU_DEVICE (buildOptions, kernels/shared_types.h): helpers
// forced inline, a texel integral's column shares kept in an array, a tile's rows read ahead. Only
// the code's shape changes, so the GPUs' build of the same kernels (DECALCOMP_KERNEL_FLAVOUR=gpu,
// run here on PoCL) must give every pixel bit for bit, on antialiased frames with silhouettes and creases, in
// closed form and with taps, and on random scenes of every kind and depth convention.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_antialias.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

GBuffer composite(ComputeDevice& device, const GBuffer& frame, const Camera& camera, const DecalScene& decals) {
    Compositor compositor(device);
    compositor.setScene(decals);
    GBuffer out = frame;
    compositor.composite(out, camera);
    return out;
}

// Both builds' outputs on PoCL, each on a device of its own (programs build lazily, at a device's
// first composite, so the variable is set around it).
std::pair<GBuffer, GBuffer> bothFlavours(const GBuffer& frame, const Camera& camera, const DecalScene& decals) {
    const test::ScopedEnv flavour_unset("DECALCOMP_KERNEL_FLAVOUR", nullptr);
    ComputeDevice cpu_way("cpu");
    GBuffer cpu = composite(cpu_way, frame, camera, decals);
    ComputeDevice gpu_way("cpu");
    const test::ScopedEnv flavour("DECALCOMP_KERNEL_FLAVOUR", "gpu");
    GBuffer gpu = composite(gpu_way, frame, camera, decals);
    return {std::move(cpu), std::move(gpu)};
}

// Every plane bit for bit; returns how many albedo samples the decals changed.
std::size_t expectIdentical(const GBuffer& input, const GBuffer& cpu, const GBuffer& gpu) {
    EXPECT_EQ(cpu.planes.size(), gpu.planes.size());
    for (const auto& [attribute, plane] : cpu.planes) {
        const auto& a = plane.samples;
        const auto& b = gpu.planes.at(attribute).samples;
        EXPECT_EQ(a.size(), b.size()) << attributeName(attribute);
        std::size_t differing = 0;
        for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
            differing += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
        EXPECT_EQ(differing, 0u) << attributeName(attribute) << " differs between the CPU and GPU builds";
    }
    const auto& before = input.planes.at(Attribute::Albedo).samples;
    const auto& after = cpu.planes.at(Attribute::Albedo).samples;
    std::size_t changed = 0;
    for (std::size_t i = 0; i < before.size(); ++i) changed += before[i] != after[i];
    return changed;
}

TEST(KernelFlavour, CpuDevicesBuildTheCpuFlavour) {
    const test::ScopedEnv options("DECALCOMP_CL_OPTIONS", nullptr);
    {
        const test::ScopedEnv unset("DECALCOMP_KERNEL_FLAVOUR", nullptr);
        EXPECT_EQ(buildOptions("cpu"), "-cl-std=CL1.2 -DDC_CPU_DEVICE");
        EXPECT_EQ(buildOptions("gpu"), "-cl-std=CL1.2");
        EXPECT_EQ(buildOptions("accelerator"), "-cl-std=CL1.2");
    }
    {
        const test::ScopedEnv gpu("DECALCOMP_KERNEL_FLAVOUR", "gpu");
        EXPECT_EQ(buildOptions("cpu"), "-cl-std=CL1.2");
    }
    {
        const test::ScopedEnv cpu("DECALCOMP_KERNEL_FLAVOUR", "cpu");
        EXPECT_EQ(buildOptions("gpu"), "-cl-std=CL1.2 -DDC_CPU_DEVICE");
    }
    const test::ScopedEnv bad("DECALCOMP_KERNEL_FLAVOUR", "scalar");
    try {
        buildOptions("cpu");
        ADD_FAILURE() << "a flavour that is neither cpu nor gpu was taken";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Usage);
        EXPECT_EQ(std::string(e.what()), "DECALCOMP_KERNEL_FLAVOUR=scalar: not a kernel flavour; cpu or gpu");
    }
}

// The demo scene rendered 4x finer and filtered down: silhouettes (averaged depths) and creases
// (short normals) whose taps split, decals with nearest and linear textures of a few pixels a texel.
TEST(KernelFlavour, AntialiasedFramesMatchTheGpuBuild) {
    constexpr int kWidth = 120, kHeight = 90, kFactor = 4;
    const Camera fine_camera = synth::demoCamera(kWidth * kFactor, kHeight * kFactor);
    const GBuffer fine =
        synth::render(synth::demoScene(), fine_camera, synth::RenderOptions{kWidth * kFactor, kHeight * kFactor});
    const Camera camera = synth::demoCamera(kWidth, kHeight);
    synth::ScatterOptions scatter;
    scatter.count = 120;
    scatter.min_size = 0.4;
    scatter.max_size = 1.2;
    scatter.texture_size = 16;
    const GBuffer point_frame = synth::render(synth::demoScene(), camera, synth::RenderOptions{kWidth, kHeight});
    const DecalScene decals = synth::scatterDecals(point_frame, camera, scatter);
    for (const bool fast : {true, false}) {
        const GBuffer frame = synth::filterDown(fine, kFactor, {PixelFilterType::BlackmanHarris, 3.0, fast});
        std::size_t creases = 0;
        const Plane& normal = frame.planes.at(Attribute::Normal);
        for (std::size_t i = 0; i < frame.pixelCount(); ++i) {
            const double len = std::hypot(normal.at(i, 0), normal.at(i, 1), normal.at(i, 2));
            creases += len > 0.0 && len < 0.995;
        }
        ASSERT_GT(creases, 50u) << "the frame should hold mixed normals";
        const auto [cpu, gpu] = bothFlavours(frame, camera, decals);
        EXPECT_GT(expectIdentical(frame, cpu, gpu), frame.pixelCount() / 10) << (fast ? "fast" : "taps");
    }
}

// Random frames: every kind (box, volume, frustum, cube), every depth convention, orthographic too.
TEST(KernelFlavour, RandomScenesOfEveryKindMatchTheGpuBuild) {
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
        test::RandomFrame f = test::makeRandomFrame(seed);
        f.gbuffer.pixel_filter = {PixelFilterType::BlackmanHarris, 3.0, seed % 2 == 1};
        const DecalScene decals = test::makeRandomDecals(f, seed, 200);
        const auto [cpu, gpu] = bothFlavours(f.gbuffer, f.camera, decals);
        EXPECT_GT(expectIdentical(f.gbuffer, cpu, gpu), f.gbuffer.pixelCount() / 20) << "seed " << seed;
    }
}

}  // namespace
}  // namespace decalcomp
