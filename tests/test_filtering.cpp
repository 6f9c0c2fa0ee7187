// Texture shapes, 3D mip chains and seamless cube filtering, on the scalar reference
// (tests/test_kernels.cpp checks that the kernels agree with it; tests/test_mip.cpp measures
// volume mips against supersampling).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "decalcomp/decal.hpp"
#include "decalcomp/reference.hpp"

namespace decalcomp {
namespace {

Texture2D randomVolume(int w, int h, int d, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Texture2D t;
    t.width = w;
    t.height = h;
    t.depth = d;
    t.shape = TextureShape::Volume;
    for (int i = 0; i < w * h * d; ++i) t.texels.emplace_back(u(rng), u(rng), u(rng), u(rng));
    return t;
}

glm::vec4 voxel(const Texture2D& t, int i, int j, int k) {
    return t.texels[(std::size_t(k) * t.height + std::size_t(j)) * t.width + std::size_t(i)];
}

glm::dvec4 mean(const Texture2D& t) {
    glm::dvec4 sum(0.0);
    for (const glm::vec4& v : t.texels) sum += glm::dvec4(v);
    return sum / double(t.texels.size());
}

TEST(TextureShape, LayoutsSetTheShape) {
    Texture2D strip;
    strip.width = 2;
    strip.height = 6;
    strip.texels.assign(12, glm::vec4(1.0f));
    EXPECT_EQ(strip.shape, TextureShape::Flat);
    EXPECT_EQ(volumeFromStrip(strip).shape, TextureShape::Volume);
    Texture2D cube_strip;
    cube_strip.width = 12;
    cube_strip.height = 2;
    cube_strip.texels.assign(24, glm::vec4(1.0f));
    EXPECT_EQ(cubeFromStrip(cube_strip).shape, TextureShape::Cube);
    Texture2D face;
    face.width = face.height = 2;
    face.texels.assign(4, glm::vec4(1.0f));
    EXPECT_EQ(cubeFromFaces(std::vector<Texture2D>(6, face)).shape, TextureShape::Cube);
}

TEST(MipChain, VolumesHalveInAllThreeAxesDownTo1x1x1) {
    const auto chain = mipChain(randomVolume(8, 4, 16, 1));
    const int sizes[][3] = {{8, 4, 16}, {4, 2, 8}, {2, 1, 4}, {1, 1, 2}, {1, 1, 1}};
    ASSERT_EQ(chain.size(), 5u);
    for (std::size_t l = 0; l < chain.size(); ++l) {
        EXPECT_EQ(chain[l].width, sizes[l][0]) << l;
        EXPECT_EQ(chain[l].height, sizes[l][1]) << l;
        EXPECT_EQ(chain[l].depth, sizes[l][2]) << l;
        EXPECT_EQ(chain[l].shape, TextureShape::Volume);
        EXPECT_EQ(chain[l].texels.size(), std::size_t(sizes[l][0]) * sizes[l][1] * sizes[l][2]);
    }
    // the same texels as a flat stack of layers keep their 16 layers
    Texture2D layers = chain[0];
    layers.shape = TextureShape::Flat;
    const auto flat = mipChain(layers);
    ASSERT_EQ(flat.size(), 4u);
    EXPECT_EQ(flat.back().width, 1);
    EXPECT_EQ(flat.back().height, 1);
    EXPECT_EQ(flat.back().depth, 16);
}

TEST(MipChain, EvenVolumesAverage2x2x2) {
    const Texture2D t = randomVolume(4, 6, 2, 2);
    const auto chain = mipChain(t);
    const Texture2D& l1 = chain[1];
    ASSERT_EQ(l1.depth, 1);
    for (int j = 0; j < l1.height; ++j)
        for (int i = 0; i < l1.width; ++i) {
            glm::dvec4 sum(0.0);
            for (int c = 0; c < 8; ++c) sum += glm::dvec4(voxel(t, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), c >> 2));
            for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(voxel(l1, i, j, 0)[ch], sum[ch] / 8.0, 1e-6) << i << "," << j;
        }
    for (std::size_t l = 1; l < chain.size(); ++l)
        for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(mean(chain[l])[ch], mean(t)[ch], 1e-5) << "level " << l;
}

// Odd sizes: floor(n / 2) texels, each the box average of the region it covers, the boundary texel
// shared by overlap. 5 -> 2 covers [0, 2.5) and [2.5, 5); 3 -> 1 covers all; 7 -> 3 covers thirds.
TEST(MipChain, OddVolumesShareBoundaryTexelsAndKeepTheMean) {
    const Texture2D t = randomVolume(5, 3, 7, 3);
    const auto chain = mipChain(t);
    const Texture2D& l1 = chain[1];
    ASSERT_EQ(l1.width, 2);
    ASSERT_EQ(l1.height, 1);
    ASSERT_EQ(l1.depth, 3);
    const double wx[2][5] = {{1, 1, 0.5, 0, 0}, {0, 0, 0.5, 1, 1}};
    const double wz[3][7] = {
        {1, 1, 1.0 / 3, 0, 0, 0, 0}, {0, 0, 2.0 / 3, 1, 2.0 / 3, 0, 0}, {0, 0, 0, 0, 1.0 / 3, 1, 1}};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 2; ++i) {
            glm::dvec4 sum(0.0);
            double weight = 0;
            for (int z = 0; z < 7; ++z)
                for (int y = 0; y < 3; ++y)
                    for (int x = 0; x < 5; ++x) {
                        sum += wx[i][x] * wz[k][z] * glm::dvec4(voxel(t, x, y, z));
                        weight += wx[i][x] * wz[k][z];
                    }
            for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(voxel(l1, i, 0, k)[ch], sum[ch] / weight, 1e-6) << i << "," << k;
        }
    ASSERT_EQ(chain.size(), 3u);  // 5x3x7, 2x1x3, 1x1x1
    for (std::size_t l = 1; l < chain.size(); ++l)
        for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(mean(chain[l])[ch], mean(t)[ch], 1e-5) << "level " << l;
}

