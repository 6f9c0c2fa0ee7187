// Cameras in EXR headers: RenderMan worldToCamera/worldToNDC <-> decalcomp's OpenGL-style Camera.
#include <gtest/gtest.h>

#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cmath>

#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/header_camera.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

void expectMatrixNear(const glm::dmat4& got, const glm::dmat4& expected, double tolerance, const char* what) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(got[c][r], expected[c][r], tolerance) << what << " row " << r << " col " << c;
}

glm::dvec3 ndcOf(const Camera& camera, const glm::dvec3& world) {
    const glm::dvec4 clip = camera.projection * camera.world_to_camera * glm::dvec4(world, 1.0);
    return glm::dvec3(clip) / clip.w;
}

std::string inputErrorMessage(const Imf::Header& header) {
    try {
        cameraFromExrHeader(header, "shot.exr");
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        return e.what();
    }
    ADD_FAILURE() << "expected an input error";
    return {};
}

// A copy of `header` without the named attributes (not Header::erase, which leaks in OpenEXR 3.1).
Imf::Header without(const Imf::Header& header, const std::vector<std::string>& names) {
    Imf::Header copy;
    for (auto it = header.begin(); it != header.end(); ++it)
        if (std::find(names.begin(), names.end(), it.name()) == names.end()) copy.insert(it.name(), it.attribute());
    return copy;
}

const glm::dvec3 kEye(3.0, -4.0, 2.0), kTarget(0.0, 0.5, 0.3), kUp(0.0, 0.0, 1.0);

Camera perspectiveCamera() {
    Camera camera;
    camera.world_to_camera = lookAt(kEye, kTarget, kUp);
    camera.projection = perspectiveProjection(0.8, 4.0 / 3.0, 0.1, 100.0, 0.04, -0.03);
    return camera;
}

TEST(HeaderCamera, PerspectiveRoundTrip) {
    const Camera camera = perspectiveCamera();
    Imf::Header header(64, 48);
    writeCameraToExrHeader(camera, header);
    ASSERT_NE(header.findTypedAttribute<Imf::M44fAttribute>("worldToCamera"), nullptr);
    ASSERT_NE(header.findTypedAttribute<Imf::M44fAttribute>("worldToNDC"), nullptr);

    const std::optional<Camera> back = cameraFromExrHeader(header, "shot.exr");
    ASSERT_TRUE(back.has_value());
    expectMatrixNear(back->world_to_camera, camera.world_to_camera, 1e-5, "world_to_camera");
    expectMatrixNear(back->projection, camera.projection, 1e-5, "projection");
    EXPECT_FALSE(back->isOrthographic());
    EXPECT_NEAR(back->nearPlane(), 0.1, 1e-6);
    EXPECT_NEAR(back->farPlane(), 100.0, 1e-3);
    EXPECT_EQ(back->source, "shot.exr (EXR header worldToCamera/worldToNDC)");
}

TEST(HeaderCamera, OrthographicRoundTrip) {
    Camera camera;
    camera.world_to_camera = lookAt({-2.0, 1.0, 5.0}, {0.5, 0.0, 0.0}, {0.0, 1.0, 0.0});
    camera.projection = orthographicProjection(2.5, 1.5, 0.5, 40.0);
    Imf::Header header(30, 20);
    writeCameraToExrHeader(camera, header);
    const std::optional<Camera> back = cameraFromExrHeader(header, "ortho.exr");
    ASSERT_TRUE(back.has_value());
    EXPECT_TRUE(back->isOrthographic());
    expectMatrixNear(back->world_to_camera, camera.world_to_camera, 1e-5, "world_to_camera");
    expectMatrixNear(back->projection, camera.projection, 1e-5, "projection");
}

