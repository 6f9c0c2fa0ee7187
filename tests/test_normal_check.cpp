// checkNormalEncoding: which space and encoding a normal pass uses, judged against the surfaces
// the depth pass describes; --normals constraints keep the fixed part out of the competition.
#include <gtest/gtest.h>

#include "decalcomp/normal_check.hpp"
#include "decalcomp/synth.hpp"

namespace decalcomp {
namespace {

struct Frame {
    GBuffer gbuffer;
    Camera camera;
};

// The demo scene (floor, wall, sphere, box) with world-space signed normals.
Frame demoFrame() {
    Frame f;
    f.camera = synth::demoCamera(160, 90);
    f.gbuffer = synth::render(synth::demoScene(), f.camera, synth::RenderOptions{160, 90});
    return f;
}

// Rewrites the normal plane as camera-space, packed normals (RenderMan-like Nn, n * 0.5 + 0.5).
void toCameraPacked(Frame& f) {
    const glm::dmat3 rotation(f.camera.world_to_camera);
    Plane& n = f.gbuffer.planes.at(Attribute::Normal);
    for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
        const glm::dvec3 c = rotation * glm::dvec3(n.at(i, 0), n.at(i, 1), n.at(i, 2));
        for (int k = 0; k < 3; ++k) n.at(i, k) = float(c[k] * 0.5 + 0.5);
    }
}

TEST(NormalCheck, WorldSignedNormalsAreRecognised) {
    const Frame f = demoFrame();
    const NormalCheck check = checkNormalEncoding(f.gbuffer, f.camera);
    ASSERT_TRUE(check.performed) << check.summary();
    ASSERT_TRUE(check.verdict) << check.summary();
    EXPECT_EQ(check.verdict->space, NormalSpace::World);
    EXPECT_FALSE(check.verdict->packed);
    EXPECT_GT(check.agreement[0][0], 0.99);
}

TEST(NormalCheck, AWrongProfileIsCorrectedToCameraPacked) {
    Frame f = demoFrame();
    toCameraPacked(f);  // the G-buffer still claims world/signed, as a wrong profile would
    const NormalCheck check = checkNormalEncoding(f.gbuffer, f.camera);
    ASSERT_TRUE(check.verdict) << check.summary();
    EXPECT_EQ(check.verdict->space, NormalSpace::Camera);
    EXPECT_TRUE(check.verdict->packed);
    EXPECT_GT(check.agreement[1][1], 0.99);
}

TEST(NormalCheck, FixedPartsDoNotCompete) {
    Frame f = demoFrame();
    toCameraPacked(f);
    // --normals camera: the space is fixed, the encoding is still found
    NormalConstraints space_fixed;
    space_fixed.space = NormalSpace::Camera;
    const NormalCheck by_space = checkNormalEncoding(f.gbuffer, f.camera, space_fixed);
    ASSERT_TRUE(by_space.verdict) << by_space.summary();
    EXPECT_EQ(by_space.verdict->space, NormalSpace::Camera);
    EXPECT_TRUE(by_space.verdict->packed);
    // --normals world,signed on these normals: the one reading left does not fit, so no verdict
    NormalConstraints both_fixed;
    both_fixed.space = NormalSpace::World;
    both_fixed.packed = false;
    const NormalCheck fixed = checkNormalEncoding(f.gbuffer, f.camera, both_fixed);
    EXPECT_TRUE(fixed.performed);
    EXPECT_FALSE(fixed.verdict) << fixed.summary();
    // an encoding fixed to signed: only world/signed and camera/signed compete
    NormalConstraints signed_fixed;
    signed_fixed.packed = false;
    const NormalCheck by_encoding = checkNormalEncoding(f.gbuffer, f.camera, signed_fixed);
    EXPECT_TRUE(!by_encoding.verdict || !by_encoding.verdict->packed) << by_encoding.summary();
}

TEST(NormalCheck, NoNormalPassIsNotPerformed) {
    Frame f = demoFrame();
    f.gbuffer.planes.erase(Attribute::Normal);
    const NormalCheck check = checkNormalEncoding(f.gbuffer, f.camera);
    EXPECT_FALSE(check.performed);
    EXPECT_FALSE(check.verdict);
}

}  // namespace
}  // namespace decalcomp