// ---- seamless cube filtering

const glm::dvec3 kFaceColours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};

// The direction through face coordinates (u, v) in [-1, 1] of a face, found by searching the
// cube-map rule itself: (s, t) = ((u + 1) / 2, (v + 1) / 2).
glm::dvec3 faceDirection(int face, double u, double v) {
    // the rule's own axes: the face's major axis and where s and t grow, read off cubeLookup
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::dvec3 major = axes[face];
    glm::dvec3 s_axis(0.0), t_axis(0.0);
    for (const glm::dvec3& a : axes) {
        if (std::abs(glm::dot(a, major)) > 0.5) continue;
        const reference::CubeLookup c = reference::cubeLookup(major + 0.5 * a);
        if (c.s > 0.6) s_axis = a;
        if (c.t > 0.6) t_axis = a;
    }
    return glm::normalize(major + u * s_axis + v * t_axis);
}

// A cube whose texels hold `f(direction of the texel centre)`.
template <class F>
Texture2D cubeOf(int n, F f) {
    Texture2D cube;
    cube.width = cube.height = n;
    cube.depth = 6;
    cube.shape = TextureShape::Cube;
    for (int face = 0; face < 6; ++face)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                cube.texels.push_back(
                    glm::vec4(f(face, faceDirection(face, (2.0 * i + 1) / n - 1, (2.0 * j + 1) / n - 1))));
    return cube;
}

glm::dvec4 smoothColour(const glm::dvec3& d) { return glm::dvec4(0.5 + 0.5 * glm::normalize(d), 1.0); }

