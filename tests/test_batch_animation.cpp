// Decals over time: lifetimes and fades, keyframed placement (translate/rotate/scale and matrix
// keys, linear and step), the scene-file keys and their errors.
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "decalcomp/decal.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

void expectMatrixNear(const glm::dmat4& a, const glm::dmat4& b, double tolerance = 1e-9) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "row " << r << " col " << c;
}

glm::dmat4 trs(glm::dvec3 t, double z_deg, glm::dvec3 s) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), t);
    m = glm::rotate(m, glm::radians(z_deg), glm::dvec3(0, 0, 1));
    return glm::scale(m, s);
}

TEST(DecalLifetime, AliveOnlyInsideInclusive) {
    Decal d;
    d.first_frame = 10;
    d.last_frame = 20;
    EXPECT_FALSE(decalAtFrame(d, 9));
    EXPECT_TRUE(decalAtFrame(d, 10));
    EXPECT_TRUE(decalAtFrame(d, 20));
    EXPECT_FALSE(decalAtFrame(d, 20.5));
    Decal open;
    open.first_frame = 5;  // no last frame: alive from 5 on
    EXPECT_FALSE(decalAtFrame(open, 4));
    EXPECT_TRUE(decalAtFrame(open, 1e6));
    EXPECT_TRUE(decalAtFrame(Decal{}, -1e6));  // static decals are always alive
}

TEST(DecalLifetime, FadesRampOverTheGivenFrames) {
    Decal d;
    d.opacity = 0.8f;
    d.first_frame = 10;
    d.last_frame = 30;
    d.fade_in_frames = 3;
    d.fade_out_frames = 1;
    const double expected_in[] = {0.25, 0.5, 0.75, 1.0, 1.0};
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(decalAtFrame(d, 10 + i)->opacity, 0.8 * expected_in[i], 1e-6) << i;
    EXPECT_NEAR(decalAtFrame(d, 29)->opacity, 0.8, 1e-6);
    EXPECT_NEAR(decalAtFrame(d, 30)->opacity, 0.4, 1e-6);
}

TEST(DecalKeyframes, TranslateRotateScaleInterpolate) {
    Decal d;
    d.keyframes = {{0.0, trs({0, 0, 0}, 0, {1, 1, 1})}, {10.0, trs({10, -4, 2}, 90, {3, 1, 1})}};
    d.world_matrix = d.keyframes[0].world_matrix;
    expectMatrixNear(decalAtFrame(d, 0)->world_matrix, d.keyframes[0].world_matrix);
    expectMatrixNear(decalAtFrame(d, 10)->world_matrix, d.keyframes[1].world_matrix);
    expectMatrixNear(decalAtFrame(d, 5)->world_matrix, trs({5, -2, 1}, 45, {2, 1, 1}));
    expectMatrixNear(decalAtFrame(d, 2.5)->world_matrix, trs({2.5, -1, 0.5}, 22.5, {1.5, 1, 1}));
    // Held before the first and after the last key.
    expectMatrixNear(decalAtFrame(d, -3)->world_matrix, d.keyframes[0].world_matrix);
    expectMatrixNear(decalAtFrame(d, 99)->world_matrix, d.keyframes[1].world_matrix);
}

TEST(DecalKeyframes, RotationTakesTheShortestArc) {
    Decal d;
    d.keyframes = {{0.0, trs({0, 0, 0}, 170, {1, 1, 1})}, {2.0, trs({0, 0, 0}, -170, {1, 1, 1})}};
    expectMatrixNear(decalAtFrame(d, 1)->world_matrix, trs({0, 0, 0}, 180, {1, 1, 1}));
}

TEST(DecalKeyframes, MirroredKeysStayMirrored) {
    Decal d;
    d.keyframes = {{0.0, trs({0, 0, 0}, 0, {-1, 1, 1})}, {4.0, trs({4, 0, 0}, 0, {-3, 1, 1})}};
    expectMatrixNear(decalAtFrame(d, 2)->world_matrix, trs({2, 0, 0}, 0, {-2, 1, 1}));
}

TEST(DecalKeyframes, StepHoldsThePreviousKey) {
    Decal d;
    d.keyframe_interpolation = KeyframeInterpolation::Step;
    d.keyframes = {{1.0, trs({0, 0, 0}, 0, {1, 1, 1})}, {5.0, trs({4, 0, 0}, 0, {1, 1, 1})},
                   {9.0, trs({8, 0, 0}, 0, {1, 1, 1})}};
    expectMatrixNear(decalAtFrame(d, 4.99)->world_matrix, d.keyframes[0].world_matrix);
    expectMatrixNear(decalAtFrame(d, 5)->world_matrix, d.keyframes[1].world_matrix);
    expectMatrixNear(decalAtFrame(d, 8)->world_matrix, d.keyframes[1].world_matrix);
}

TEST(DecalKeyframes, SceneAtFrameKeepsOrderTexturesAndDropsTheDead) {
    DecalScene scene;
    scene.textures.resize(2);
    scene.decals.resize(3);
    scene.decals[0].name = "a";
    scene.decals[1].name = "b";
    scene.decals[1].last_frame = 4;
    scene.decals[2].name = "c";
    const DecalScene at = sceneAtFrame(scene, 5);
    EXPECT_EQ(at.textures.size(), 2u);
    ASSERT_EQ(at.decals.size(), 2u);
    EXPECT_EQ(at.decals[0].name, "a");
    EXPECT_EQ(at.decals[1].name, "c");
    EXPECT_TRUE(isAnimated(scene));
    scene.decals.erase(scene.decals.begin() + 1);
    EXPECT_FALSE(isAnimated(scene));
}

