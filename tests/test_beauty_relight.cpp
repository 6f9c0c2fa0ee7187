// --relight (issue 14, item 2): the direct light of a normal decal's pixels scaled by the ratio of a
// Lambert fit with the new and the old normal. Against the generator's exact Lambert re-render
// (one sun, no shadows: the model's own case), and measured on Cycles' direct-light render, where
// a normal swap on the sphere gives a reference (docs/decisions.md "Relight").
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <fstream>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/synth_light.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

std::vector<float> floats(const ExrImage& image, const std::string& name) {
    const ExrChannel& c = test::channel(image, name);
    std::vector<float> out(c.bytes.size() / sizeof(float));
    std::memcpy(out.data(), c.bytes.data(), c.bytes.size());
    return out;
}

// A pass's three channels as vectors ("ViewLayer.Normal" + X,Y,Z).
std::vector<glm::dvec3> vectors(const ExrImage& image, const std::string& pass, const char* components = "RGB") {
    const auto x = floats(image, pass + "." + components[0]), y = floats(image, pass + "." + components[1]),
               z = floats(image, pass + "." + components[2]);
    std::vector<glm::dvec3> out(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = {x[i], y[i], z[i]};
    return out;
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// One box decal of the dent normal map (strength 2, normal only) with this placement.
std::string dentScene(const std::string& placement) {
    return R"({"textures": {"dent": {"normal": ")" + test::dataPath("sample/textures/dent_n.png") +
           R"("}}, "decals": [{"name": "dent", "kind": "box", "texture": "dent", )" + placement +
           R"(, "affects": {"normal": {"factor": 1, "mode": "rnm", "strength": 2}}, "filter": "linear"}]})";
}

test::CommandResult composite(const std::string& in, const std::string& scene, const std::string& camera,
                              const std::string& out, const std::string& extra) {
    return test::runCli("composite " + test::shellQuote(in) + " --decals " + test::shellQuote(scene) + " --camera " +
                        test::shellQuote(camera) + " --device cpu -o " + test::shellQuote(out) + " " + extra);
}

// The generator's light is a sun without shadows plus a constant sky, the case the fit assumes:
// the relit beauty is the exact Lambert re-render of the new normal (synth::lightPasses on the
// output's albedo and normals) to float rounding, 1e-6 absolute on a beauty of at most ~1.2 (measured
// 9e-8: the fit recovers the sun to float precision), wherever
// the old normal saw the sun at n.l >= 0.25 (so the ratio stays under its clamp of 4). Elsewhere
// the kernel keeps the light (ratio 1 when n.l was ~0, at most 4 times otherwise): counted, not asserted.
TEST(BeautyRelight, GeneratorSunMatchesTheLambertRerender) {
    test::ScratchDir dir;
    const std::string in = dir.file("in.exr"), camera = dir.file("cam.json"), scene = dir.file("dent.json");
    ASSERT_EQ(test::runGenerator("--width 160 --height 90 --light-passes", in, camera).exit_code, 0);
    writeFile(scene, dentScene(R"("translate": [-1.9, -1.2, 0.0], "rotate_deg": [0, 0, 10], "scale": [1.6, 1.6, 0.3])"));
    const auto relit = composite(in, scene, camera, dir.file("relit.exr"), "--relight");
    ASSERT_EQ(relit.exit_code, 0) << relit.output;
    EXPECT_NE(relit.output.find("relit (approximation)"), std::string::npos) << relit.output;
    const auto plain = composite(in, scene, camera, dir.file("plain.exr"), "");
    ASSERT_EQ(plain.exit_code, 0) << plain.output;
    EXPECT_NE(plain.output.find("--relight approximates normal changes"), std::string::npos) << plain.output;

    const ExrImage before = readExr(in), after = readExr(dir.file("relit.exr")), unlit = readExr(dir.file("plain.exr"));
    const auto n0 = vectors(before, "ViewLayer.Normal", "XYZ"), n1 = vectors(after, "ViewLayer.Normal", "XYZ");
    // The exact re-render: the generator's own light model on the composited albedo and normals.
    GBuffer g;
    g.width = before.parts[0].width, g.height = before.parts[0].height;
    Plane albedo{3, {}}, normal{3, {}};
    for (const glm::dvec3& a : vectors(after, "ViewLayer.DiffCol"))
        for (int c = 0; c < 3; ++c) albedo.samples.push_back(float(a[c]));
    for (const glm::dvec3& n : n1)
        for (int c = 0; c < 3; ++c) normal.samples.push_back(float(n[c]));
    g.planes[Attribute::Albedo] = albedo, g.planes[Attribute::Normal] = normal;
    const Plane exact = synth::lightPasses(g).beauty;
    const Plane old_light = synth::lightPasses([&] {
        GBuffer b = g;
        for (std::size_t i = 0; i < n0.size(); ++i)
            for (int c = 0; c < 3; ++c) b.planes[Attribute::Normal].at(i, c) = float(n0[i][c]);
        return b;
    }()).beauty;
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, -0.6, 0.7));  // synth/light_passes.cpp

    const auto b1 = vectors(after, "ViewLayer.Combined"), b_plain = vectors(unlit, "ViewLayer.Combined");
    std::size_t checked = 0, outside = 0;
    double worst = 0, relit_squares = 0, plain_squares = 0;
    for (std::size_t i = 0; i < n0.size(); ++i) {
        if (n0[i] == n1[i]) continue;
        const glm::dvec3 e(exact.at(i, 0), exact.at(i, 1), exact.at(i, 2));
        const glm::dvec3 o(old_light.at(i, 0), old_light.at(i, 1), old_light.at(i, 2));
        if (glm::length(e - o) < 1e-4) continue;  // a tilt the light does not see
        if (glm::dot(glm::normalize(n0[i]), sun) < 0.25) {
            ++outside;
            continue;
        }
        ++checked;
        worst = std::max(worst, glm::length(b1[i] - e) / std::sqrt(3.0));
        for (int c = 0; c < 3; ++c) {
            relit_squares += std::pow(b1[i][c] - e[c], 2);
            plain_squares += std::pow(b_plain[i][c] - e[c], 2);
            ASSERT_NEAR(b1[i][c], e[c], 1e-6) << "pixel " << i << " channel " << c;
        }
    }
    RecordProperty("checked_pixels", std::to_string(checked));
    RecordProperty("outside_pixels", std::to_string(outside));
    RecordProperty("relit_rms", std::to_string(std::sqrt(relit_squares / (3.0 * checked))));
    RecordProperty("unrelit_rms", std::to_string(std::sqrt(plain_squares / (3.0 * checked))));
    std::cout << "relight vs exact Lambert: " << checked << " pixels, max " << worst << ", rms "
              << std::sqrt(relit_squares / (3.0 * checked)) << "; without --relight rms "
              << std::sqrt(plain_squares / (3.0 * checked)) << "; " << outside << " pixels below n.l 0.25\n";
    EXPECT_GT(checked, 300u);
    EXPECT_GT(plain_squares, 1e4 * relit_squares);  // the dent really changes the light
}

}  // namespace
}  // namespace decalcomp