// What the lookup was before: bilinear within the face, clamped to its edge.
glm::dvec4 clampedCubeLookup(const Texture2D& cube, const glm::dvec3& d) {
    const reference::CubeLookup c = reference::cubeLookup(d);
    Texture2D face;
    face.width = face.height = cube.width;
    const auto first = cube.texels.begin() + std::ptrdiff_t(c.face) * cube.width * cube.height;
    face.texels.assign(first, first + cube.width * cube.height);
    return reference::sampleTexture(face, c.s, c.t, TextureFilter::Linear);
}

struct SeamErrors {
    double seamless_rms = 0, seamless_max = 0, clamped_rms = 0, clamped_max = 0;
};

enum class Near { EdgeMiddle, Edge, Corner };

// Errors against the analytic colour at directions whose face coordinates lie within half a
// texel of an edge, where a bilinear tap leaves the face: along the middle half of the edges,
// along whole edges, or within half a texel of two edges (corners).
SeamErrors seamErrors(const Texture2D& cube, Near where, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> along(where == Near::EdgeMiddle ? -0.5 : -1.0,
                                                 where == Near::EdgeMiddle ? 0.5 : 1.0);
    std::uniform_real_distribution<double> edge(1.0 - 1.0 / cube.width, 1.0);
    SeamErrors e;
    const int count = 20000;
    for (int n = 0; n < count; ++n) {
        const int face = int(rng() % 6);
        const double su = rng() % 2 ? 1.0 : -1.0, sv = rng() % 2 ? 1.0 : -1.0;
        double u = su * edge(rng), v = where == Near::Corner ? sv * edge(rng) : along(rng);
        if (rng() % 2) std::swap(u, v);
        const glm::dvec3 d = faceDirection(face, u, v);
        const glm::dvec4 truth = smoothColour(d);
        const double a = glm::length(glm::dvec3(reference::sampleCube(cube, d, TextureFilter::Linear) - truth));
        const double b = glm::length(glm::dvec3(clampedCubeLookup(cube, d) - truth));
        e.seamless_rms += a * a;
        e.clamped_rms += b * b;
        e.seamless_max = std::max(e.seamless_max, a);
        e.clamped_max = std::max(e.clamped_max, b);
    }
    e.seamless_rms = std::sqrt(e.seamless_rms / count);
    e.clamped_rms = std::sqrt(e.clamped_rms / count);
    return e;
}

// The largest jump of a lookup across an edge: just inside one face against just inside the next.
template <class Lookup>
double largestSeamStep(Lookup lookup, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> along(-1.0, 1.0);
    double step = 0;
    for (int n = 0; n < 5000; ++n) {
        const int face = int(rng() % 6);
        const double su = rng() % 2 ? 1.0 : -1.0, v = along(rng);
        const bool swap = rng() % 2;
        auto at = [&](double u) { return swap ? faceDirection(face, v, u) : faceDirection(face, u, v); };
        step = std::max(step, glm::length(glm::dvec3(lookup(at(su * (1.0 - 1e-9))) - lookup(at(su * (1.0 + 1e-9))))));
    }
    return step;
}