// A header built by hand in RenderMan terms, without decalcomp's writer: camera axes right r,
// up u, forward f (looking down +Z), screen x_s = x_c/(z_c tan(fov/2) aspect) - 2 shift_x, NDC
// x_rm = (x_s + 1)/2 left to right and y_rm = (1 - y_s)/2 top to bottom.
struct RenderManCamera {
    double fov_y = 0.8, aspect = 4.0 / 3.0, shift_x = 0.04, shift_y = -0.03;
    glm::dvec3 r, u, f;

    RenderManCamera() {
        f = glm::normalize(kTarget - kEye);
        r = glm::normalize(glm::cross(f, kUp));
        u = glm::cross(r, f);
    }
    glm::dvec3 cameraPoint(const glm::dvec3& p) const {
        const glm::dvec3 d = p - kEye;
        return {glm::dot(r, d), glm::dot(u, d), glm::dot(f, d)};
    }
    glm::dvec2 ndc(const glm::dvec3& p) const {  // (x_rm, y_rm), straight from the definition
        const glm::dvec3 c = cameraPoint(p);
        const double t = std::tan(fov_y / 2.0);
        const double xs = c.x / (c.z * t * aspect) - 2.0 * shift_x;
        const double ys = c.y / (c.z * t) - 2.0 * shift_y;
        return {(xs + 1.0) / 2.0, (1.0 - ys) / 2.0};
    }
    // Row-vector matrices as Imath stores them: p' = p * M.
    Imath::M44f worldToCamera() const {
        Imath::M44f m;  // identity
        for (int i = 0; i < 3; ++i) {
            m[i][0] = float(r[i]);
            m[i][1] = float(u[i]);
            m[i][2] = float(f[i]);
        }
        m[3][0] = float(-glm::dot(r, kEye));
        m[3][1] = float(-glm::dot(u, kEye));
        m[3][2] = float(-glm::dot(f, kEye));
        return m;
    }
    Imath::M44f cameraToNdc() const {
        const double t = std::tan(fov_y / 2.0);
        Imath::M44f m(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f);
        m[0][0] = float(0.5 / (t * aspect));         // X = (x_s + 1)/2 * z_c
        m[2][0] = float(0.5 * (1.0 - 2.0 * shift_x));
        m[1][1] = float(-0.5 / t);                   // Y = (1 - y_s)/2 * z_c
        m[2][1] = float(0.5 * (1.0 + 2.0 * shift_y));
        m[2][2] = 1.0f;                              // Z: unused by decalcomp
        m[2][3] = 1.0f;                              // W = z_c
        return m;
    }
};

TEST(HeaderCamera, RenderManHeaderProjectsLikeTheConvertedCamera) {
    const RenderManCamera rm;
    const Imath::M44f world_to_ndc = rm.worldToCamera() * rm.cameraToNdc();
    Imf::Header header(64, 48);
    header.insert("worldToCamera", Imf::M44fAttribute(rm.worldToCamera()));
    header.insert("worldToNDC", Imf::M44fAttribute(world_to_ndc));
    header.insert("clipNear", Imf::FloatAttribute(0.1f));
    header.insert("clipFar", Imf::FloatAttribute(100.0f));

    const std::optional<Camera> camera = cameraFromExrHeader(header, "rm.exr");
    ASSERT_TRUE(camera.has_value());
    // The same camera, built with decalcomp's own helpers.
    expectMatrixNear(camera->world_to_camera, lookAt(kEye, kTarget, kUp), 1e-5, "world_to_camera");
    expectMatrixNear(camera->projection, perspectiveProjection(0.8, 4.0 / 3.0, 0.1, 100.0, 0.04, -0.03), 1e-5,
                     "projection");

    for (const glm::dvec3& p : {kTarget, glm::dvec3(1.0, 1.0, 1.0), glm::dvec3(-0.5, 2.0, -0.2),
                                glm::dvec3(0.7, -1.5, 0.9)}) {
        const glm::dvec2 expected = rm.ndc(p);
        // The test's own matrix agrees with the definition (checks the fixture, not the code).
        const Imath::V4f h = Imath::V4f(float(p.x), float(p.y), float(p.z), 1.0f) * world_to_ndc;
        ASSERT_NEAR(h.x / h.w, expected.x, 1e-5);
        ASSERT_NEAR(h.y / h.w, expected.y, 1e-5);
        // And the converted camera lands on the same spot.
        const glm::dvec3 ndc = ndcOf(*camera, p);
        EXPECT_NEAR(ndc.x, 2.0 * expected.x - 1.0, 1e-5) << p.x << "," << p.y << "," << p.z;
        EXPECT_NEAR(ndc.y, 1.0 - 2.0 * expected.y, 1e-5) << p.x << "," << p.y << "," << p.z;
        EXPECT_LT(camera->world_to_camera[0][2] * p.x + camera->world_to_camera[1][2] * p.y +
                      camera->world_to_camera[2][2] * p.z + camera->world_to_camera[3][2],
                  0.0)
            << "points in front of the camera have z < 0";
    }
}

