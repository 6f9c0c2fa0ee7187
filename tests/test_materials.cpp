// Material blending (docs/conventions.md "Materials"): the kernel against the scalar reference on
// random scenes with full texture sets, every normal encoding, hand-computed analytic cases, and
// reference::combineNormals against independent rotation math.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <sstream>

#include "decalcomp/compositor.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

using test::RandomFrame;
using test::albedoTolerance;
using test::cpuDevice;
using test::makeRandomDecals;
using test::makeRandomFrame;
using test::randomTexture;
using test::roundingMargin;

constexpr Attribute kMaterialPlanes[] = {Attribute::Albedo,   Attribute::Normal,           Attribute::Roughness,
                                         Attribute::Metallic, Attribute::AmbientOcclusion, Attribute::Emission};

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// A stored normal as a world-space unit vector, decoded here (not with the code under test).
glm::dvec3 worldNormal(const GBuffer& g, const Camera& camera, const Plane& plane, std::size_t i) {
    glm::dvec3 n(plane.at(i, 0), plane.at(i, 1), plane.at(i, 2));
    if (g.normal_encoding.packed) n = n * 2.0 - 1.0;
    // camera space -> world: the transpose of the camera's rotation
    if (g.normal_encoding.space == NormalSpace::Camera) n = glm::transpose(glm::dmat3(camera.world_to_camera)) * n;
    return glm::normalize(n);
}

// The frame's normals re-encoded (the synth frames store world, signed normals).
void encodeNormals(GBuffer& g, const Camera& camera, NormalEncoding encoding) {
    Plane& plane = g.planes.at(Attribute::Normal);
    const glm::dmat3 to_camera(camera.world_to_camera);
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        glm::dvec3 n(plane.at(i, 0), plane.at(i, 1), plane.at(i, 2));
        if (encoding.space == NormalSpace::Camera) n = to_camera * n;
        if (encoding.packed) n = n * 0.5 + 0.5;
        for (int c = 0; c < 3; ++c) plane.at(i, c) = float(n[c]);
    }
    g.normal_encoding = encoding;
}

