// Cameras solved from the position pass (perspective with lens shift, orthographic, ndc depth),
// refusals (scrambled positions, flat scenes), the planar/radial depth check, and camera sources
// through the command line (header, sidecar, solve, singular header matrices).
#include <gtest/gtest.h>

#include <OpenEXR/ImfMatrixAttribute.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "decalcomp/camera.hpp"
#include "decalcomp/camera_solve.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/depth_check.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/sequence_conventions.hpp"
#include "decalcomp/synth.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;
using test::shellQuote;

struct Generated {
    ExrImage image;
    ChannelMapping mapping;
    GBuffer gbuffer;
    Camera truth;  // the generator's sidecar
};

Generated generate(const ScratchDir& dir, const std::string& name, const std::string& arguments,
                   const MappingOptions& options = {}) {
    const std::string exr = dir.file(name + ".exr");
    const auto r = test::runGenerator(arguments, exr, dir.file(name + ".json"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    Generated g;
    g.image = readExr(exr);
    g.mapping = mapChannels(g.image, options);
    g.gbuffer = extractGBuffer(g.image, g.mapping);
    g.truth = loadCameraJson(dir.file(name + ".json"));
    return g;
}

std::string solveError(const GBuffer& g) {
    try {
        solveCamera(g, "frame.exr");
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        return e.what();
    }
    ADD_FAILURE() << "expected the solve to be refused";
    return {};
}

void expectNear(const glm::dmat4& got, const glm::dmat4& want, double tolerance, const char* what) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(got[c][r], want[c][r], tolerance) << what << " row " << r << " col " << c;
}

// x, y, w rows of the projection (the z row depends on the near/far rule).
void expectSameXYW(const glm::dmat4& got, const glm::dmat4& want, double tolerance) {
    for (int c = 0; c < 4; ++c)
        for (int r : {0, 1, 3}) EXPECT_NEAR(got[c][r], want[c][r], tolerance) << "projection row " << r << " col " << c;
}

TEST(CameraSolve, PerspectiveWithLensShiftIsRecovered) {
    ScratchDir dir;
    const Generated g = generate(dir, "shift", "--width 96 --height 64 --naming generic --depth planar --lens-shift 0.12,-0.07");
    CameraSolveReport report;
    const Camera solved = solveCamera(g.gbuffer, "shift.exr", &report);
    EXPECT_FALSE(report.orthographic);
    EXPECT_FALSE(report.mirrored);
    EXPECT_EQ(report.outliers, 0u);
    EXPECT_GT(report.points, g.gbuffer.pixelCount() * 9 / 10);
    EXPECT_LT(report.max_px, 0.01);
    EXPECT_LT(report.rms_px, 0.01);
    EXPECT_LT(reprojectionError(g.gbuffer, solved).max_px, 0.01);
    expectNear(solved.world_to_camera, g.truth.world_to_camera, 1e-4, "world_to_camera");
    expectSameXYW(solved.projection, g.truth.projection, 1e-4);
    EXPECT_NEAR(solved.projection[2][0], 0.24, 1e-4) << "lens shift x";
    EXPECT_NEAR(solved.projection[2][1], -0.14, 1e-4) << "lens shift y";
    // Near/far from the depth range: every pixel lies between them.
    double lo = 1e300, hi = 0;
    for (std::size_t i = 0; i < g.gbuffer.pixelCount(); ++i) {
        lo = std::min(lo, double(g.gbuffer.planes.at(Attribute::Depth).at(i, 0)));
        hi = std::max(hi, double(g.gbuffer.planes.at(Attribute::Depth).at(i, 0)));
    }
    EXPECT_NEAR(solved.nearPlane(), 0.5 * lo, 1e-3 * lo);
    EXPECT_NEAR(solved.farPlane(), 2.0 * hi, 1e-3 * hi);
    EXPECT_NE(solved.source.find("solved from the position pass"), std::string::npos) << solved.source;
    EXPECT_NE(report.summary().find("perspective, reprojection RMS"), std::string::npos) << report.summary();
}

// The real Blender 3.4 render (no camera in its header): the solve finds camera.json's camera.
TEST(CameraSolve, BlenderSampleRecoversItsCamera) {
    const std::string path = test::dataPath("blender/gbuffer.exr"), camera_path = test::dataPath("blender/camera.json");
    if (!fs::exists(path) || !fs::exists(camera_path)) GTEST_SKIP() << "Blender sample absent";
    const ExrImage image = readExr(path);
    const GBuffer g = extractGBuffer(image, mapChannels(image, MappingOptions{}));
    const Camera truth = loadCameraJson(camera_path);
    CameraSolveReport report;
    const Camera solved = solveCamera(g, path, &report);
    EXPECT_FALSE(report.orthographic);
    EXPECT_EQ(report.outliers, 0u);
    EXPECT_LT(report.max_px, 0.01);
    expectNear(solved.world_to_camera, truth.world_to_camera, 1e-4, "world_to_camera");
    expectSameXYW(solved.projection, truth.projection, 1e-4);
    const DepthCheck check = checkDepthConvention(g, solved);
    ASSERT_TRUE(check.verdict.has_value()) << check.summary();
    EXPECT_EQ(*check.verdict, DepthConvention::Planar) << "Cycles' Depth pass is planar";
}

TEST(CameraSolve, OrthographicIsDetectedAndRecovered) {
    ScratchDir dir;
    const Generated g = generate(dir, "ortho", "--width 80 --height 60 --naming generic --depth planar --ortho 3.5");
    ASSERT_TRUE(g.truth.isOrthographic());
    CameraSolveReport report;
    const Camera solved = solveCamera(g.gbuffer, "ortho.exr", &report);
    EXPECT_TRUE(report.orthographic);
    EXPECT_TRUE(solved.isOrthographic());
    EXPECT_FALSE(report.mirrored);
    EXPECT_LT(report.max_px, 0.01);
    EXPECT_LT(reprojectionError(g.gbuffer, solved).max_px, 0.01);
    // The planar depth pass fixes the position along the view axis too.
    expectNear(solved.world_to_camera, g.truth.world_to_camera, 1e-4, "world_to_camera");
    expectSameXYW(solved.projection, g.truth.projection, 1e-5);
}

TEST(CameraSolve, NdcDepthGivesNearAndFar) {
    ScratchDir dir;
    MappingOptions ndc;
    ndc.depth_convention = DepthConvention::Ndc;
    const Generated g = generate(dir, "ndc", "--width 64 --height 48 --naming generic --depth ndc", ndc);
    CameraSolveReport report;
    const Camera solved = solveCamera(g.gbuffer, "ndc.exr", &report);
    EXPECT_LT(report.max_px, 0.01);
    EXPECT_NEAR(solved.nearPlane(), g.truth.nearPlane(), 1e-3 * g.truth.nearPlane());
    EXPECT_NEAR(solved.farPlane(), g.truth.farPlane(), 2e-2 * g.truth.farPlane());
    EXPECT_NE(report.near_far_rule.find("ndc depth pass"), std::string::npos) << report.near_far_rule;
}

TEST(CameraSolve, ReversedZOrthographicNdc) {
    ScratchDir dir;
    MappingOptions ndc;
    ndc.depth_convention = DepthConvention::Ndc;
    ndc.reversed_z = true;
    const Generated g =
        generate(dir, "rz", "--width 64 --height 48 --naming generic --depth ndc --reversed-z --ortho 3", ndc);
    CameraSolveReport report;
    const Camera solved = solveCamera(g.gbuffer, "rz.exr", &report);
    EXPECT_TRUE(report.orthographic);
    EXPECT_FALSE(report.mirrored) << "reversed-Z must not flip the view axis";
    EXPECT_LT(report.max_px, 0.01);
    // The ndc values themselves come back through the solved projection.
    const Plane& depth = g.gbuffer.planes.at(Attribute::Depth);
    const Plane& position = g.gbuffer.planes.at(Attribute::Position);
    double worst = 0.0;
    for (std::size_t i = 0; i < g.gbuffer.pixelCount(); ++i) {
        const glm::dvec4 clip =
            solved.projection * solved.world_to_camera *
            glm::dvec4(position.at(i, 0), position.at(i, 1), position.at(i, 2), 1.0);
        const double d = 1.0 - (clip.z / clip.w + 1.0) * 0.5;
        worst = std::max(worst, std::abs(d - depth.at(i, 0)));
    }
    EXPECT_LT(worst, 1e-4);
}

TEST(CameraSolve, ScrambledPositionsAreRefused) {
    ScratchDir dir;
    Generated g = generate(dir, "scrambled", "--width 64 --height 48 --naming generic --depth planar");
    Plane& position = g.gbuffer.planes.at(Attribute::Position);
    std::mt19937 rng(7);
    for (std::size_t i = g.gbuffer.pixelCount() - 1; i > 0; --i) {
        const std::size_t j = rng() % (i + 1);
        for (int c = 0; c < 3; ++c) std::swap(position.at(i, c), position.at(j, c));
    }
    const std::string message = solveError(g.gbuffer);
    EXPECT_EQ(message.rfind("frame.exr: cannot solve the camera from the position pass: reprojection error too "
                            "large: RMS ",
                            0),
              0u)
        << message;
    EXPECT_NE(message.find("px"), std::string::npos);
    EXPECT_NE(message.find("--camera"), std::string::npos);
}

TEST(CameraSolve, SlightNoiseIsToleratedAndReported) {
    ScratchDir dir;
    Generated g = generate(dir, "noisy", "--width 64 --height 48 --naming generic --depth planar");
    // A few "antialiased edge" pixels far off their pixel: left out of the fit, counted.
    Plane& position = g.gbuffer.planes.at(Attribute::Position);
    for (std::size_t i = 0; i < g.gbuffer.pixelCount(); i += 97)
        for (int c = 0; c < 3; ++c) position.at(i, c) *= 0.5f;
    CameraSolveReport report;
    const Camera solved = solveCamera(g.gbuffer, "noisy.exr", &report);
    EXPECT_GT(report.outliers, 0u);
    EXPECT_LT(report.max_px, 0.01) << "the inliers still fit exactly";
    EXPECT_GT(report.max_all_px, 1.0);
    expectNear(solved.world_to_camera, g.truth.world_to_camera, 1e-3, "world_to_camera");
    EXPECT_NE(report.summary().find("outliers"), std::string::npos);
}

TEST(CameraSolve, FlatGeometryIsRefused) {
    synth::Scene scene;
    scene.materials = {{}};
    scene.planes = {{{0, 0, 0}, {0, 0, 1}, 0}};
    Camera camera;
    camera.world_to_camera = lookAt({0.5, -4.0, 3.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
    camera.projection = perspectiveProjection(0.8, 1.5, 0.1, 100.0);
    synth::RenderOptions options;
    options.width = 48;
    options.height = 32;
    const GBuffer g = synth::render(scene, camera, options);
    const std::string message = solveError(g);
    EXPECT_NE(message.find("flat"), std::string::npos) << message;
}

TEST(CameraSolve, TooFewPixelsOrNoPositionPass) {
    GBuffer g;
    g.width = g.display_width = 4;
    g.height = g.display_height = 2;
    EXPECT_NE(solveError(g).find("no position pass"), std::string::npos);
    g.planes[Attribute::Position] = Plane{3, std::vector<float>(24, std::nanf(""))};
    EXPECT_NE(solveError(g).find("0 valid pixels"), std::string::npos);
}

// ---- planar or radial ----

TEST(DepthCheck, TellsPlanarFromRadial) {
    ScratchDir dir;
    for (const char* convention : {"planar", "radial"}) {
        const Generated g =
            generate(dir, convention, std::string("--width 64 --height 48 --naming generic --depth ") + convention);
        EXPECT_EQ(g.gbuffer.depth_convention, DepthConvention::Planar) << "the profile's default";
        const DepthCheck check = checkDepthConvention(g.gbuffer, g.truth);
        ASSERT_TRUE(check.performed) << check.reason;
        ASSERT_TRUE(check.verdict.has_value()) << check.summary();
        EXPECT_EQ(depthConventionName(*check.verdict), std::string(convention));
        EXPECT_NE(check.summary().find("planar median"), std::string::npos);

        // The pipeline adopts the verdict unless --depth was explicit.
        GBuffer gbuffer = g.gbuffer;
        ChannelMapping mapping = g.mapping;
        settleDepthConvention(gbuffer, mapping, g.truth);
        EXPECT_EQ(depthConventionName(gbuffer.depth_convention), std::string(convention));
        EXPECT_EQ(depthConventionName(mapping.depth_convention), std::string(convention));

        MappingOptions explicit_planar;
        explicit_planar.depth_convention = DepthConvention::Planar;
        ChannelMapping forced = mapChannels(g.image, explicit_planar);
        GBuffer forced_gbuffer = extractGBuffer(g.image, forced);
        settleDepthConvention(forced_gbuffer, forced, g.truth);
        EXPECT_EQ(forced_gbuffer.depth_convention, DepthConvention::Planar) << "explicit --depth wins";
    }
}

TEST(DepthCheck, NotPerformedWithoutAPositionPassOrForOrthographic) {
    ScratchDir dir;
    const Generated ortho = generate(dir, "o", "--width 32 --height 24 --naming generic --ortho 3");
    EXPECT_FALSE(checkDepthConvention(ortho.gbuffer, ortho.truth).performed);
    const Generated plain = generate(dir, "p", "--width 32 --height 24 --naming generic --no-position");
    const DepthCheck check = checkDepthConvention(plain.gbuffer, plain.truth);
    EXPECT_FALSE(check.performed);
    EXPECT_NE(check.summary().find("needs a depth and a position pass"), std::string::npos);
}

// ---- camera sources through the command line ----

std::vector<float> albedoOf(const std::string& path) {
    const ExrImage image = readExr(path);
    const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    return extractGBuffer(image, mapping).planes.at(Attribute::Albedo).samples;
}

TEST(CameraSolve, CompositeWithASolvedCameraMatchesTheSidecar) {
    ScratchDir dir;
    const std::string exr = dir.file("in.exr");
    ASSERT_EQ(test::runCommand(shellQuote(DECALCOMP_GEN) + " --width 160 --height 120 --naming generic -o " +
                               shellQuote(exr) + " --camera " + shellQuote(dir.file("cam.json")))
                  .exit_code,
              0);
    const std::string scene = shellQuote(test::dataPath("sample/scene.json"));
    const auto with_sidecar = test::runCli("composite " + shellQuote(exr) + " --decals " + scene + " --camera " +
                                           shellQuote(dir.file("cam.json")) + " --device cpu -o " +
                                           shellQuote(dir.file("sidecar.exr")));
    ASSERT_EQ(with_sidecar.exit_code, 0) << with_sidecar.output;
    const auto solved = test::runCli("composite " + shellQuote(exr) + " --decals " + scene + " --device cpu -o " +
                                     shellQuote(dir.file("solved.exr")));
    ASSERT_EQ(solved.exit_code, 0) << solved.output;
    EXPECT_NE(solved.output.find("camera solve: perspective, reprojection RMS"), std::string::npos) << solved.output;
    EXPECT_NE(solved.output.find("depth check: planar"), std::string::npos) << solved.output;

    const std::vector<float> a = albedoOf(dir.file("sidecar.exr")), b = albedoOf(dir.file("solved.exr")),
                             original = albedoOf(exr);
    ASSERT_EQ(a.size(), b.size());
    std::size_t changed = 0, differ = 0;
    for (std::size_t i = 0; i < a.size(); i += 3) {
        changed += a[i] != original[i] || a[i + 1] != original[i + 1] || a[i + 2] != original[i + 2];
        differ += std::abs(a[i] - b[i]) > 1e-3f || std::abs(a[i + 1] - b[i + 1]) > 1e-3f ||
                  std::abs(a[i + 2] - b[i + 2]) > 1e-3f;
    }
    EXPECT_GT(changed, a.size() / 3 / 50) << "the sample decals cover part of the frame";
    EXPECT_LE(differ, a.size() / 3 / 1000) << "solved and sidecar cameras composite the same";

    const auto info = test::runCli("info " + shellQuote(exr));
    EXPECT_EQ(info.exit_code, 0) << info.output;
    for (const char* needle : {"camera solve: perspective, reprojection RMS", "near/far: half the nearest",
                               "depth check: planar (the depth pass matches the position pass)"})
        EXPECT_NE(info.output.find(needle), std::string::npos) << needle << "\n" << info.output;
}

TEST(CameraSolve, CliRefusesWithTheResidual) {
    ScratchDir dir;
    const std::string exr = dir.file("in.exr");
    ASSERT_EQ(test::runGenerator("--width 48 --height 32 --naming generic", exr).exit_code, 0);
    // Scramble the position pass in the file: P.X's pixels in reverse order.
    ExrImage image = readExr(exr);
    for (ExrChannel& c : image.parts[0].channels)
        if (c.name == "P.X") {
            ASSERT_EQ(c.type, SampleType::Float);
            for (std::size_t i = 0, j = c.bytes.size() / 4 - 1; i < j; ++i, --j)
                std::swap_ranges(c.bytes.begin() + std::ptrdiff_t(4 * i), c.bytes.begin() + std::ptrdiff_t(4 * i + 4),
                                 c.bytes.begin() + std::ptrdiff_t(4 * j));
        }
    writeExrAtomic(image, exr);
    const auto r = test::runCli("composite " + shellQuote(exr) + " --decals " +
                                shellQuote(test::dataPath("sample/scene.json")) + " --device cpu -o " +
                                shellQuote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("reprojection error too large: RMS"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
    const auto info = test::runCli("info " + shellQuote(exr));
    EXPECT_EQ(info.exit_code, 0) << info.output;
    EXPECT_NE(info.output.find("camera: none ("), std::string::npos) << info.output;
}

TEST(CameraSolve, HeaderCameraCompositesLikeTheSidecar) {
    ScratchDir dir;
    const std::string exr = dir.file("in.exr");
    ASSERT_EQ(test::runCommand(shellQuote(DECALCOMP_GEN) + " --width 96 --height 64 --naming blender --no-position "
                               "--header-camera -o " + shellQuote(exr) + " --camera " + shellQuote(dir.file("cam.json")))
                  .exit_code,
              0);
    const std::string scene = shellQuote(test::dataPath("sample/scene.json"));
    const auto header = test::runCli("composite " + shellQuote(exr) + " --decals " + scene + " --device cpu -o " +
                                     shellQuote(dir.file("header.exr")));
    ASSERT_EQ(header.exit_code, 0) << header.output;
    EXPECT_NE(header.output.find("EXR header worldToCamera/worldToNDC"), std::string::npos) << header.output;
    const auto sidecar = test::runCli("composite " + shellQuote(exr) + " --decals " + scene + " --camera " +
                                      shellQuote(dir.file("cam.json")) + " --device cpu -o " +
                                      shellQuote(dir.file("sidecar.exr")));
    ASSERT_EQ(sidecar.exit_code, 0) << sidecar.output;
    const std::vector<float> a = albedoOf(dir.file("header.exr")), b = albedoOf(dir.file("sidecar.exr"));
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += std::abs(a[i] - b[i]) > 1e-3f;
    EXPECT_LE(differ, a.size() / 1000) << "the header camera (float matrices) is the sidecar camera";
}

TEST(CameraSolve, SingularHeaderMatrixIsAnInputError) {
    ScratchDir dir;
    const std::string exr = dir.file("in.exr");
    ASSERT_EQ(test::runCommand(shellQuote(DECALCOMP_GEN) + " --width 32 --height 24 --naming generic --no-position "
                               "--header-camera -o " + shellQuote(exr))
                  .exit_code,
              0);
    ExrImage image = readExr(exr);
    Imath::M44f m = image.parts[0].header.typedAttribute<Imf::M44fAttribute>("worldToCamera").value();
    for (int i = 0; i < 4; ++i) m[i][2] = 0.0f;
    image.parts[0].header.insert("worldToCamera", Imf::M44fAttribute(m));
    writeExrAtomic(image, exr);
    const auto r = test::runCli("composite " + shellQuote(exr) + " --decals " +
                                shellQuote(test::dataPath("sample/scene.json")) + " --device cpu -o " +
                                shellQuote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find(exr + ": worldToCamera: matrix is singular"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

}  // namespace
}  // namespace decalcomp