TEST(HeaderCamera, SurvivesAFileAndAcceptsDoubleMatrices) {
    test::ScratchDir dir;
    const Camera camera = perspectiveCamera();
    Imf::Header header(8, 6);
    header.channels().insert("Y", Imf::Channel(Imf::HALF));
    writeCameraToExrHeader(camera, header);
    // Some writers use m44d; the reader takes both.
    const Imath::M44f f = header.typedAttribute<Imf::M44fAttribute>("worldToNDC").value();
    Imath::M44d d;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) d[i][j] = f[i][j];
    header = without(header, {"worldToNDC"});
    header.insert("worldToNDC", Imf::M44dAttribute(d));
    {
        Imf::OutputFile out(dir.file("cam.exr").c_str(), header);
        out.setFrameBuffer(Imf::FrameBuffer());
        out.writePixels(6);
    }
    const ExrImage image = readExr(dir.file("cam.exr"));
    const std::optional<Camera> back = cameraFromExrHeader(image.parts[0].header, image.path);
    ASSERT_TRUE(back.has_value());
    expectMatrixNear(back->projection, camera.projection, 1e-5, "projection");
    EXPECT_NE(back->source.find(dir.file("cam.exr")), std::string::npos);
}

TEST(HeaderCamera, DefaultClipRangeWithoutClipAttributes) {
    Imf::Header header(64, 48);
    writeCameraToExrHeader(perspectiveCamera(), header);
    header = without(header, {"clipNear", "clipFar"});
    const std::optional<Camera> back = cameraFromExrHeader(header, "shot.exr");
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->nearPlane(), 0.1, 1e-9);
    EXPECT_NEAR(back->farPlane() / 1e6, 1.0, 1e-6);
    const glm::dvec3 ndc = ndcOf(*back, kTarget);
    const glm::dvec3 expected = ndcOf(perspectiveCamera(), kTarget);
    EXPECT_NEAR(ndc.x, expected.x, 1e-5);
    EXPECT_NEAR(ndc.y, expected.y, 1e-5);
}

TEST(HeaderCamera, WritingReplacesMatricesOfAnotherType) {
    Imf::Header header(64, 48);
    header.insert("worldToNDC", Imf::M44dAttribute(Imath::M44d()));
    header.insert("clipNear", Imf::StringAttribute("near"));
    header.insert("studio:note", Imf::StringAttribute("keep me"));
    header.dataWindow() = Imath::Box2i({4, 2}, {40, 30});
    writeCameraToExrHeader(perspectiveCamera(), header);
    EXPECT_NE(header.findTypedAttribute<Imf::M44fAttribute>("worldToNDC"), nullptr);
    ASSERT_NE(header.findTypedAttribute<Imf::StringAttribute>("studio:note"), nullptr);
    EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("studio:note").value(), "keep me");
    EXPECT_EQ(header.dataWindow(), Imath::Box2i({4, 2}, {40, 30}));
    const std::optional<Camera> back = cameraFromExrHeader(header, "shot.exr");
    ASSERT_TRUE(back.has_value());
    expectMatrixNear(back->projection, perspectiveCamera().projection, 1e-5, "projection");
}

