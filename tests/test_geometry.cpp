// Pixel geometry (decalcomp_geometry): the background rule, pixel centres and the point each pixel
// sees under every depth convention, against the generator's own position pass and the scalar
// reference's independent reconstruction.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "decalcomp/camera.hpp"
#include "decalcomp/geometry.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"

namespace decalcomp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Geometry, BackgroundDepthRule) {
    for (DepthConvention c : {DepthConvention::Planar, DepthConvention::Radial, DepthConvention::Position}) {
        for (double d : {kNaN, kInf, -kInf, 0.0, -1.0, kBackgroundDepth, 2e10})
            EXPECT_TRUE(isBackgroundDepth(c, false, d)) << d;
        for (double d : {1e-3, 1.0, 9.9e9}) EXPECT_FALSE(isBackgroundDepth(c, false, d)) << d;
    }
    for (double d : {kNaN, kInf, 1.0, 1.5, -0.1}) EXPECT_TRUE(isBackgroundDepth(DepthConvention::Ndc, false, d)) << d;
    for (double d : {0.0, 0.5, 0.999}) EXPECT_FALSE(isBackgroundDepth(DepthConvention::Ndc, false, d)) << d;
    for (double d : {kNaN, 0.0, -0.1, 1.5}) EXPECT_TRUE(isBackgroundDepth(DepthConvention::Ndc, true, d)) << d;
    for (double d : {1.0, 0.5, 1e-3}) EXPECT_FALSE(isBackgroundDepth(DepthConvention::Ndc, true, d)) << d;
}

TEST(Geometry, PixelCentresOverTheDisplayWindow) {
    GBuffer g;
    g.width = g.height = 2;
    g.display_width = g.display_height = 4;
    g.origin_x = 1;
    g.origin_y = 2;
    const glm::dvec2 ndc = pixelNdc(g, 0, 0);  // display pixel (1, 2): centre (1.5, 2.5)
    EXPECT_DOUBLE_EQ(ndc.x, -0.25);
    EXPECT_DOUBLE_EQ(ndc.y, -0.25);
    EXPECT_EQ(displayPixelToNdc(g, {0.0, 0.0}), glm::dvec2(-1.0, 1.0));  // top left corner
}

TEST(Geometry, DepthBeyondTheFarPlaneIsBackground) {
    GBuffer g;
    g.width = g.height = g.display_width = g.display_height = 1;
    g.planes[Attribute::Depth] = Plane{1, {50.0f}};
    Camera camera;
    camera.projection = perspectiveProjection(1.0, 1.0, 0.1, 100.0);
    ASSERT_TRUE(pixelCameraPoint(g, camera, 0, 0));
    EXPECT_NEAR(pixelCameraPoint(g, camera, 0, 0)->z, -50.0, 1e-9);
    g.planes[Attribute::Depth].samples[0] = 150.0f;
    EXPECT_FALSE(pixelCameraPoint(g, camera, 0, 0));
    EXPECT_TRUE(isGeometryPixel(g, 0));  // by the depth value alone, which needs no camera
}

struct Case {
    const char* name;
    DepthConvention depth;
    bool reversed_z = false, with_depth = true, orthographic = false;
};

class GeometryConventions : public ::testing::TestWithParam<Case> {};

// Every pixel: geometry and the reference agree on background, and on the point to double
// precision; the point is the generator's world position to float precision.
TEST_P(GeometryConventions, MatchesTheReferenceAndThePositionPass) {
    const Case c = GetParam();
    const int width = 96, height = 64;
    Camera camera = synth::demoCamera(width, height);
    if (c.orthographic) camera.projection = orthographicProjection(4.0, double(width) / height, 0.5, 60.0);
    synth::RenderOptions options{width, height};
    options.depth = c.depth;
    options.reversed_z = c.reversed_z;
    options.with_depth = c.with_depth;
    const GBuffer g = synth::render(synth::demoScene(), camera, options);
    const Plane& position = g.planes.at(Attribute::Position);
    int geometry_pixels = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const auto ours = pixelWorldPoint(g, camera, x, y);
            const auto oracle = reference::pixelWorldPoint(g, camera, x, y);
            ASSERT_EQ(bool(ours), bool(oracle)) << c.name << " pixel " << x << "," << y;
            const std::size_t i = std::size_t(y) * width + x;
            EXPECT_EQ(bool(ours), isGeometryPixel(g, i)) << c.name << " pixel " << x << "," << y;
            if (!ours) continue;
            ++geometry_pixels;
            EXPECT_LT(glm::length(*ours - *oracle), 1e-9 * (1.0 + glm::length(*oracle))) << c.name;
            const glm::dvec3 truth(position.at(i, 0), position.at(i, 1), position.at(i, 2));
            const double tolerance = c.depth == DepthConvention::Ndc ? 2e-2 : 1e-4;  // float ndc depth
            EXPECT_LT(glm::length(*ours - truth), tolerance * (1.0 + glm::length(truth))) << c.name;
        }
    EXPECT_GT(geometry_pixels, width * height / 2) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Conventions, GeometryConventions,
                         ::testing::Values(Case{"planar", DepthConvention::Planar},
                                           Case{"radial", DepthConvention::Radial},
                                           Case{"ndc", DepthConvention::Ndc},
                                           Case{"ndc_reversed", DepthConvention::Ndc, true},
                                           Case{"position", DepthConvention::Position},
                                           Case{"position_only", DepthConvention::Position, false, false},
                                           Case{"planar_ortho", DepthConvention::Planar, false, true, true},
                                           Case{"radial_ortho", DepthConvention::Radial, false, true, true},
                                           Case{"ndc_ortho", DepthConvention::Ndc, false, true, true}),
                         [](const ::testing::TestParamInfo<Case>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace decalcomp
