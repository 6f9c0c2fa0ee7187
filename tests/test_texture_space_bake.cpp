// Bake mode of texture-space decals (docs/texture-space.md "Bake mode"): the UV-space bake against
// exact mode on the analytic deforming tube, the seam crack that dilation closes, Cycles' truth on
// data/blender-deform at 2048², and `decalcomp bake` with reused baked files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "decalcomp/bake.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/mesh_file.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_mesh.hpp"
#include "decalcomp/textures.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::cpuDevice;

constexpr int kWidth = 200, kHeight = 150;

Camera tubeCamera() {
    Camera camera;
    camera.world_to_camera = lookAt({5.0, -1.0, 1.6}, {0.6, 0.0, 1.0}, {0, 0, 1});
    camera.projection = perspectiveProjection(0.75, double(kWidth) / kHeight, 0.1, 100.0);
    return camera;
}

// The tube twisted and bent, its pixels (object 1) the scene's one mask plane.
synth::MeshFrame renderTube(const RestMesh& tube, double twist_deg, double bend_deg) {
    std::vector<synth::PosedMesh> meshes(1);
    meshes[0] = {&tube, synth::twistAndBend(tube, twist_deg, bend_deg), 1, glm::vec3(0.6f, 0.5f, 0.4f)};
    synth::MeshFrame frame = synth::renderMeshes(meshes, tubeCamera(), kWidth, kHeight);
    Plane mask;
    mask.components = 1;
    mask.samples.assign(frame.gbuffer.pixelCount(), 0.0f);
    for (std::size_t i = 0; i < frame.gbuffer.pixelCount(); ++i)
        mask.samples[i] = frame.gbuffer.planes.at(Attribute::ObjectId).at(i, 0) == 1.0f;
    frame.gbuffer.mask_weights = {mask};
    return frame;
}

// A box across the tube's UV seam (angle 0, +X) with a procedural texture, nearest texels.
DecalScene seamScene(const RestMesh& tube, RestMode mode, int resolution, int dilation, bool flat = false) {
    DecalScene scene;
    scene.meshes = {tube};
    DecalMask mask;
    mask.include_ids = {1};
    scene.masks = {mask};
    scene.textures.push_back(synth::proceduralTexture(0, 16, 3));
    if (flat) {  // one opaque red texel: only the coverage can differ
        scene.textures[0].width = scene.textures[0].height = 1;
        scene.textures[0].texels = {glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)};
    }
    Decal d;
    d.name = "seam";
    d.space = DecalSpace::ObjectRest;
    d.rest_mesh = 0;
    d.mask = 0;
    d.albedo_texture = 0;
    d.filter = TextureFilter::Nearest;
    glm::dmat4 box(0.0);
    box[0] = glm::dvec4(0, 0.7, 0, 0);  // local X -> around the tube
    box[1] = glm::dvec4(0, 0, 0.9, 0);  // local Y -> up the tube
    box[2] = glm::dvec4(0.6, 0, 0, 0);  // local Z -> object +X, through the seam
    box[3] = glm::dvec4(0.5, 0.0, 1.0, 1);
    d.world_matrix = box;
    d.rest_mode = mode;
    d.bake_resolution = resolution;
    d.bake_dilation = dilation;
    d.bake_slot = 0;
    scene.decals.push_back(d);
    return scene;
}

GBuffer composite(ComputeDevice& device, const DecalScene& scene, const synth::MeshFrame& frame) {
    Compositor compositor(device);
    compositor.setScene(scene);
    GBuffer out = frame.gbuffer;
    compositor.composite(out, tubeCamera());
    return out;
}

// Per-pixel largest albedo difference between two composites.
std::vector<float> albedoDifference(const GBuffer& a, const GBuffer& b) {
    std::vector<float> out(a.pixelCount(), 0.0f);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < 3; ++c)
            out[i] = std::max(out[i], std::abs(a.planes.at(Attribute::Albedo).at(i, c) - b.planes.at(Attribute::Albedo).at(i, c)));
    return out;
}

// Pixels whose UV lies within `texels` of the seam (u at either end of the island's 0.05..0.95).
bool nearSeam(const GBuffer& g, std::size_t i, double texels, int resolution) {
    const double u = g.planes.at(Attribute::UV).at(i, 0), reach = texels / resolution;
    return std::abs(u - 0.05) <= reach || std::abs(u - 0.95) <= reach;
}