TEST(HeaderCamera, AbsentMatricesMeanNoCamera) {
    Imf::Header header(64, 48);
    EXPECT_FALSE(cameraFromExrHeader(header, "shot.exr").has_value());
}

TEST(HeaderCamera, WorldToCameraAloneIsAnError) {
    Imf::Header header(64, 48);
    writeCameraToExrHeader(perspectiveCamera(), header);
    header = without(header, {"worldToNDC"});
    EXPECT_EQ(inputErrorMessage(header),
              "shot.exr: worldToNDC missing (worldToCamera alone does not define the projection)");
}

TEST(HeaderCamera, SingularMatricesAreErrors) {
    Imf::Header header(64, 48);
    writeCameraToExrHeader(perspectiveCamera(), header);
    Imf::Header flat_camera = header;
    Imath::M44f squashed = header.typedAttribute<Imf::M44fAttribute>("worldToCamera").value();
    for (int i = 0; i < 4; ++i) squashed[i][1] = 0.0f;  // camera y always 0
    flat_camera.insert("worldToCamera", Imf::M44fAttribute(squashed));
    const std::string camera_message = inputErrorMessage(flat_camera);
    EXPECT_EQ(camera_message.rfind("shot.exr: worldToCamera: ", 0), 0u) << camera_message;
    EXPECT_NE(camera_message.find("singular"), std::string::npos) << camera_message;

    Imf::Header flat_ndc = header;
    const Imath::M44f zero(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
                           0.0f);
    flat_ndc.insert("worldToNDC", Imf::M44fAttribute(zero));
    const std::string ndc_message = inputErrorMessage(flat_ndc);
    EXPECT_EQ(ndc_message.rfind("shot.exr: worldToNDC: ", 0), 0u) << ndc_message;

    Imf::Header no_x = header;
    Imath::M44f ndc = header.typedAttribute<Imf::M44fAttribute>("worldToNDC").value();
    for (int i = 0; i < 4; ++i) ndc[i][0] = 0.5f * ndc[i][3];  // every point at x_rm = 0.5
    no_x.insert("worldToNDC", Imf::M44fAttribute(ndc));
    const std::string no_x_message = inputErrorMessage(no_x);
    EXPECT_EQ(no_x_message, "shot.exr: worldToNDC: matrix is singular") << no_x_message;
}

TEST(HeaderCamera, MatricesOfDifferentCamerasAreInconsistent) {
    Imf::Header header(64, 48);
    writeCameraToExrHeader(perspectiveCamera(), header);
    Imf::Header other(64, 48);
    Camera turned = perspectiveCamera();
    turned.world_to_camera = lookAt(kEye, kTarget + glm::dvec3(2.0, 0.0, 0.0), kUp);
    writeCameraToExrHeader(turned, other);
    header.insert("worldToCamera", other.typedAttribute<Imf::M44fAttribute>("worldToCamera"));
    const std::string message = inputErrorMessage(header);
    EXPECT_NE(message.find("shot.exr: worldToNDC: inconsistent with worldToCamera"), std::string::npos) << message;
}

TEST(HeaderCamera, WrongAttributeTypeIsAnError) {
    Imf::Header header(64, 48);
    writeCameraToExrHeader(perspectiveCamera(), header);
    header = without(header, {"worldToCamera"});
    header.insert("worldToCamera", Imf::StringAttribute("identity"));
    const std::string message = inputErrorMessage(header);
    EXPECT_NE(message.find("shot.exr: worldToCamera: expected an m44f or m44d attribute, got string"),
              std::string::npos)
        << message;
}

}  // namespace
}  // namespace decalcomp