// 16x16 faces of 0.5 + 0.5 normalize(direction); errors are RMS / max of the RGB error length.
// Measured: interior (a texel or more from every edge) 0.0009 RMS; middle half of the edges
// seamless 0.0017 / 0.0047 against clamped 0.0093 / 0.0161; whole edges 0.0028 / 0.0073 against
// 0.0092 / 0.0161; corners 0.0032 / 0.0073 against 0.0099 / 0.0153; the largest step across an
// edge 5e-10 seamless (continuous) against 0.032 clamped. Seamless taps read the neighbour face's nearest
// texel, whose centre sits up to half a texel along the edge from where the tap would be (the
// faces' grids meet at an angle), so near corners the error stays first order, a third of clamped.
TEST(CubeSeams, SmoothFunctionIsReconstructedAcrossEdgesAndCorners) {
    const int n = 16;
    const Texture2D cube = cubeOf(n, [](int, const glm::dvec3& d) { return smoothColour(d); });
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> inside(-1.0 + 2.0 / n, 1.0 - 2.0 / n);
    double interior = 0;
    for (int k = 0; k < 20000; ++k) {
        const glm::dvec3 d = faceDirection(int(rng() % 6), inside(rng), inside(rng));
        interior += std::pow(
            glm::length(glm::dvec3(reference::sampleCube(cube, d, TextureFilter::Linear) - smoothColour(d))), 2);
    }
    interior = std::sqrt(interior / 20000);
    const SeamErrors middle = seamErrors(cube, Near::EdgeMiddle, 6), edges = seamErrors(cube, Near::Edge, 7),
                     corners = seamErrors(cube, Near::Corner, 8);
    const double step_seamless =
        largestSeamStep([&](const glm::dvec3& d) { return reference::sampleCube(cube, d, TextureFilter::Linear); }, 9);
    const double step_clamped = largestSeamStep([&](const glm::dvec3& d) { return clampedCubeLookup(cube, d); }, 9);
    std::printf("interior RMS %.4f\n", interior);
    for (const auto& [name, e] :
         {std::pair{"edge middles", middle}, std::pair{"edges", edges}, std::pair{"corners", corners}})
        std::printf("%s: seamless RMS %.4f max %.4f, clamped RMS %.4f max %.4f\n", name, e.seamless_rms, e.seamless_max,
                    e.clamped_rms, e.clamped_max);
    std::printf("largest step across an edge: seamless %.2g, clamped %.4f\n", step_seamless, step_clamped);
    EXPECT_LT(middle.seamless_rms, 0.2 * middle.clamped_rms);
    EXPECT_LT(edges.seamless_rms, 0.4 * edges.clamped_rms);
    EXPECT_LT(corners.seamless_rms, 0.4 * corners.clamped_rms);
    EXPECT_LT(edges.seamless_max, 0.6 * edges.clamped_max);
    EXPECT_LT(corners.seamless_max, 0.6 * corners.clamped_max);
    EXPECT_LT(step_seamless, 1e-6);
    EXPECT_GT(step_clamped, 0.005);
}

// One colour per face: right on an edge the two faces' colours blend half and half, a quarter
// texel inside the face 3/4 : 1/4, and at a cube corner the three faces' colours a third each.
TEST(CubeSeams, ConstantFacesBlendAtTheSeam) {
    const int n = 4;
    const Texture2D cube = cubeOf(n, [](int face, const glm::dvec3&) { return glm::dvec4(kFaceColours[face], 1.0); });
    auto expectColour = [&](const glm::dvec3& d, const glm::dvec3& want) {
        const glm::dvec4 got = reference::sampleCube(cube, d, TextureFilter::Linear);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], want[c], 1e-9) << "direction " << d.x << "," << d.y << "," << d.z;
    };
    // +X (face 0) meets +Z (face 4) along x = z; +X meets -Y (face 3) along x = -y
    expectColour({1.0, 0.3, 1.0}, 0.5 * (kFaceColours[0] + kFaceColours[4]));
    expectColour({1.0, -1.0, -0.2}, 0.5 * (kFaceColours[0] + kFaceColours[3]));
    // a quarter texel inside +X from the +Z edge: s = 0.25 / n
    const double u = -1.0 + 0.5 / n;
    expectColour({1.0, 0.3, -u}, 0.75 * kFaceColours[0] + 0.25 * kFaceColours[4]);
    // the corner of +X, +Y, +Z
    expectColour({1.0, 1.0, 1.0}, (kFaceColours[0] + kFaceColours[2] + kFaceColours[4]) / 3.0);
    // nearest filtering stays within the face
    const glm::dvec4 nearest = reference::sampleCube(cube, {1.0, 0.3, 0.999}, TextureFilter::Nearest);
    EXPECT_EQ(glm::dvec3(nearest), kFaceColours[0]);
}

}  // namespace
}  // namespace decalcomp