TEST(TextureSpaceBake, AgreesWithExactModeWithinTheTexelSize) {
    ComputeDevice& device = cpuDevice();
    const RestMesh tube = synth::tubeMesh(48, 24);
    const synth::MeshFrame frame = renderTube(tube, 10.0, 30.0);
    const GBuffer exact = composite(device, seamScene(tube, RestMode::Exact, 0, 0), frame);
    constexpr int kResolution = 2048;
    const GBuffer baked = composite(device, seamScene(tube, RestMode::Bake, kResolution, 8), frame);
    const std::vector<float> diff = albedoDifference(exact, baked);
    std::size_t decal = 0, off = 0;
    for (std::size_t i = 0; i < diff.size(); ++i) {
        const bool changed = exact.planes.at(Attribute::Albedo).at(i, 0) != frame.gbuffer.planes.at(Attribute::Albedo).at(i, 0);
        if (!changed) continue;
        ++decal;
        off += diff[i] > 0.02f;
    }
    std::printf("bake %d² vs exact: %zu of %zu decal pixels differ by more than 0.02\n", kResolution, off, decal);
    EXPECT_GT(decal, 200u);  // the box's visible part (measured 278 pixels)
    // The procedural texture's 16-texel cells cover ~20 pixels each here; a bake texel moves a
    // nearest-texel edge by at most ~1/10 pixel, so only pixels on those edges may differ
    // (measured: 4 of 278 pixels, 1.4 %).
    EXPECT_LE(double(off), 0.05 * double(decal));
}

TEST(TextureSpaceBake, DilationClosesTheSeamCrack) {
    ComputeDevice& device = cpuDevice();
    const RestMesh tube = synth::tubeMesh(48, 24);
    const synth::MeshFrame frame = renderTube(tube, 10.0, 30.0);
    const GBuffer exact = composite(device, seamScene(tube, RestMode::Exact, 0, 0, true), frame);
    constexpr int kResolution = 64;  // coarse, so the seam's texels span pixels
    auto crack = [&](int dilation) {
        const GBuffer baked = composite(device, seamScene(tube, RestMode::Bake, kResolution, dilation, true), frame);
        const std::vector<float> diff = albedoDifference(exact, baked);
        std::size_t n = 0, seam = 0;
        for (std::size_t i = 0; i < diff.size(); ++i)
            // the seam inside the box (v 0.30..0.70), away from its top and bottom edges
            if (frame.gbuffer.mask_weights[0].at(i, 0) > 0.0f && nearSeam(frame.gbuffer, i, 1.0, kResolution) &&
                std::abs(frame.gbuffer.planes.at(Attribute::UV).at(i, 1) - 0.5) < 0.15) {
                ++seam;
                n += diff[i] > 0.1f;
            }
        std::printf("dilation %d: %zu of %zu seam pixels off by > 0.1\n", dilation, n, seam);
        return n;
    };
    const std::size_t without = crack(0), with = crack(8);
    std::printf("seam pixels off by > 0.1: %zu without dilation, %zu with\n", without, with);
    // measured at 64²: 7 of the 93 seam pixels crack without dilation (bilinear reads of the empty
    // texel beyond the border), none with it
    EXPECT_GE(without, 5u);
    EXPECT_EQ(with, 0u);
}

