// Bake mode of texture-space decals (docs/texture-space.md "Bake mode"): the UV-space bake against
// exact mode on the analytic deforming tube, the seam crack that dilation closes, Cycles' truth on
// data/blender-deform at 2048², and `decalcomp bake` with reused baked files.
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include <nlohmann/json.hpp>

#include "decalcomp/bake.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/mesh_file.hpp"
#include "decalcomp/reference_bake.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_mesh.hpp"
#include "decalcomp/textures.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"
#include "support/tube_frames.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::cpuDevice;

constexpr int kWidth = 200, kHeight = 150;

Camera tubeCamera() { return test::tubeCamera(kWidth, kHeight); }

// The tube twisted and bent, its pixels (object 1) the scene's one mask plane.
synth::MeshFrame renderTube(const RestMesh& tube, double twist_deg, double bend_deg) {
    std::vector<synth::PosedMesh> meshes(1);
    meshes[0] = {&tube, synth::twistAndBend(tube, twist_deg, bend_deg), 1, glm::vec3(0.6f, 0.5f, 0.4f)};
    synth::MeshFrame frame = synth::renderMeshes(meshes, tubeCamera(), kWidth, kHeight);
    test::maskObjectOne(frame.gbuffer);
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

// The albedo exact mode gives a tube pixel whose UV is `uv` (0.6, 0.5, 0.4 under the box's texels),
// through the reference; nullopt off the mesh. The seam is crossed as the surface does (u wraps).
std::optional<glm::dvec3> exactAlbedoAt(const RestMesh& tube, const reference::BakeEvaluator& decal, glm::dvec2 uv,
                                        const glm::dvec3& base) {
    if (uv.x < 0.05) uv.x += 0.9;
    if (uv.x > 0.95) uv.x -= 0.9;
    const auto hit = findRestPoint(tube, glm::vec2(uv));
    if (!hit) return std::nullopt;
    const glm::ivec3& t = tube.triangles[std::size_t(hit->triangle)];
    glm::dvec3 normal(0.0);
    for (int k = 0; k < 3; ++k) normal += double(hit->weights[k]) * glm::dvec3(tube.vertices[std::size_t(t[k])].normal);
    const glm::dvec3 rest(hit->position);
    const glm::dvec4 a = decal.at(rest, glm::normalize(normal), rest, rest).albedo;  // nearest: no footprint
    return base * (1.0 - a.a) + glm::dvec3(a);  // over, premultiplied
}

// The issue's "within the bake's texel size", split: pixels whose neighbourhood of one bake texel
// (in UV) holds one decal value must match exact mode closely; pixels with a decal or texel edge
// in it read a bilinear mix of texels from that neighbourhood, so their albedo must lie between
// the values exact mode takes there (a shift of at most one texel).
TEST(TextureSpaceBake, AgreesWithExactModeWithinTheTexelSize) {
    ComputeDevice& device = cpuDevice();
    const RestMesh tube = synth::tubeMesh(48, 24);
    const synth::MeshFrame frame = renderTube(tube, 10.0, 30.0);
    const DecalScene exact_scene = seamScene(tube, RestMode::Exact, 0, 0);
    const GBuffer exact = composite(device, exact_scene, frame);
    constexpr int kResolution = 2048;
    const GBuffer baked = composite(device, seamScene(tube, RestMode::Bake, kResolution, 8), frame);
    const reference::BakeEvaluator decal(exact_scene, exact_scene.decals[0]);
    const Plane& uv = frame.gbuffer.planes.at(Attribute::UV);
    const Plane &in = frame.gbuffer.planes.at(Attribute::Albedo), &a = exact.planes.at(Attribute::Albedo),
                &b = baked.planes.at(Attribute::Albedo);
    std::size_t interior = 0, edge = 0, edge_off = 0, edge_shifted = 0;
    double interior_worst = 0, edge_worst_outside = 0;
    for (std::size_t i = 0; i < frame.gbuffer.pixelCount(); ++i) {
        if (!(frame.gbuffer.mask_weights[0].at(i, 0) > 0.0f)) continue;
        const glm::dvec3 base(in.at(i, 0), in.at(i, 1), in.at(i, 2));
        // exact mode's albedo over the square of +-1 texel around the pixel's UV (3 x 3 points:
        // the bilinear taps' centres lie in it, and the texture's cells are far larger)
        glm::dvec3 lo(1e9), hi(-1e9);
        bool on_mesh = true;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const glm::dvec2 at(uv.at(i, 0) + dx / double(kResolution), uv.at(i, 1) + dy / double(kResolution));
                const auto v = exactAlbedoAt(tube, decal, at, base);
                on_mesh = on_mesh && v.has_value();
                if (!v) continue;
                lo = glm::min(lo, *v);
                hi = glm::max(hi, *v);
            }
        const bool changed = glm::length(hi - base) > 0.0 || glm::length(lo - base) > 0.0;
        if (!changed && a.at(i, 0) == in.at(i, 0) && b.at(i, 0) == in.at(i, 0)) continue;  // beyond the decal
        ASSERT_TRUE(on_mesh) << "the box lies away from the tube's open ends";
        double outside = 0, diff = 0;
        for (int c = 0; c < 3; ++c) {
            outside = std::max({outside, lo[c] - b.at(i, c), b.at(i, c) - hi[c]});
            diff = std::max(diff, double(std::abs(a.at(i, c) - b.at(i, c))));
        }
        if (glm::length(hi - lo) <= 1e-6) {
            ++interior;
            interior_worst = std::max(interior_worst, diff);
        } else {
            ++edge;
            edge_shifted += diff > 0.02;
            edge_worst_outside = std::max(edge_worst_outside, outside);
            edge_off += outside > 1e-4;
        }
    }
    std::printf("bake %d² vs exact: %zu interior pixels, largest difference %.2g; %zu edge pixels, %zu differ by > 0.02, "
                "%zu outside exact mode's values within one texel (by at most %.2g)\n",
                kResolution, interior, interior_worst, edge, edge_shifted, edge_off, edge_worst_outside);
    EXPECT_GT(interior, 200u);  // the box's visible part (measured 270 interior + 15 edge pixels)
    // four equal taps of premultiplied texels read back (measured 0: bit-identical); 1e-5 leaves
    // room for float rounding of the bilinear weights on other devices
    EXPECT_LT(interior_worst, 1e-5);
    // edge pixels: a mix of exact mode's values within one texel, to float rounding (measured
    // none outside); 8 of the 15 differ from exact by more than 0.02 (the texel's shift)
    EXPECT_EQ(edge_off, 0u);
    EXPECT_LE(double(edge_shifted), 0.05 * double(interior + edge));
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

// ---- the device's bake layers against the scalar reference (reference_bake.hpp)

// A small tube of random proportions, its UVs jittered by up to a quarter cell so that island
// borders and inner edges are slanted (the tube's own are axis-aligned).
RestMesh randomTube(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int around = 6 + int(rng() % 10), along = 3 + int(rng() % 6);
    RestMesh m = synth::tubeMesh(around, along, 0.3 + 0.5 * u(rng), 1.0 + 1.5 * u(rng));
    for (RestVertex& v : m.vertices)
        v.uv += glm::vec2(float((u(rng) - 0.5) * 0.5 * 0.9 / around), float((u(rng) - 0.5) * 0.5 * 0.9 / along));
    finishRestMesh(m);
    return m;
}

// A decal of `kind` on the tube's surface at a random angle and height, with random filter, fades
// and materials; `cover_all`: an opaque box around the whole tube (every found texel gets alpha 1).
DecalScene randomBakeScene(const RestMesh& tube, DecalKind kind, bool cover_all, int dilation, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    DecalScene scene;
    scene.meshes = {tube};
    double radius = 0, height = 0;
    for (const RestVertex& v : tube.vertices) {
        radius = std::max(radius, double(glm::length(glm::vec2(v.position))));
        height = std::max(height, double(v.position.z));
    }
    const int shapes = kind == DecalKind::Volume ? 5 : kind == DecalKind::Cube ? 6 : 1;
    const TextureShape shape = kind == DecalKind::Volume ? TextureShape::Volume
                               : kind == DecalKind::Cube ? TextureShape::Cube
                                                         : TextureShape::Flat;
    scene.textures.push_back(test::randomTexture(cover_all ? 1 : 7, cover_all ? 1 : 7, shapes, rng, shape));
    if (cover_all) scene.textures[0].texels.assign(scene.textures[0].texels.size(), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
    Decal d;
    d.name = "random";
    d.kind = kind;
    d.space = DecalSpace::ObjectRest;
    d.rest_mesh = 0;
    d.albedo_texture = 0;
    d.rest_mode = RestMode::Bake;
    d.bake_resolution = 48 + 16 * int(rng() % 4);  // 48..96: small layers, texels of a few per face
    d.bake_dilation = dilation;
    const TextureFilter filters[3] = {TextureFilter::Nearest, TextureFilter::Linear, TextureFilter::Mip};
    d.filter = filters[rng() % 3];
    const double angle = 2.0 * std::numbers::pi * u(rng), z = height * (0.3 + 0.4 * u(rng));
    const glm::dvec3 out(std::cos(angle), std::sin(angle), 0.0), around(-std::sin(angle), std::cos(angle), 0.0), up(0, 0, 1);
    const glm::dvec3 at = radius * out + z * up;
    const double size = radius * (0.6 + 0.8 * u(rng));
    glm::dmat4 m(1.0);
    if (cover_all) {
        m = glm::dmat4(glm::dvec4(4.0 * radius, 0, 0, 0), glm::dvec4(0, 4.0 * radius, 0, 0),
                       glm::dvec4(0, 0, 2.0 * height, 0), glm::dvec4(0, 0, 0.5 * height, 1));
    } else if (kind == DecalKind::Frustum) {
        const glm::dvec3 origin = at + out * (1.0 + u(rng)) * radius + around * (u(rng) - 0.5) * radius;
        m = glm::inverse(lookAt(origin, at, up));
        d.fov_y_deg = 25.0 + 30.0 * u(rng);
        d.near = 0.05;
        d.far = 4.0 * radius + 1.0;
        if (rng() % 2) d.distance_fade = {0.5 * d.far, d.far};
    } else if (kind == DecalKind::Cube) {
        m = glm::dmat4(size);
        m[3] = glm::dvec4(at + out * 0.1 * radius, 1.0);  // outside: its facing (from the surface to its centre) is outward
    } else {
        m[0] = glm::dvec4(around * size, 0.0);
        m[1] = glm::dvec4(up * size * (0.7 + 0.6 * u(rng)), 0.0);
        m[2] = glm::dvec4(out * radius, 0.0);
        m[3] = glm::dvec4(at, 1.0);
        if (rng() % 2) d.axis_fade = 0.5;
    }
    d.world_matrix = m;
    if (!cover_all) {
        if (rng() % 2) d.angle_fade_deg = {20.0, 70.0};  // the mesh's rest normal against the decal's facing
        d.opacity = float(0.5 + 0.5 * u(rng));
        if (rng() % 2) {  // ORM map, sometimes with a constant beside it
            scene.textures.push_back(test::randomTexture(5, 5, shapes, rng, shape));
            d.orm_texture = int(scene.textures.size()) - 1;
            if (rng() % 2) d.effect(DecalTarget::Roughness).value = glm::vec3(0.3f);
        }
        if (rng() % 2) {
            scene.textures.push_back(test::randomTexture(4, 4, shapes, rng, shape));
            d.emission_texture = int(scene.textures.size()) - 1;
        }
        if (rng() % 3 == 0) d.effect(DecalTarget::Albedo).value = glm::vec3(0.9f, 0.1f, 0.2f);
    }
    scene.decals.push_back(d);
    return scene;
}

struct BakeAgreement {
    std::size_t texels = 0, covered = 0, dilated = 0, reached = 0, ambiguous = 0, mismatched = 0, class_mismatched = 0;
    double max_error = 0;  // over texels not ambiguous
};

// Device layers against the reference's, texel by texel.
BakeAgreement compareBakes(const BakedLayers& device, const reference::BakeReference& ref) {
    BakeAgreement a;
    a.texels = ref.albedo.size();
    for (std::size_t i = 0; i < a.texels; ++i) {
        a.covered += ref.classes[i] == reference::BakeTexelClass::Covered;
        a.dilated += ref.classes[i] == reference::BakeTexelClass::Dilated;
        a.reached += ref.albedo[i].a > 0.0;
        if (ref.ambiguous[i]) {
            ++a.ambiguous;
            continue;
        }
        double error = 0;
        auto add = [&](const std::optional<Texture2D>& layer, const glm::dvec4& r) {
            const glm::dvec4 v = layer ? glm::dvec4(layer->texels[i]) : glm::dvec4(0.0);
            for (int c = 0; c < 4; ++c) error = std::max(error, std::abs(v[c] - r[c]));
        };
        add(device.albedo, ref.albedo[i]);
        add(device.orm, ref.orm[i]);
        add(device.emission, ref.emission[i]);
        a.max_error = std::max(a.max_error, error);
        // colours: float against double through texture filtering and fades stays far below this
        a.mismatched += error > 1e-4;
        a.class_mismatched += (device.albedo.texels[i].w > 0.0f) != (ref.albedo[i].a > 0.0);
    }
    return a;
}

class BakeKernelMatchesReference : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(BakeKernelMatchesReference, OnRandomTubesAndDecalsOfEveryKind) {
    std::mt19937 rng(GetParam());
    const RestMesh tube = randomTube(rng);
    BakeAgreement total;
    for (bool cover_all : {true, false})
        for (DecalKind kind : {DecalKind::Box, DecalKind::Volume, DecalKind::Frustum, DecalKind::Cube}) {
            if (cover_all && kind != DecalKind::Box) continue;
            for (int dilation : {0, 1 + int(rng() % 6)}) {
                const DecalScene scene = randomBakeScene(tube, kind, cover_all, dilation, rng);
                const Decal& d = scene.decals[0];
                const BakedLayers device = bakeDecal(cpuDevice(), scene, d);
                const reference::BakeReference ref = reference::bakeLayers(scene, d);
                const BakeAgreement a = compareBakes(device, ref);
                std::printf("seed %u kind %d%s %d² dilation %d: %zu covered, %zu dilated, %zu reached by the decal, "
                            "%zu ambiguous, %zu off, max error %.2g\n",
                            GetParam(), int(kind), cover_all ? " (cover all)" : "", d.bake_resolution, dilation,
                            a.covered, a.dilated, a.reached, a.ambiguous, a.mismatched, a.max_error);
                EXPECT_GT(a.reached, 10u) << "the decal reaches the tube";
                EXPECT_EQ(a.mismatched, 0u) << "kind " << int(kind) << " dilation " << dilation;
                EXPECT_EQ(a.class_mismatched, 0u) << "kind " << int(kind) << " dilation " << dilation;
                if (cover_all) {
                    EXPECT_GT(a.covered, a.texels / 4) << "the tube's island fills most of the square";
                    if (dilation > 0) {
                        EXPECT_GT(a.dilated, 0u);
                    }
                }
                total.texels += a.texels;
                total.ambiguous += a.ambiguous;
                total.max_error = std::max(total.max_error, a.max_error);
            }
        }
    std::printf("seed %u: %zu of %zu texels ambiguous, max error %.2g\n", GetParam(), total.ambiguous, total.texels,
                total.max_error);
    EXPECT_LT(total.ambiguous, total.texels / 100);
}

INSTANTIATE_TEST_SUITE_P(Seeds, BakeKernelMatchesReference, ::testing::Values(1u, 2u, 3u, 4u));

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
    // The same bake gives the same bytes: no capture date in the header (OpenImageIO would stamp one).
    const std::vector<Imf::Header> headers = readExrHeaders(dir.file("layers/tube_label.exr"));
    const auto* date = headers.front().findTypedAttribute<Imf::StringAttribute>("capDate");
    EXPECT_TRUE(!date || date->value().empty()) << date->value();

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