// A random frame with every material plane: roughness, metallic, ao and emission get random values.
RandomFrame materialFrame(std::uint32_t seed) {
    RandomFrame f = makeRandomFrame(seed);
    std::mt19937 rng(seed * 977 + 5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const std::size_t n = f.gbuffer.pixelCount();
    auto randomPlane = [&](Attribute a, int components, float scale) {
        Plane p{components, std::vector<float>(n * std::size_t(components))};
        for (float& v : p.samples) v = u(rng) * scale;
        f.gbuffer.planes[a] = p;
    };
    randomPlane(Attribute::Roughness, 1, 1.0f);
    randomPlane(Attribute::Metallic, 1, 1.0f);
    randomPlane(Attribute::AmbientOcclusion, 1, 1.0f);
    randomPlane(Attribute::Emission, 3, 2.0f);
    return f;
}

// Premultiplied texels whose straight colour is in [lo, hi] per channel and alpha in [0.3, 1]
// (data textures: a tiny alpha would amplify filtering rounding in the straight value).
Texture2D dataTexture(int w, int h, int depth, TextureShape shape, std::mt19937& rng, glm::vec3 lo, glm::vec3 hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Texture2D t;
    t.source = "random data";
    t.width = w;
    t.height = h;
    t.depth = depth;
    t.shape = shape;
    for (int i = 0; i < w * h * depth; ++i) {
        const float a = 0.3f + 0.7f * u(rng);
        glm::vec3 c;
        for (int k = 0; k < 3; ++k) c[k] = lo[k] + (hi[k] - lo[k]) * u(rng);
        t.texels.emplace_back(c * a, a);
    }
    return t;
}

// Pools of normal / orm / emission textures per shape (flat, volume, cube).
struct TexturePools {
    std::array<std::vector<int>, 3> normal, orm, emission;  // by TextureShape
};

TexturePools addTexturePools(DecalScene& scene, std::mt19937& rng) {
    TexturePools pools;
    auto add = [&](std::vector<int>& pool, int shape, glm::vec3 lo, glm::vec3 hi) {
        for (int k = 0; k < 2; ++k) {
            pool.push_back(int(scene.textures.size()));
            if (shape == 0) {
                const int size = 5 + int(rng() % 12);
                scene.textures.push_back(dataTexture(size, size + int(rng() % 3), 1, TextureShape::Flat, rng, lo, hi));
            } else if (shape == 1) {
                scene.textures.push_back(dataTexture(6, 6, 5, TextureShape::Volume, rng, lo, hi));
            } else {
                scene.textures.push_back(dataTexture(7, 7, 6, TextureShape::Cube, rng, lo, hi));
            }
        }
    };
    for (int shape = 0; shape < 3; ++shape) {
        // normal maps: detail z = 2 b - 1 in [0.2, 1] (surface-facing, tilted up to 45 degrees and more)
        add(pools.normal[std::size_t(shape)], shape, glm::vec3(0.0f, 0.0f, 0.6f), glm::vec3(1.0f));
        add(pools.orm[std::size_t(shape)], shape, glm::vec3(0.0f), glm::vec3(1.0f));
        add(pools.emission[std::size_t(shape)], shape, glm::vec3(0.0f), glm::vec3(2.0f));
    }
    return pools;
}

std::size_t shapeIndex(DecalKind kind) {
    return kind == DecalKind::Volume ? 1 : kind == DecalKind::Cube ? 2 : 0;
}

// The random decal scene of test_kernels with full texture sets, random per-target effects, every
// op, every normal mode and strengths 0, 0.5, 1, 2.
DecalScene materialDecals(const RandomFrame& f, std::uint32_t seed, int count) {
    DecalScene scene = makeRandomDecals(f, seed, count);
    std::mt19937 rng(seed * 131 + 3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const TexturePools pools = addTexturePools(scene, rng);
    const float strengths[] = {0.0f, 0.5f, 1.0f, 2.0f};
    for (std::size_t k = 0; k < scene.decals.size(); ++k) {
        Decal& d = scene.decals[k];
        const std::size_t shape = shapeIndex(d.kind);
        auto pick = [&](const std::vector<int>& pool) { return pool[rng() % pool.size()]; };
        if (u(rng) < 0.25f) d.albedo_texture = -1;  // constants or the next texture give coverage
        d.normal_texture = u(rng) < 0.7f ? pick(pools.normal[shape]) : -1;
        d.orm_texture = u(rng) < 0.6f ? pick(pools.orm[shape]) : -1;
        d.emission_texture = u(rng) < 0.6f ? pick(pools.emission[shape]) : -1;
        for (int t = 0; t < kDecalTargets; ++t) {
            TargetEffect& e = d.effects[std::size_t(t)];
            const float r = u(rng);
            e.factor = r < 0.1f ? 0.0f : r < 0.7f ? 0.2f + 0.8f * u(rng) : 1.0f + 1.5f * u(rng);
            e.op = BlendOp(rng() % 4);
            if (u(rng) < 0.7f) e.value = glm::vec3(u(rng), u(rng), u(rng));
            else e.value.reset();
        }
        d.normal_blend = NormalBlend(rng() % 4);
        d.normal_strength = strengths[rng() % 4];
    }
    return scene;
}

struct PlaneReport {
    std::size_t compared = 0, changed = 0, mismatched = 0;
    double max_error = 0;
    std::string first_mismatch;
};

// Kernel output against the reference for one material plane; normals as the angle between the
// decoded world normals (radians), others as |difference| / (1 + |reference|).
PlaneReport comparePlane(const GBuffer& input, const Camera& camera, const GBuffer& output,
                         const reference::ShadeResult& ref, Attribute a, double tolerance,
                         const std::vector<std::uint8_t>* skip = nullptr) {
    PlaneReport r;
    const Plane& in = input.planes.at(a);
    const Plane& out = output.planes.at(a);
    const Plane& expected = ref.planes.at(a);
    for (std::size_t i = 0; i < input.pixelCount(); ++i) {
        bool changed = false;
        for (int c = 0; c < in.components; ++c) changed |= !sameBits(expected.at(i, c), in.at(i, c));
        r.changed += changed;
        if (ref.ambiguous[i] || (skip && (*skip)[i])) continue;
        ++r.compared;
        double error = 0;
        if (a == Attribute::Normal) {
            // (bit-exact untouched normals: MaterialNormals, where touched pixels are known exactly)
            bool same = true;
            for (int c = 0; c < 3; ++c) same &= sameBits(out.at(i, c), expected.at(i, c));
            // (NaN, e.g. a zero background normal, counts as a mismatch unless the bits agree)
            if (!same) error = angleBetween(worldNormal(input, camera, out, i), worldNormal(input, camera, expected, i));
            if (std::isnan(error)) error = 1e9;
        } else {
            for (int c = 0; c < in.components; ++c)
                error = std::max(error, std::abs(double(out.at(i, c)) - double(expected.at(i, c))) /
                                            (1.0 + std::abs(double(expected.at(i, c)))));
        }
        r.max_error = std::max(r.max_error, error);
        if (error > tolerance) {
            if (r.mismatched == 0) {
                std::ostringstream s;
                s << "pixel " << i << " (" << i % std::size_t(input.width) << ", " << i / std::size_t(input.width)
                  << "): input";
                for (int c = 0; c < in.components; ++c) s << " " << in.at(i, c);
                s << " kernel";
                for (int c = 0; c < in.components; ++c) s << " " << out.at(i, c);
                s << " reference";
                for (int c = 0; c < in.components; ++c) s << " " << expected.at(i, c);
                r.first_mismatch = s.str();
            }
            ++r.mismatched;
        }
    }
    return r;
}

// Tolerances: scalar and colour planes as albedoTolerance (relative to 1 + |value|, since add
// with factors > 1 grows emission past 1); normals as an angle. Normal maps go through a tangent
// frame built in float from a reconstructed point and the texel's straight colour.
double normalTolerance(const GBuffer& g) { return g.depth_convention == DepthConvention::Ndc ? 1e-2 : 2e-3; }
double planeTolerance(const GBuffer& g, Attribute a) { return a == Attribute::Normal ? normalTolerance(g) : albedoTolerance(g); }

GBuffer compositeOnce(const GBuffer& frame, const Camera& camera, const DecalScene& scene) {
    Compositor compositor(cpuDevice());
    compositor.setScene(scene);
    GBuffer out = frame;
    compositor.composite(out, camera);
    return out;
}

// ---------------------------------------------------------------------------------------------
// 1. Kernel vs reference, every material plane, random texture sets.

// Pixels where float rounding is amplified past what reference::shade's `ambiguous` flags (found
// by sweeping 60 seeds; each was a legitimate float-vs-double divergence, not a semantic one):
// - ill_all: within 5% of a cube decal's centre the lookup direction's error grows as 1/r (a
//   linear lookup moved by 1e-3 of the face on ndc depth); and nearest frustum lookups near a
//   texel edge at 10x the rounding margin (s = x / (2 z tan) amplifies the local point's error).
// - ill_normal: a normal-mapping decal whose tangent frame is nearly degenerate (|t_raw| or
//   |b_raw| below 0.2% of the image axis: the surface almost contains the decal's right or up),
//   where the float frame is measurably non-orthonormal (5e-3 rad seen at 1.5e-4).
struct IllConditioned {
    std::vector<std::uint8_t> all, normal;
};
IllConditioned illConditioned(const RandomFrame& f, const DecalScene& scene) {
    const GBuffer& g = f.gbuffer;
    IllConditioned out;
    DecalScene frustums = scene;  // ambiguity is per decal: the nearest frustums' alone at 10x margin
    std::erase_if(frustums.decals,
                  [](const Decal& d) { return d.kind != DecalKind::Frustum || d.filter != TextureFilter::Nearest; });
    out.all = reference::shade(g, f.camera, frustums, 10.0 * roundingMargin(g)).ambiguous;
    out.normal.assign(g.pixelCount(), 0);
    std::vector<glm::dmat4> to_local;
    for (const Decal& d : scene.decals) to_local.push_back(glm::inverse(d.world_matrix));
    const Plane& np = g.planes.at(Attribute::Normal);
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
            const auto p = reference::pixelWorldPoint(g, f.camera, x, y);
            if (!p) continue;
            const glm::dvec3 n = glm::normalize(glm::dvec3(np.at(i, 0), np.at(i, 1), np.at(i, 2)));
            for (std::size_t k = 0; k < scene.decals.size(); ++k) {
                const Decal& d = scene.decals[k];
                const glm::dvec3 l(to_local[k] * glm::dvec4(*p, 1.0));
                if (!reference::insideDecal(d, l)) continue;
                if (d.kind == DecalKind::Cube && glm::length(l) < 0.025) out.all[i] = 1;
                if (d.normal_texture < 0 || !(d.effect(DecalTarget::Normal).factor > 0.0f)) continue;
                // the frame as the first normal-mapping decal builds it (later ones see a changed
                // normal, close enough for this threshold); cube faces use any two local axes: check all three
                const glm::dmat3 axes(d.world_matrix);
                const glm::dvec3 z = d.normal_blend == NormalBlend::Replace
                                         ? (d.kind == DecalKind::Box || d.kind == DecalKind::Volume
                                                ? glm::normalize(axes[2])
                                                : glm::normalize(glm::dvec3(d.world_matrix[3]) - *p))
                                         : n;
                for (int a = 0; a < (d.kind == DecalKind::Cube ? 3 : 2); ++a)
                    if (glm::length(axes[a] - z * glm::dot(z, axes[a])) < 2e-3 * glm::length(axes[a])) out.normal[i] = 1;
                const glm::dvec3 t = glm::normalize(axes[0] - z * glm::dot(z, axes[0]));
                const glm::dvec3 b = axes[1] - z * glm::dot(z, axes[1]) - t * glm::dot(t, axes[1]);
                if (glm::length(b) < 2e-3 * glm::length(axes[1])) out.normal[i] = 1;
            }
        }
    return out;
}

class MaterialScenes : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(MaterialScenes, EveryMaterialPlaneMatchesReference) {
    const std::uint32_t seed = GetParam();
    const RandomFrame f = materialFrame(seed);
    const DecalScene scene = materialDecals(f, seed, 100);
    const GBuffer out = compositeOnce(f.gbuffer, f.camera, scene);
    const auto ref = reference::shade(f.gbuffer, f.camera, scene, roundingMargin(f.gbuffer));
    const double pixels = double(f.gbuffer.pixelCount());
    std::size_t ambiguous = 0;
    for (auto a : ref.ambiguous) ambiguous += a;
    EXPECT_LT(double(ambiguous), test::ambiguousShare(f.gbuffer) * pixels) << "too many boundary pixels";
    const IllConditioned ill = illConditioned(f, scene);
    std::vector<std::uint8_t> ill_normal = ill.normal;
    std::size_t ill_count = 0;
    for (std::size_t i = 0; i < ill_normal.size(); ++i) {
        ill_normal[i] |= ill.all[i];
        ill_count += ill_normal[i] && !ref.ambiguous[i];
    }
    for (Attribute a : kMaterialPlanes) {
        ASSERT_TRUE(out.has(a)) << attributeName(a);
        const PlaneReport r = comparePlane(f.gbuffer, f.camera, out, ref, a, planeTolerance(f.gbuffer, a),
                                           a == Attribute::Normal ? &ill_normal : &ill.all);
        if (std::getenv("MATERIALS_VERBOSE"))
            std::printf("seed %u %s: compared %zu changed %zu max error %g (tolerance %g), %zux%d px, ill %zu\n", seed,
                        attributeName(a), r.compared, r.changed, r.max_error, planeTolerance(f.gbuffer, a),
                        std::size_t(f.gbuffer.width), f.gbuffer.height, ill_count);
        EXPECT_EQ(r.mismatched, 0u) << "seed " << seed << " plane " << attributeName(a) << ": max error "
                                    << r.max_error << " over " << r.compared << " pixels; first " << r.first_mismatch;
        EXPECT_GT(double(r.compared), 0.25 * pixels) << "seed " << seed << " plane " << attributeName(a)
                                                     << ": too few pixels compared (ambiguous or ill-conditioned)";
        EXPECT_GT(double(r.changed), 0.03 * pixels) << "seed " << seed << " plane " << attributeName(a)
                                                    << " barely changed: the comparison would be hollow";
    }
    // Every kind, and mip filtering, reaches a good number of (unambiguous) pixels of this frame.
    std::array<std::size_t, 4> kind_pixels{};
    std::size_t mip_pixels = 0;
    std::vector<glm::dmat4> to_local;
    for (const Decal& d : scene.decals) to_local.push_back(glm::inverse(d.world_matrix));
    for (int y = 0; y < f.gbuffer.height; ++y)
        for (int x = 0; x < f.gbuffer.width; ++x) {
            const auto p = reference::pixelWorldPoint(f.gbuffer, f.camera, x, y);
            if (!p || ref.ambiguous[std::size_t(y) * std::size_t(f.gbuffer.width) + std::size_t(x)]) continue;
            std::array<bool, 4> hit{};
            bool mip = false;
            for (std::size_t k = 0; k < scene.decals.size(); ++k) {
                const Decal& d = scene.decals[k];
                if (d.name == "huge" || d.name == "camera_inside") continue;
                if (!reference::insideDecal(d, glm::dvec3(to_local[k] * glm::dvec4(*p, 1.0)))) continue;
                if (d.normal_texture >= 0 || d.orm_texture >= 0 || d.emission_texture >= 0) hit[std::size_t(d.kind)] = true;
                mip |= d.filter == TextureFilter::Mip;
            }
            for (int k = 0; k < 4; ++k) kind_pixels[std::size_t(k)] += hit[std::size_t(k)];
            mip_pixels += mip;
        }
    for (int k = 0; k < 4; ++k)
        EXPECT_GT(kind_pixels[std::size_t(k)], 20u) << "seed " << seed << ": kind " << decalKindName(DecalKind(k))
                                                    << " with a texture set reaches too few pixels";
    EXPECT_GT(mip_pixels, 20u) << "seed " << seed << ": mip-filtered decals reach too few pixels";
}

// Seeds 1..8: planar, radial, ndc (2: forward z, 6: reversed z), position; 4 is orthographic.
INSTANTIATE_TEST_SUITE_P(Materials, MaterialScenes, ::testing::Range(1u, 9u));

// ---------------------------------------------------------------------------------------------
// 2. Normal encodings: camera space and packed 0..1.

// Decals whose albedo is replaced by a marker colour exactly where their normal map applies (same
// factor, no albedo texture: coverage is the normal map's alpha >= 0.3), so a pixel's albedo tells
// whether its normal was touched.
const glm::vec3 kMarker(7.0f, -3.0f, 5.0f);

DecalScene markedNormalDecals(const RandomFrame& f, std::uint32_t seed) {
    DecalScene scene = makeRandomDecals(f, seed, 60);
    std::erase_if(scene.decals, [](const Decal& d) { return d.name == "huge" || d.name == "camera_inside"; });
    std::mt19937 rng(seed * 7 + 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const TexturePools pools = addTexturePools(scene, rng);
    const float strengths[] = {0.0f, 0.5f, 1.0f, 2.0f};
    for (Decal& d : scene.decals) {
        d.albedo_texture = -1;
        d.orm_texture = d.emission_texture = -1;
        const auto& pool = pools.normal[shapeIndex(d.kind)];
        d.normal_texture = pool[rng() % pool.size()];
        const float factor = 0.3f + 1.2f * u(rng);
        for (TargetEffect& e : d.effects) e = TargetEffect{0.0f, BlendOp::Over, std::nullopt};
        d.effect(DecalTarget::Albedo) = TargetEffect{factor, BlendOp::Replace, kMarker};
        d.effect(DecalTarget::Normal).factor = factor;
        d.normal_blend = NormalBlend(rng() % 4);
        d.normal_strength = strengths[rng() % 4];
    }
    return scene;
}

TEST(MaterialNormals, EveryEncodingMatchesReferenceAndKeepsUntouchedBits) {
    for (std::uint32_t seed : {1u, 3u}) {
        const RandomFrame base = materialFrame(seed);
        const DecalScene scene = markedNormalDecals(base, seed);
        const GBuffer world_out = compositeOnce(base.gbuffer, base.camera, scene);
        const auto world_ref = reference::shade(base.gbuffer, base.camera, scene, roundingMargin(base.gbuffer));
        const NormalEncoding encodings[] = {{NormalSpace::World, false},
                                            {NormalSpace::World, true},
                                            {NormalSpace::Camera, false},
                                            {NormalSpace::Camera, true}};
        for (const NormalEncoding& encoding : encodings) {
            const std::string what = "seed " + std::to_string(seed) + " encoding " +
                                     (encoding.space == NormalSpace::Camera ? "camera" : "world") +
                                     (encoding.packed ? "/packed" : "/signed");
            GBuffer in = base.gbuffer;
            encodeNormals(in, base.camera, encoding);
            const GBuffer out = compositeOnce(in, base.camera, scene);
            const auto ref = reference::shade(in, base.camera, scene, roundingMargin(in));
            for (Attribute a : {Attribute::Albedo, Attribute::Normal}) {
                const PlaneReport r = comparePlane(in, base.camera, out, ref, a, planeTolerance(in, a));
                EXPECT_EQ(r.mismatched, 0u) << what << " plane " << attributeName(a) << ": max error " << r.max_error
                                            << "; first " << r.first_mismatch;
            }
            const Plane& in_albedo = in.planes.at(Attribute::Albedo);
            const Plane& ref_albedo = world_ref.planes.at(Attribute::Albedo);
            const Plane& in_n = in.planes.at(Attribute::Normal);
            const Plane& out_n = out.planes.at(Attribute::Normal);
            std::size_t touched = 0, untouched = 0, bits_changed = 0, drifted = 0;
            double max_drift = 0;
            for (std::size_t i = 0; i < in.pixelCount(); ++i) {
                if (ref.ambiguous[i] || world_ref.ambiguous[i]) continue;
                bool marked = true, clean = true;
                for (int c = 0; c < 3; ++c) {
                    marked &= ref_albedo.at(i, c) == kMarker[c];
                    clean &= sameBits(ref_albedo.at(i, c), in_albedo.at(i, c));
                }
                if (clean) {
                    ++untouched;
                    for (int c = 0; c < 3; ++c) bits_changed += !sameBits(out_n.at(i, c), in_n.at(i, c));
                } else if (marked) {
                    ++touched;
                    const double drift = angleBetween(worldNormal(in, base.camera, out_n, i),
                                                      worldNormal(base.gbuffer, base.camera,
                                                                  world_out.planes.at(Attribute::Normal), i));
                    max_drift = std::max(max_drift, drift);
                    drifted += drift > 1e-4;
                }
            }
            EXPECT_EQ(bits_changed, 0u) << what << ": untouched normal samples changed";
            EXPECT_EQ(drifted, 0u) << what << ": touched normals differ from the world/signed run by up to "
                                   << max_drift << " rad";
            const double pixels = double(in.pixelCount());
            EXPECT_GT(double(touched), 0.05 * pixels) << what;
            EXPECT_GT(double(untouched), 0.05 * pixels) << what;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Analytic cases: a box decal on the plane z = 0, seen head-on from +Z.

Texture2D constantTexture(glm::vec3 straight, float alpha) {
    Texture2D t;
    t.source = "constant";
    t.width = t.height = 2;
    t.texels.assign(4, glm::vec4(straight * alpha, alpha));
    return t;
}

const glm::vec3 kAlbedo(0.2f, 0.4f, 0.6f), kEmission(0.1f, 0.2f, 0.3f);
constexpr float kRoughness = 0.5f, kMetallic = 0.25f, kAo = 0.8f;

struct Analytic {
    GBuffer frame;
    Camera camera;
    std::vector<std::size_t> inside, outside;  // well inside / outside the decal's 2 x 2 footprint
};

Analytic analyticFrame() {
    Analytic a;
    synth::Scene scene;
    scene.materials.push_back(synth::Material{});
    scene.planes.push_back(synth::InfinitePlane{glm::dvec3(0.0), glm::dvec3(0, 0, 1), 0});
    a.camera.world_to_camera = lookAt(glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0), glm::dvec3(0, 1, 0));
    a.camera.projection = perspectiveProjection(glm::radians(60.0), 1.0, 0.1, 100.0);
    synth::RenderOptions options;
    options.width = options.height = 32;
    a.frame = synth::render(scene, a.camera, options);
    const std::size_t n = a.frame.pixelCount();
    auto fill = [&](Attribute attr, std::vector<float> v) {
        Plane p{int(v.size()), {}};
        for (std::size_t i = 0; i < n; ++i) p.samples.insert(p.samples.end(), v.begin(), v.end());
        a.frame.planes[attr] = p;
    };
    fill(Attribute::Albedo, {kAlbedo.x, kAlbedo.y, kAlbedo.z});
    fill(Attribute::Roughness, {kRoughness});
    fill(Attribute::Metallic, {kMetallic});
    fill(Attribute::AmbientOcclusion, {kAo});
    fill(Attribute::Emission, {kEmission.x, kEmission.y, kEmission.z});
    fill(Attribute::Normal, {0.0f, 0.0f, 1.0f});
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const auto p = reference::pixelWorldPoint(a.frame, a.camera, x, y);
            if (!p) continue;
            const double e = std::max(std::abs(p->x), std::abs(p->y));
            if (e < 0.8) a.inside.push_back(std::size_t(y) * 32 + std::size_t(x));
            if (e > 1.2) a.outside.push_back(std::size_t(y) * 32 + std::size_t(x));
        }
    return a;
}

// A 2 x 2 x 1 box decal at the origin, optionally turned about Z.
Decal boxDecal(double turn_deg = 0.0) {
    Decal d;
    d.name = "box";
    d.world_matrix = glm::scale(glm::rotate(glm::dmat4(1.0), glm::radians(turn_deg), glm::dvec3(0, 0, 1)),
                                glm::dvec3(2.0, 2.0, 1.0));
    return d;
}

glm::dvec3 pixelVec3(const GBuffer& g, Attribute a, std::size_t i) {
    const Plane& p = g.planes.at(a);
    return {p.at(i, 0), p.at(i, 1), p.at(i, 2)};
}

void expectNear3(const glm::dvec3& got, const glm::dvec3& want, double tol, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tol) << what << " component " << c;
}

// Every sample of plane `a` of the pixels listed bit-identical to the input.
std::size_t changedSamples(const GBuffer& in, const GBuffer& out, Attribute a, const std::vector<std::size_t>& pixels) {
    std::size_t n = 0;
    const Plane& p = in.planes.at(a);
    const Plane& q = out.planes.at(a);
    for (std::size_t i : pixels)
        for (int c = 0; c < p.components; ++c) n += !sameBits(p.at(i, c), q.at(i, c));
    return n;
}

TEST(MaterialAnalytic, BlendOpsOnEveryTarget) {
    const Analytic a = analyticFrame();
    ASSERT_GT(a.inside.size(), 20u);
    ASSERT_GT(a.outside.size(), 20u);
    // albedo texture: straight (0.8, 0.6, 0.4), alpha 0.5 -> coverage 0.5, g = 0.5;
    // ORM: ao 0.3, roughness 0.9, metallic 0.7 (alpha 1); emission straight (2, 1, 0.5), alpha 0.5.
    struct Expected {
        BlendOp op;
        glm::dvec3 albedo;
        double roughness, ao;
        glm::dvec3 emission;  // factor 2: gt = 1, f = 1
    };
    const Expected cases[] = {
        // over: a (1 - f) + v f
        {BlendOp::Over, {0.5, 0.5, 0.5}, 0.7, 0.55, {2.0, 1.0, 0.5}},
        // multiply: a (1 - f) + a v f
        {BlendOp::Multiply, {0.18, 0.32, 0.42}, 0.475, 0.52, {0.2, 0.2, 0.15}},
        // add: a + v gt
        {BlendOp::Add, {0.6, 0.7, 0.8}, 0.95, 0.95, {2.1, 1.2, 0.8}},
        // replace: v
        {BlendOp::Replace, {0.8, 0.6, 0.4}, 0.9, 0.3, {2.0, 1.0, 0.5}},
    };
    for (const Expected& e : cases) {
        DecalScene scene;
        scene.textures = {constantTexture({0.8f, 0.6f, 0.4f}, 0.5f), constantTexture({0.3f, 0.9f, 0.7f}, 1.0f),
                          constantTexture({2.0f, 1.0f, 0.5f}, 0.5f)};
        Decal d = boxDecal();
        d.albedo_texture = 0;
        d.orm_texture = 1;
        d.emission_texture = 2;
        for (TargetEffect& t : d.effects) t = TargetEffect{1.0f, e.op, std::nullopt};
        d.effect(DecalTarget::Metallic).factor = 0.0f;  // factor 0: metallic untouched
        d.effect(DecalTarget::Emission).factor = 2.0f;
        scene.decals.push_back(d);
        const GBuffer out = compositeOnce(a.frame, a.camera, scene);
        const std::string what = std::string("op ") + blendOpName(e.op);
        for (std::size_t i : a.inside) {
            expectNear3(pixelVec3(out, Attribute::Albedo, i), e.albedo, 1e-5, what + " albedo");
            EXPECT_NEAR(out.planes.at(Attribute::Roughness).at(i, 0), e.roughness, 1e-5) << what << " roughness";
            EXPECT_NEAR(out.planes.at(Attribute::AmbientOcclusion).at(i, 0), e.ao, 1e-5) << what << " ao";
            expectNear3(pixelVec3(out, Attribute::Emission, i), e.emission, 1e-5, what + " emission");
            if (HasFailure()) return;
        }
        EXPECT_EQ(changedSamples(a.frame, out, Attribute::Metallic, a.inside), 0u) << what << ": factor 0 changed metallic";
        EXPECT_EQ(changedSamples(a.frame, out, Attribute::Normal, a.inside), 0u) << what << ": no normal map, normal changed";
        for (Attribute attr : kMaterialPlanes)
            EXPECT_EQ(changedSamples(a.frame, out, attr, a.outside), 0u) << what << ": outside the decal " << attributeName(attr);
    }
}

TEST(MaterialAnalytic, ConstantsWithoutTexturesAndFactorZero) {
    const Analytic a = analyticFrame();
    DecalScene scene;
    Decal d = boxDecal();  // no texture: coverage 1
    d.effect(DecalTarget::Albedo) = TargetEffect{0.5f, BlendOp::Over, glm::vec3(1.0f, 0.0f, 0.0f)};
    d.effect(DecalTarget::Roughness) = TargetEffect{0.25f, BlendOp::Add, glm::vec3(0.4f)};
    d.effect(DecalTarget::Metallic) = TargetEffect{3.0f, BlendOp::Multiply, glm::vec3(0.5f)};  // f = 1
    d.effect(DecalTarget::AmbientOcclusion) = TargetEffect{0.0f, BlendOp::Replace, glm::vec3(0.1f)};
    d.effect(DecalTarget::Emission) = TargetEffect{1.0f, BlendOp::Replace, std::nullopt};  // no value: untouched
    scene.decals.push_back(d);
    const GBuffer out = compositeOnce(a.frame, a.camera, scene);
    for (std::size_t i : a.inside) {
        expectNear3(pixelVec3(out, Attribute::Albedo, i), {0.6, 0.2, 0.3}, 1e-6, "albedo over 0.5");
        EXPECT_NEAR(out.planes.at(Attribute::Roughness).at(i, 0), 0.5 + 0.4 * 0.25, 1e-6);
        EXPECT_NEAR(out.planes.at(Attribute::Metallic).at(i, 0), 0.25 * 0.5, 1e-6);
        if (HasFailure()) return;
    }
    EXPECT_EQ(changedSamples(a.frame, out, Attribute::AmbientOcclusion, a.inside), 0u) << "factor 0";
    EXPECT_EQ(changedSamples(a.frame, out, Attribute::Emission, a.inside), 0u) << "no texture, no value";
}

TEST(MaterialAnalytic, TargetMissingFromFrameIsSkipped) {
    Analytic a = analyticFrame();
    a.frame.planes.erase(Attribute::Emission);
    a.frame.planes.erase(Attribute::Metallic);
    DecalScene scene;
    scene.textures = {constantTexture({0.8f, 0.6f, 0.4f}, 0.5f), constantTexture({2.0f, 1.0f, 0.5f}, 1.0f)};
    Decal d = boxDecal();
    d.albedo_texture = 0;
    d.emission_texture = 1;
    d.effect(DecalTarget::Metallic) = TargetEffect{1.0f, BlendOp::Replace, glm::vec3(0.9f)};
    d.effect(DecalTarget::Roughness) = TargetEffect{1.0f, BlendOp::Replace, glm::vec3(0.1f)};
    scene.decals.push_back(d);
    GBuffer out;
    ASSERT_NO_THROW(out = compositeOnce(a.frame, a.camera, scene));
    EXPECT_FALSE(out.has(Attribute::Emission));
    EXPECT_FALSE(out.has(Attribute::Metallic));
    for (std::size_t i : a.inside) {
        expectNear3(pixelVec3(out, Attribute::Albedo, i), {0.5, 0.5, 0.5}, 1e-5, "albedo over");
        EXPECT_NEAR(out.planes.at(Attribute::Roughness).at(i, 0), 0.1, 1e-6);  // replace
        if (HasFailure()) return;
    }
    // the reference agrees and skips the missing planes too
    const auto ref = reference::shade(a.frame, a.camera, scene);
    EXPECT_EQ(ref.planes.count(Attribute::Emission), 0u);
    EXPECT_EQ(ref.planes.at(Attribute::Roughness).samples, out.planes.at(Attribute::Roughness).samples);
}

// A normal map of one straight colour; alpha 1 (coverage 1, f = 1) unless given.
DecalScene normalMapScene(glm::vec3 rgb, NormalBlend mode, float strength, double turn_deg = 0.0, float alpha = 1.0f) {
    DecalScene scene;
    scene.textures = {constantTexture(rgb, alpha)};
    Decal d = boxDecal(turn_deg);
    d.normal_texture = 0;
    d.normal_blend = mode;
    d.normal_strength = strength;
    scene.decals.push_back(d);
    return scene;
}

// The straight rgb of a unit detail normal.
glm::vec3 encodeDetail(glm::dvec3 detail) { return glm::vec3(glm::normalize(detail) * 0.5 + 0.5); }

TEST(MaterialAnalytic, FlatNormalMapKeepsNormals) {
    const Analytic a = analyticFrame();
    for (NormalBlend mode : {NormalBlend::Reoriented, NormalBlend::Whiteout, NormalBlend::Udn, NormalBlend::Replace}) {
        const GBuffer out = compositeOnce(a.frame, a.camera, normalMapScene({0.5f, 0.5f, 1.0f}, mode, 1.0f));
        for (std::size_t i : a.inside)
            EXPECT_LT(angleBetween(pixelVec3(out, Attribute::Normal, i), {0, 0, 1}), 1e-3) << normalBlendName(mode);
        EXPECT_EQ(changedSamples(a.frame, out, Attribute::Normal, a.outside), 0u);
    }
    // An 8-bit "flat" texel (128, 128, 255) is 128/255 = 0.50196, not 0.5: detail (1/255, 1/255, 1)
    // before normalizing, a tilt of atan(sqrt(2) / 255) = 5.5 mrad toward the decal's +X+Y diagonal.
    const float v = 128.0f / 255.0f;
    const GBuffer out = compositeOnce(a.frame, a.camera, normalMapScene({v, v, 1.0f}, NormalBlend::Reoriented, 1.0f));
    const double tilt = std::atan(std::sqrt(2.0) * (2.0 * 128.0 / 255.0 - 1.0));
    for (std::size_t i : a.inside)
        EXPECT_NEAR(angleBetween(pixelVec3(out, Attribute::Normal, i), {0, 0, 1}), tilt, 1e-4);
}

TEST(MaterialAnalytic, TiltedNormalMapTiltsTowardDecalX) {
    const Analytic a = analyticFrame();
    const glm::dvec3 detail = glm::normalize(glm::dvec3(0.5, 0.0, 1.0));
    const glm::vec3 rgb = encodeDetail(detail);
    // surface (0,0,1), frame t = decal X, b = decal Y: RNM and whiteout give the detail itself,
    // UDN normalize(d.x, d.y, 1).
    struct Case {
        NormalBlend mode;
        double angle;
    };
    const Case cases[] = {{NormalBlend::Reoriented, std::atan(0.5)},
                          {NormalBlend::Whiteout, std::atan(0.5)},
                          {NormalBlend::Udn, std::atan(detail.x / 1.0)},
                          {NormalBlend::Replace, std::atan(0.5)}};
    for (double turn : {0.0, 90.0}) {
        const glm::dvec3 x_axis(std::cos(glm::radians(turn)), std::sin(glm::radians(turn)), 0.0);
        for (const Case& c : cases) {
            const GBuffer out = compositeOnce(a.frame, a.camera, normalMapScene(rgb, c.mode, 1.0f, turn));
            const glm::dvec3 want = x_axis * std::sin(c.angle) + glm::dvec3(0, 0, 1) * std::cos(c.angle);
            for (std::size_t i : a.inside)
                expectNear3(pixelVec3(out, Attribute::Normal, i), want, 1e-5,
                            std::string(normalBlendName(c.mode)) + " turn " + std::to_string(turn));
            if (HasFailure()) return;
        }
    }
    // alpha 0.5: f = 0.5 mixes (0,0,1) with the RNM result: the bisector, half the angle.
    const GBuffer half = compositeOnce(a.frame, a.camera, normalMapScene(rgb, NormalBlend::Reoriented, 1.0f, 0.0, 0.5f));
    for (std::size_t i : a.inside)
        expectNear3(pixelVec3(half, Attribute::Normal, i), {std::sin(std::atan(0.5) / 2), 0, std::cos(std::atan(0.5) / 2)},
                    1e-5, "half coverage");
    // strength 2 doubles the tangent part before normalizing: atan(2 * 0.5) = 45 degrees
    const GBuffer doubled = compositeOnce(a.frame, a.camera, normalMapScene(rgb, NormalBlend::Reoriented, 2.0f));
    for (std::size_t i : a.inside)
        expectNear3(pixelVec3(doubled, Attribute::Normal, i), {std::sqrt(0.5), 0, std::sqrt(0.5)}, 1e-5, "strength 2");
    // strength 0: flat
    for (NormalBlend mode : {NormalBlend::Reoriented, NormalBlend::Udn, NormalBlend::Whiteout}) {
        const GBuffer flat = compositeOnce(a.frame, a.camera, normalMapScene(rgb, mode, 0.0f));
        for (std::size_t i : a.inside)
            EXPECT_LT(angleBetween(pixelVec3(flat, Attribute::Normal, i), {0, 0, 1}), 1e-6) << normalBlendName(mode);
    }
}

TEST(MaterialAnalytic, ReplaceIgnoresSurfaceTiltWhileRnmFollowsIt) {
    Analytic a = analyticFrame();
    const double tilt = glm::radians(20.0);
    Plane& n = a.frame.planes.at(Attribute::Normal);
    for (std::size_t i = 0; i < a.frame.pixelCount(); ++i) {
        n.at(i, 0) = float(std::sin(tilt));
        n.at(i, 1) = 0.0f;
        n.at(i, 2) = float(std::cos(tilt));
    }
    const glm::dvec3 detail = glm::normalize(glm::dvec3(0.5, 0.0, 1.0));
    const glm::vec3 rgb = encodeDetail(detail);
    const double d_angle = std::atan(0.5);
    // replace: the frame is the decal's own (facing +Z, t = +X): the detail as is
    const GBuffer replaced = compositeOnce(a.frame, a.camera, normalMapScene(rgb, NormalBlend::Replace, 1.0f));
    // RNM: the frame's z is the tilted normal and t = +X projected on its plane, so the detail's
    // tilt adds to the surface's: 20 + 26.57 degrees toward +X
    const GBuffer rnm = compositeOnce(a.frame, a.camera, normalMapScene(rgb, NormalBlend::Reoriented, 1.0f));
    for (std::size_t i : a.inside) {
        expectNear3(pixelVec3(replaced, Attribute::Normal, i), detail, 1e-5, "replace");
        expectNear3(pixelVec3(rnm, Attribute::Normal, i), {std::sin(tilt + d_angle), 0, std::cos(tilt + d_angle)}, 1e-5,
                    "rnm");
        if (HasFailure()) return;
    }
    // the reference agrees with both
    for (const GBuffer* g : {&replaced, &rnm}) {
        const auto ref = reference::shade(a.frame, a.camera,
                                          normalMapScene(rgb, g == &replaced ? NormalBlend::Replace : NormalBlend::Reoriented, 1.0f));
        for (std::size_t i : a.inside)
            EXPECT_LT(angleBetween(pixelVec3(*g, Attribute::Normal, i),
                                   {ref.planes.at(Attribute::Normal).at(i, 0), ref.planes.at(Attribute::Normal).at(i, 1),
                                    ref.planes.at(Attribute::Normal).at(i, 2)}),
                      1e-5);
    }
}

// ---------------------------------------------------------------------------------------------
// 4. reference::combineNormals and reference::blend against independent math.

glm::dvec3 randomUnit(std::mt19937& rng, double min_z) {
    std::normal_distribution<double> g;
    for (;;) {
        const glm::dvec3 v = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
        if (v.z >= min_z) return v;
    }
}

TEST(MaterialReference, RnmWithFlatBaseReturnsDetail) {
    std::mt19937 rng(11);
    for (int k = 0; k < 200; ++k) {
        const glm::dvec3 d = randomUnit(rng, -1.0);
        expectNear3(reference::combineNormals({0, 0, 1}, d, NormalBlend::Reoriented), d, 1e-12, "rnm flat base");
    }
}

TEST(MaterialReference, RnmRotatesDetailByTheRotationTakingZToBase) {
    std::mt19937 rng(12);
    for (int k = 0; k < 500; ++k) {
        const glm::dvec3 b = randomUnit(rng, -0.95), d = randomUnit(rng, -1.0);
        const glm::dvec3 axis = glm::cross(glm::dvec3(0, 0, 1), b);
        const double angle = std::acos(std::clamp(b.z, -1.0, 1.0));
        const glm::dquat q = glm::length(axis) > 1e-12 ? glm::angleAxis(angle, glm::normalize(axis)) : glm::dquat(1, 0, 0, 0);
        const glm::dvec3 want = q * d;
        const glm::dvec3 got = reference::combineNormals(b, d, NormalBlend::Reoriented);
        expectNear3(got, want, 1e-9, "rnm rotation");
        EXPECT_NEAR(glm::dot(got, b), d.z, 1e-9);  // the detail's angle to +Z becomes the angle to base
        expectNear3(reference::combineNormals(b, {0, 0, 1}, NormalBlend::Reoriented), b, 1e-12, "rnm flat detail");
        if (HasFailure()) return;
    }
}

TEST(MaterialReference, UdnWhiteoutReplaceClosedForms) {
    // base (0,0,1): UDN keeps z = 1 under the detail's xy; whiteout gives the detail back
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.0, 1.0));  // (0.7071, 0, 0.7071)
    const double s = std::sqrt(0.5);
    expectNear3(reference::combineNormals({0, 0, 1}, d, NormalBlend::Udn), glm::dvec3(s, 0, 1) / std::sqrt(1.5), 1e-12, "udn");
    expectNear3(reference::combineNormals({0, 0, 1}, d, NormalBlend::Whiteout), d, 1e-12, "whiteout");
    // a tilted base: b = (0.6, 0, 0.8), d = (0, 0.6, 0.8)
    const glm::dvec3 b(0.6, 0.0, 0.8), e(0.0, 0.6, 0.8);
    // UDN: (0.6, 0.6, 0.8) / sqrt(1.36); whiteout: (0.6, 0.6, 0.64) / sqrt(1.1296)
    expectNear3(reference::combineNormals(b, e, NormalBlend::Udn), glm::dvec3(0.6, 0.6, 0.8) / std::sqrt(1.36), 1e-12, "udn tilted");
    expectNear3(reference::combineNormals(b, e, NormalBlend::Whiteout), glm::dvec3(0.6, 0.6, 0.64) / std::sqrt(1.1296), 1e-12,
                "whiteout tilted");
    expectNear3(reference::combineNormals(b, e, NormalBlend::Replace), e, 0.0, "replace");
    // RNM of the same pair: rotation by 36.87 degrees about +Y applied to e
    const double c = 0.8, sn = 0.6;
    expectNear3(reference::combineNormals(b, e, NormalBlend::Reoriented), {sn * 0.8, 0.6, c * 0.8}, 1e-12, "rnm tilted");
}

TEST(MaterialReference, BlendOps) {
    // a = 0.4, v = 0.9
    EXPECT_NEAR(reference::blend(0.4, 0.9, 0.25, BlendOp::Over), 0.4 * 0.75 + 0.9 * 0.25, 1e-15);
    EXPECT_NEAR(reference::blend(0.4, 0.9, 2.0, BlendOp::Over), 0.9, 1e-15);  // f clamps to 1
    EXPECT_NEAR(reference::blend(0.4, 0.9, 0.25, BlendOp::Multiply), 0.4 * 0.75 + 0.4 * 0.9 * 0.25, 1e-15);
    EXPECT_NEAR(reference::blend(0.4, 0.9, 2.0, BlendOp::Add), 0.4 + 1.8, 1e-15);  // add uses g unclamped
    EXPECT_EQ(reference::blend(0.4, 0.9, 1e-9, BlendOp::Replace), 0.9);
    EXPECT_EQ(reference::blend(0.4, 0.9, 0.0, BlendOp::Replace), 0.4);
}

}  // namespace
}  // namespace decalcomp