// A decal with an ORM map and an ORM constant: where the map is transparent but the albedo is not,
// exact mode applies the constant (roughness) and leaves the map's channels (ao, metallic) alone;
// the bake must too (it used to bake 0 into them there).
TEST(TextureSpaceBake, TransparentOrmMapLeavesItsChannelsAloneAsInExactMode) {
    ComputeDevice& device = cpuDevice();
    const RestMesh tube = synth::tubeMesh(48, 24);
    synth::MeshFrame frame = renderTube(tube, 10.0, 30.0);
    for (Attribute a : {Attribute::Roughness, Attribute::Metallic, Attribute::AmbientOcclusion}) {
        Plane p;
        p.components = 1;
        p.samples.assign(frame.gbuffer.pixelCount(), 0.5f);
        frame.gbuffer.planes[a] = p;
    }
    auto scene = [&](RestMode mode) {
        DecalScene s = seamScene(tube, mode, 2048, 8, true);  // opaque albedo everywhere
        Texture2D orm;  // left half transparent, right half ao 0.2, roughness 0.9, metallic 1
        orm.source = "orm";
        orm.width = 2;
        orm.height = 1;
        orm.texels = {glm::vec4(0.0f), glm::vec4(0.2f, 0.9f, 1.0f, 1.0f)};
        s.textures.push_back(orm);
        s.decals[0].orm_texture = 1;
        s.decals[0].effect(DecalTarget::Roughness).value = glm::vec3(0.7f);
        return s;
    };
    const GBuffer exact = composite(device, scene(RestMode::Exact), frame);
    const GBuffer baked = composite(device, scene(RestMode::Bake), frame);
    std::size_t decal = 0, transparent = 0, off = 0;
    for (std::size_t i = 0; i < exact.pixelCount(); ++i) {
        if (exact.planes.at(Attribute::Albedo).at(i, 0) == frame.gbuffer.planes.at(Attribute::Albedo).at(i, 0)) continue;
        ++decal;
        transparent += exact.planes.at(Attribute::AmbientOcclusion).at(i, 0) == 0.5f;
        float worst = 0.0f;
        for (Attribute a : {Attribute::Roughness, Attribute::Metallic, Attribute::AmbientOcclusion})
            worst = std::max(worst, std::abs(exact.planes.at(a).at(i, 0) - baked.planes.at(a).at(i, 0)));
        off += worst > 0.02f;
    }
    std::printf("ORM map half transparent: %zu of %zu decal pixels under the transparent half, %zu differ by > 0.02\n",
                transparent, decal, off);
    EXPECT_GT(transparent, 50u) << "the transparent half is seen";
    // only the column of pixels on the map's middle edge, where a bake texel moves it (as the
    // albedo's texel edges in AgreesWithExactModeWithinTheTexelSize)
    EXPECT_LE(double(off), 0.05 * double(decal));
}

// ---- data/blender-deform (README "Deforming sequence")

std::string deform(const std::string& file) { return test::dataPath("blender-deform/" + file); }
std::string frameName(const char* stem, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "%s.%04d.exr", stem, frame);
    return name;
}

// The Blender scene with its decal in bake mode (and `extra` fields), written to `dir`.
std::string bakeScene(const test::ScratchDir& dir, const nlohmann::json& extra, const std::string& name = "bake.json") {
    std::ifstream in(deform("decals.json"));
    nlohmann::json scene = nlohmann::json::parse(in);
    nlohmann::json& decal = scene["decals"][0];
    decal["mode"] = "bake";
    decal["mesh"] = deform("mesh_rest.obj");
    decal["texture"] = deform("decal_label.png");
    for (const auto& [key, value] : extra.items()) decal[key] = value;
    const std::string file = dir.file(name);
    std::ofstream(file) << scene.dump(2);
    return file;
}

test::CommandResult batch(const test::ScratchDir& dir, const std::string& scene, const std::string& frames,
                          const std::string& stem) {
    return test::runCli("batch " + test::shellQuote(deform("gbuffer.####.exr")) + " --frames " + frames + " --decals " +
                        test::shellQuote(scene) + " --camera " + test::shellQuote(deform("camera.json")) +
                        " --device cpu -q -o " + test::shellQuote(dir.file(stem + ".####.exr")));
}

TEST(TextureSpaceBakeBlender, ScoresAtLeast42DbOnEveryFrameAt2048) {
    test::ScratchDir dir;
    const auto run = batch(dir, bakeScene(dir, {{"bake_resolution", 2048}}), "1-6", "out");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (int f = 1; f <= 6; ++f) {
        const auto score =
            test::scoreAgainstTruth(readExr(dir.file(frameName("out", f))), readExr(deform(frameName("truth", f))));
        std::printf("bake 2048², frame %d: %.1f dB over %zu decal pixels\n", f, score.psnr, score.pixels / 3);
        // issue 11's target for a 2048² bake (the README's numpy bake scores 41-42 dB)
        EXPECT_GE(score.psnr, 42.0) << "frame " << f;
        RecordProperty("psnr_db_frame_" + std::to_string(f), std::to_string(score.psnr));
    }
}