// ---- scene files ----

std::string writeScene(const test::ScratchDir& dir, const std::string& decals) {
    test::writeSolidPng(dir.file("t.png"), 200, 10, 10);
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << "{\"decals\": [" << decals << "]}";
    return path;
}

TEST(SceneAnimation, KeysAreRead) {
    test::ScratchDir dir;
    const DecalScene scene = loadScene(writeScene(dir, R"(
      {"name": "m", "texture": "t.png", "frames": [2, 40], "fade_in": 3, "fade_out": 5,
       "keyframe_interpolation": "step",
       "keyframes": [{"frame": 2, "translate": [1, 2, 3], "rotate_deg": [0, 0, 90], "scale": 2},
                     {"frame": 10, "matrix": [[1,0,0,5],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},
                     {"frame": 12.5, "origin": [0, -5, 0], "target": [0, 0, 0], "up": [0, 0, 1], "size": 1}]},
      {"name": "s", "texture": "t.png", "frames": [null, 7], "translate": [0, 0, 1]})"));
    ASSERT_EQ(scene.decals.size(), 2u);
    const Decal& m = scene.decals[0];
    EXPECT_EQ(*m.first_frame, 2.0);
    EXPECT_EQ(*m.last_frame, 40.0);
    EXPECT_EQ(m.fade_in_frames, 3.0);
    EXPECT_EQ(m.fade_out_frames, 5.0);
    EXPECT_EQ(m.keyframe_interpolation, KeyframeInterpolation::Step);
    ASSERT_EQ(m.keyframes.size(), 3u);
    EXPECT_EQ(m.keyframes[2].frame, 12.5);
    expectMatrixNear(m.keyframes[0].world_matrix, trs({1, 2, 3}, 90, {2, 2, 2}));
    EXPECT_DOUBLE_EQ(m.keyframes[1].world_matrix[3][0], 5.0);
    expectMatrixNear(m.world_matrix, m.keyframes[0].world_matrix);  // what single-frame compositing sees
    const Decal& s = scene.decals[1];
    EXPECT_FALSE(s.first_frame);
    EXPECT_EQ(*s.last_frame, 7.0);
    EXPECT_TRUE(s.keyframes.empty());
    EXPECT_DOUBLE_EQ(s.world_matrix[3][2], 1.0);
}

struct AnimationErrorCase {
    const char* decal;
    const char* message;  // expected part of the error
};

class SceneAnimationErrors : public ::testing::TestWithParam<AnimationErrorCase> {};

TEST_P(SceneAnimationErrors, NameTheJsonPath) {
    test::ScratchDir dir;
    const std::string path = writeScene(dir, std::string("{\"texture\": \"t.png\", ") + GetParam().decal + "}");
    try {
        loadScene(path);
        ADD_FAILURE() << "accepted " << GetParam().decal;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_NE(std::string(e.what()).find(GetParam().message), std::string::npos) << e.what();
    }
}

const AnimationErrorCase kAnimationErrors[] = {
    {R"("translate": [0,0,0], "frames": [5, 1])", "decals[0].frames: first frame 5 is after last frame 1"},
    {R"("translate": [0,0,0], "frames": 5)", "decals[0].frames: expected [first, last]"},
    {R"("translate": [0,0,0], "frames": [1, "x"])", "decals[0].frames[1]: expected a number"},
    {R"("translate": [0,0,0], "fade_in": 2)", "decals[0].fade_in: needs the first frame"},
    {R"("translate": [0,0,0], "frames": [1, null], "fade_out": 2)", "decals[0].fade_out: needs the last frame"},
    {R"("translate": [0,0,0], "frames": [1, 9], "fade_in": -1)", "decals[0].fade_in: expected a number of frames >= 0"},
    {R"("translate": [0,0,0], "keyframes": [{"frame": 1, "translate": [0,0,0]}])",
     "decals[0]: give either a placement ('translate') or 'keyframes', not both"},
    {R"("keyframes": [])", "decals[0].keyframes: expected a non-empty array"},
    {R"("keyframes": [{"translate": [0,0,0]}])", "decals[0].keyframes[0]: missing 'frame'"},
    {R"("keyframes": [{"frame": 1}])", "decals[0].keyframes[0]: missing placement"},
    {R"("keyframes": [{"frame": 1, "translate": [0,0,0], "opacity": 1}])", "decals[0].keyframes[0].opacity: unknown key"},
    {R"("keyframes": [{"frame": 2, "translate": [0,0,0]}, {"frame": 2, "translate": [1,0,0]}])",
     "decals[0].keyframes[1].frame: 2 is not after the previous keyframe's 2"},
    {R"("keyframes": [{"frame": 1, "scale": 0}])", "decals[0].keyframes[0].scale: not invertible"},
    {R"("keyframes": [{"frame": 1, "scale": 1}, {"frame": 2, "scale": [-1, 1, 1]}])",
     "decals[0].keyframes[1]: mirrored where the previous keyframe is not"},
    {R"("keyframes": [{"frame": 1, "scale": 1}], "keyframe_interpolation": "cubic")",
     "decals[0].keyframe_interpolation: expected one of: linear, step (got 'cubic')"},
    {R"("translate": [0,0,0], "keyframe_interpolation": "step")", "decals[0].keyframe_interpolation: no 'keyframes'"},
    {R"("translate": [0,0,0], "keyframe": [])", "decals[0].keyframe: unknown key (did you mean 'keyframes'?)"},
};

INSTANTIATE_TEST_SUITE_P(Scene, SceneAnimationErrors, ::testing::ValuesIn(kAnimationErrors));

}  // namespace
}  // namespace decalcomp