TEST(TextureSpaceBakeCli, ExportsReadableLayersThatGiveTheSameResultWhenReused) {
    test::ScratchDir dir;
    const std::string scene = bakeScene(dir, {{"bake_resolution", 256}});
    const auto bake = test::runCli("bake --decals " + test::shellQuote(scene) + " --device cpu -q -o " +
                                   test::shellQuote(dir.file("layers")));
    ASSERT_EQ(bake.exit_code, 0) << bake.output;
    const RestMesh mesh = loadRestMesh(deform("mesh_rest.obj"));
    const BakedLayers layers = readBakedLayers(dir.file("layers/tube_label.exr"), mesh);
    EXPECT_EQ(layers.width, 256);
    EXPECT_FALSE(layers.orm.has_value());
    const Texture2D png = loadTexture2D(dir.file("layers/tube_label.png"));
    EXPECT_EQ(png.width, 256);
    std::size_t covered = 0;
    for (const glm::vec4& t : png.texels) covered += t.w > 0.5f;
    EXPECT_GT(covered, 1000u);

    const std::string reuse = bakeScene(dir, {{"baked", dir.file("layers/tube_label.exr")}}, "reuse.json");
    ASSERT_EQ(batch(dir, scene, "3", "in_run").exit_code, 0);
    ASSERT_EQ(batch(dir, reuse, "3", "reused").exit_code, 0);
    std::vector<float> a, b;
    const ExrImage in_run = readExr(dir.file(frameName("in_run", 3))), reused = readExr(dir.file(frameName("reused", 3)));
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.DiffCol.") + c;
        ASSERT_TRUE(test::findFloatChannel(in_run, name, a) && test::findFloatChannel(reused, name, b));
        EXPECT_EQ(a, b) << name;
    }
}

TEST(TextureSpaceBakeCli, BadBakedFilesAreOneLineErrors) {
    test::ScratchDir dir;
    const auto bake = test::runCli("bake --decals " + test::shellQuote(bakeScene(dir, {{"bake_resolution", 64}})) +
                                   " --device cpu -q -o " + test::shellQuote(dir.file("layers")));
    ASSERT_EQ(bake.exit_code, 0) << bake.output;
    auto expectError = [&](const nlohmann::json& extra, const std::string& what) {
        const auto run = batch(dir, bakeScene(dir, extra, "bad.json"), "1", "bad");
        EXPECT_NE(run.exit_code, 0) << what;
        EXPECT_NE(run.output.find("decalcomp: error: "), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("decals[0].baked"), std::string::npos) << run.output;
        EXPECT_NE(run.output.find(what), std::string::npos) << run.output;
        EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
        EXPECT_FALSE(std::ifstream(dir.file(frameName("bad", 1))).good()) << "no partial output";
    };
    expectError({{"baked", dir.file("missing.exr")}}, "not found");
    expectError({{"baked", dir.file("layers/tube_label.exr")}, {"bake_resolution", 128}}, "bake_resolution is 128");
    // the same mesh with one vertex moved: another mesh
    std::ifstream in(deform("mesh_rest.obj"));
    std::ofstream moved(dir.file("moved.obj"));
    std::string line;
    bool done = false;
    while (std::getline(in, line)) {
        if (!done && line.rfind("v ", 0) == 0) {
            line = "v 0.123 0.456 0.789";
            done = true;
        }
        moved << line << "\n";
    }
    moved.close();
    expectError({{"baked", dir.file("layers/tube_label.exr")}, {"mesh", dir.file("moved.obj")}}, "another mesh");
    // the PNG is no baked file
    expectError({{"baked", dir.file("layers/tube_label.png")}}, "EXR written by decalcomp bake");
}

TEST(TextureSpaceBakeCli, OutputsNeverOverwriteTheScenesInputs) {
    test::ScratchDir dir;
    const std::string scene = bakeScene(dir, {{"bake_resolution", 32}, {"name", "bake"}});
    // the decal named "bake" would write bake.exr/bake.png beside bake.json: harmless; name it after the scene
    std::ifstream in(scene);
    nlohmann::json j = nlohmann::json::parse(in);
    j["decals"][0]["name"] = "mesh_rest";
    j["decals"][0]["mesh"] = dir.file("mesh_rest.png");
    std::filesystem::copy_file(deform("mesh_rest.obj"), dir.file("mesh_rest.png"));
    std::ofstream(scene) << j.dump(2);
    const auto run = test::runCli("bake --decals " + test::shellQuote(scene) + " --device cpu -q -o " +
                                  test::shellQuote(dir.path().string()));
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("would overwrite"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace decalcomp
