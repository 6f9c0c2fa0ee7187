// Decals integrated over the renderer's pixel filter (docs/pixel-filter.md): the filter and its
// quadrature, the kernel against the scalar reference on PoCL, and both against the exact
// filtered truth of supersampled analytic frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <vector>

#include "decalcomp/compositor.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_antialias.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

const PixelFilter kBlackmanHarris3{PixelFilterType::BlackmanHarris, 3.0};
const PixelFilter kGaussian2{PixelFilterType::Gaussian, 2.0};
const PixelFilter kBox1{PixelFilterType::Box, 1.0};

TEST(PixelFilter, ParsesItsSpellings) {
    EXPECT_FALSE(parsePixelFilter("none", "--pixel-filter").enabled());
    const PixelFilter bh = parsePixelFilter("blackman-harris:3", "--pixel-filter");
    EXPECT_EQ(bh.type, PixelFilterType::BlackmanHarris);
    EXPECT_DOUBLE_EQ(bh.width, 3.0);
    EXPECT_DOUBLE_EQ(bh.radius(), 1.5);
    EXPECT_DOUBLE_EQ(parsePixelFilter("gaussian:2", "x").radius(), 1.5);  // 3 sigma, sigma = width / 4
    EXPECT_DOUBLE_EQ(parsePixelFilter("box:1.5", "x").radius(), 0.75);
    for (const char* text : {"none", "box:1", "gaussian:2", "blackman-harris:3", "box:1.5", "blackman-harris:3:fast"})
        EXPECT_EQ(parsePixelFilter(text, "x").spelling(), text);
    EXPECT_FALSE(bh.fast);
    const PixelFilter fast = parsePixelFilter("gaussian:2:fast", "x");
    EXPECT_TRUE(fast.fast);
    EXPECT_DOUBLE_EQ(fast.width, 2.0);
    EXPECT_FALSE(fast == parsePixelFilter("gaussian:2", "x"));  // a sequence does not mix the two
}

TEST(PixelFilter, RefusesAnythingElseNamingTheOption) {
    for (const char* text : {"", "gauss:2", "box", "box:", "box:0", "box:-1", "box:9", "box:1x", "box:nan", "auto", "box:1:", "box:1:slow", "box::fast", "none:fast"}) {
        try {
            parsePixelFilter(text, "--pixel-filter");
            ADD_FAILURE() << "accepted '" << text << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Input);
            EXPECT_NE(std::string(e.what()).find("--pixel-filter: '" + std::string(text) + "'"), std::string::npos)
                << e.what();
        }
    }
}

TEST(PixelFilter, WeightsFollowTheirDefinitions) {
    // Blackman-Harris: 1 at the centre (the four coefficients sum to 1), ~6e-5 at the support's end
    EXPECT_NEAR(kBlackmanHarris3.weight1d(0.0), 1.0, 1e-12);
    EXPECT_NEAR(kBlackmanHarris3.weight1d(1.5), 6e-5, 1e-5);
    EXPECT_EQ(kBlackmanHarris3.weight1d(1.51), 0.0);
    // Gaussian exp(-2 (2x / w)^2): exp(-2) at x = w / 2
    EXPECT_NEAR(kGaussian2.weight1d(1.0), std::exp(-2.0), 1e-12);
    EXPECT_EQ(kBox1.weight1d(0.49), 1.0);
    EXPECT_EQ(kBox1.weight1d(0.51), 0.0);
}

// The taps are strata centroids weighted by the filter's integral over each stratum: they sum to
// 1, are symmetric, and hold the (kept) filter's variance but for what lies within the strata (at
// most a box's step^2 / 12 for these smooth filters). Blackman-Harris 3 px keeps its central
// 2 px: its outer strata hold 0.46 % of the mass each.
TEST(PixelFilter, QuadratureIntegratesTheFilter) {
    for (const PixelFilter& f : {kBlackmanHarris3, kGaussian2, kBox1, PixelFilter{PixelFilterType::Gaussian, 8.0}}) {
        const FilterQuadrature q = filterQuadrature(f);
        const std::size_t n = q.offsets.size();
        ASSERT_GE(n, 4u) << f.spelling();
        ASSERT_LE(n, std::size_t(kMaxFilterTaps)) << f.spelling();
        // strata cover the support, less end strata holding under 1 % of the mass each
        const double kept = 0.5 * q.step * double(n);
        EXPECT_LE(kept, f.radius() + 1e-12);
        EXPECT_GE(f.weight1d(kept), 0.0);
        double sum = 0, variance = 0;
        for (std::size_t i = 0; i < n; ++i) {
            sum += q.weights[i];
            variance += q.weights[i] * q.offsets[i] * q.offsets[i];
            EXPECT_NEAR(q.offsets[i], -q.offsets[n - 1 - i], 1e-12);
            EXPECT_NEAR(q.weights[i], q.weights[n - 1 - i], 1e-12);
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);
        double mass = 0, second = 0;  // the kept filter's variance, by fine midpoint integration
        const int steps = 200000;
        for (int k = 0; k < steps; ++k) {
            const double x = -kept + (k + 0.5) * 2.0 * kept / steps;
            mass += f.weight1d(x);
            second += f.weight1d(x) * x * x;
        }
        EXPECT_LE(variance, second / mass + 1e-9) << f.spelling();
        EXPECT_GE(variance + q.step * q.step / 12.0, second / mass) << f.spelling();
    }
    EXPECT_TRUE(filterQuadrature(PixelFilter{}).offsets.empty());
    EXPECT_EQ(filterQuadrature(kBlackmanHarris3).offsets.size(), 4u);  // 6 strata less the tails
    EXPECT_EQ(filterQuadrature(kGaussian2).offsets.size(), 6u);        // its tails hold 2.1 % each
}

// The edge-spread function against a brute-force 2D sum of the separable filter over a fine grid,
// for edges at several angles and distances, and its table as the kernels interpolate it.
TEST(PixelFilter, EdgeSpreadIsTheFiltersShareBesideAnEdge) {
    for (const PixelFilter& f : {kBlackmanHarris3, kGaussian2, kBox1}) {
        const std::vector<double> table = edgeSpreadTable(f);
        const double r = f.radius();
        const int n = 1200;  // cells of 1/400 px and less: the sum's step error stays under 1e-3
        std::vector<double> at(n), w(n);
        for (int i = 0; i < n; ++i) {
            at[std::size_t(i)] = -r + (i + 0.5) * 2 * r / n;
            w[std::size_t(i)] = f.weight1d(at[std::size_t(i)]);
        }
        for (const double angle : {0.0, 0.3, 0.7854, 1.2, 2.5}) {
            const double nx = std::cos(angle), ny = std::sin(angle);
            for (const double d : {-1.2, -0.6, -0.2, 0.0, 0.1, 0.45, 0.9}) {
                double inside = 0, total = 0;
                for (std::size_t j = 0; j < at.size(); ++j)
                    for (std::size_t i = 0; i < at.size(); ++i) {
                        total += w[i] * w[j];
                        if (nx * at[i] + ny * at[j] <= d) inside += w[i] * w[j];
                    }
                const double truth = inside / total;
                EXPECT_NEAR(edgeSpread(f, nx, ny, d), truth, 2e-3) << f.spelling() << " angle " << angle << " d " << d;
                // a quantity growing 0.7 per pixel along n, its edge `d` pixels out
                EXPECT_NEAR(edgeSpreadFromTable(table, r, 0.7 * nx, 0.7 * ny, 0.7 * d), truth, 4e-3)
                    << f.spelling() << " angle " << angle << " d " << d;
            }
        }
        EXPECT_NEAR(edgeSpread(f, 1.0, 0.0, 0.0), 0.5, 1e-9);
        EXPECT_EQ(edgeSpreadFromTable(table, r, 0.0, 0.0, 0.2), 1.0);  // a flat quantity: the hard test
        EXPECT_EQ(edgeSpreadFromTable(table, r, 0.0, 0.0, -0.2), 0.0);
    }
    // the box of Blackman-Harris 3 px's variance (sigma 0.416 px, docs/pixel-filter.md)
    EXPECT_NEAR(equivalentBoxWidth(kBlackmanHarris3), std::sqrt(12.0) * 0.416, 0.01);
    EXPECT_NEAR(equivalentBoxWidth(kBox1), 1.0, 1e-6);
}

// ---- the kernel against the scalar reference, on random scenes of every kind and convention

class FilteredRandomScenes : public ::testing::TestWithParam<std::uint32_t> {};

PixelFilter filterFor(std::uint32_t seed) {
    const PixelFilter filters[] = {kBlackmanHarris3, kGaussian2, kBox1};
    return filters[seed % 3];
}

TEST_P(FilteredRandomScenes, KernelMatchesReference) {
    test::RandomFrame f = test::makeRandomFrame(GetParam());
    f.gbuffer.pixel_filter = filterFor(GetParam());
    test::expectFilteredKernelMatchesReference(f, test::makeRandomDecals(f, GetParam(), 300));
}

// Binning widens each decal's tiles and depth range by the taps' reach: dropping a decal that a
// tap reaches would make binned and unbinned differ.
TEST_P(FilteredRandomScenes, BinnedEqualsUnbinnedExactly) {
    test::RandomFrame f = test::makeRandomFrame(GetParam());
    f.gbuffer.pixel_filter = filterFor(GetParam());
    EXPECT_EQ(test::binnedUnbinnedDifferences(f, test::makeRandomDecals(f, GetParam(), 300)), 0u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, FilteredRandomScenes, ::testing::Values(1u, 2u, 3u, 4u));

// The closed form maps each footprint linearly onto the decal, so a projector's edges reach a little
// past its exact projection (binning widens fast frames' pixel ranges by two pixels more), and it
// integrates the filter to its last tails, which the binned depth ranges leave out: binned and
// unbinned agree within 1e-4 (measured up to 1.1e-5 on these scenes) on a few samples, exactly
// elsewhere.
TEST_P(FilteredRandomScenes, FastBinnedEqualsUnbinnedWithinTheTails) {
    test::RandomFrame f = test::makeRandomFrame(GetParam());
    f.gbuffer.pixel_filter = filterFor(GetParam());
    f.gbuffer.pixel_filter.fast = true;
    Compositor compositor(test::cpuDevice());
    compositor.setScene(test::makeRandomDecals(f, GetParam(), 300));
    GBuffer binned = f.gbuffer, unbinned = f.gbuffer;
    compositor.composite(binned, f.camera, {true});
    compositor.composite(unbinned, f.camera, {false});
    const auto& a = binned.planes.at(Attribute::Albedo).samples;
    const auto& b = unbinned.planes.at(Attribute::Albedo).samples;
    ASSERT_EQ(a.size(), b.size());
    std::size_t differing = 0, changed = 0;
    float worst = 0.0f;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::abs(a[i] - b[i]));
        differing += a[i] != b[i];
        changed += a[i] != f.gbuffer.planes.at(Attribute::Albedo).samples[i];
    }
    EXPECT_LE(worst, 1e-4f);
    EXPECT_LT(differing, 50u);
    EXPECT_GT(changed, a.size() / 20);
}

// ---- exact filtered truth: the demo scene rendered kFactor times finer, its decals composited
// point-sampled there by the reference, then both filtered down as a renderer filters samples.

constexpr int kWidth = 160, kHeight = 120, kFactor = 6;

struct FilteredTruth {
    GBuffer frame;  // antialiased G-buffer
    Camera camera;
    Plane truth;                      // filtered decal-composited albedo
    std::vector<std::uint8_t> decal;  // pixels some decal changes in the truth
};

FilteredTruth filteredTruth(const DecalScene& decals, const PixelFilter& filter) {
    const Camera fine_camera = synth::demoCamera(kWidth * kFactor, kHeight * kFactor);
    const GBuffer fine =
        synth::render(synth::demoScene(), fine_camera, synth::RenderOptions{kWidth * kFactor, kHeight * kFactor});
    const reference::ShadeResult composited = reference::shade(fine, fine_camera, decals);
    FilteredTruth t;
    t.frame = synth::filterDown(fine, kFactor, filter);
    t.camera = synth::demoCamera(kWidth, kHeight);
    t.truth = synth::filterDown(composited.albedo, fine.width, fine.height, kFactor, filter);
    const Plane& before = t.frame.planes.at(Attribute::Albedo);
    for (std::size_t i = 0; i < t.frame.pixelCount(); ++i) {
        double change = 0;
        for (int c = 0; c < 3; ++c) change = std::max(change, double(std::abs(t.truth.at(i, c) - before.at(i, c))));
        t.decal.push_back(change > 1e-4 ? 1 : 0);
    }
    return t;
}

DecalScene scatteredDecals(std::uint32_t seed, int count) {
    const Camera camera = synth::demoCamera(kWidth, kHeight);
    const GBuffer frame = synth::render(synth::demoScene(), camera, synth::RenderOptions{kWidth, kHeight});
    synth::ScatterOptions scatter;
    scatter.count = count;
    scatter.min_size = 0.4;
    scatter.max_size = 1.2;
    scatter.texture_size = 16;  // texels of a few pixels: texture edges matter as much as decal edges
    scatter.seed = seed;
    return synth::scatterDecals(frame, camera, scatter);
}

GBuffer compositeOnCpu(const GBuffer& frame, const Camera& camera, const DecalScene& decals) {
    Compositor compositor(test::cpuDevice());
    compositor.setScene(decals);
    GBuffer out = frame;
    compositor.composite(out, camera);
    return out;
}

// Pixels beside a depth jump of more than 1 % (silhouettes: mixed pixels and their neighbours).
std::vector<std::uint8_t> silhouettePixels(const GBuffer& frame) {
    const Plane& z = frame.planes.at(Attribute::Depth);
    std::vector<std::uint8_t> out(frame.pixelCount(), 0);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x)
            for (int k = 0; k < 4; ++k) {
                const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
                if (nx < 0 || ny < 0 || nx >= frame.width || ny >= frame.height) continue;
                const double a = z.at(std::size_t(y) * frame.width + x, 0), b = z.at(std::size_t(ny) * frame.width + nx, 0);
                if (std::abs(a - b) > 0.01 * a) out[std::size_t(y) * frame.width + x] = 1;
            }
    return out;
}

// Pixels whose normal pass is shorter than 0.995 without a 4-neighbour 2 % away in depth: the
// creases of an antialiased frame (docs/pixel-filter.md "Creases").
std::vector<std::uint8_t> creasePixels(const GBuffer& frame) {
    const Plane& n = frame.planes.at(Attribute::Normal);
    const Plane& z = frame.planes.at(Attribute::Depth);
    std::vector<std::uint8_t> out(frame.pixelCount(), 0);
    for (int y = 1; y + 1 < frame.height; ++y)
        for (int x = 1; x + 1 < frame.width; ++x) {
            const std::size_t i = std::size_t(y) * frame.width + x;
            if (!(glm::length(glm::dvec3(n.at(i, 0), n.at(i, 1), n.at(i, 2))) < 0.995)) continue;
            bool jump = false;
            for (int k = 0; k < 4; ++k) {
                const std::size_t j = std::size_t(y + (k == 2) - (k == 3)) * frame.width + x + (k == 0) - (k == 1);
                jump = jump || std::abs(z.at(j, 0) - z.at(i, 0)) > 0.02 * z.at(i, 0);
            }
            out[i] = jump ? 0 : 1;
        }
    return out;
}

// PSNR (peak 1) of the albedo against the truth over the decal pixels (with `select`, only those
// whose select flag equals `value`).
double decalPsnr(const GBuffer& out, const FilteredTruth& t, const std::vector<std::uint8_t>* select = nullptr,
                 std::uint8_t value = 1) {
    double squared = 0;
    std::size_t samples = 0;
    for (std::size_t i = 0; i < t.frame.pixelCount(); ++i)
        if (t.decal[i] && (!select || (*select)[i] == value))
            for (int c = 0; c < 3; ++c) {
                const double e = double(out.planes.at(Attribute::Albedo).at(i, c)) - t.truth.at(i, c);
                squared += e * e;
                ++samples;
            }
    return 10.0 * std::log10(double(samples) / std::max(squared, 1e-30));
}

// Measured (6x truth, 24 decals of 16^2 texels on the demo scene), with silhouette pixels split
// between their surfaces (docs/pixel-filter.md "Silhouettes") and decals stacked per tap:
// blackman-harris:3 40.1 dB (49.5 away from silhouettes, 36.1 beside them), point-sampled 26.9;
// gaussian:2 40.1 (50.7, 36.1), point 26.4; box:1 39.4 (51.1, 34.9), point 27.3. With the averaged plane at silhouettes instead: 33.4, 33.4 and
// 34.5 beside them (this generator averages depth, where Cycles writes one sample's).
TEST(PixelFilterTruth, FilteredDecalsMatchSupersampledTruth) {
    const DecalScene decals = scatteredDecals(7, 24);
    const std::map<std::string, double> beside_silhouettes{
        {kBlackmanHarris3.spelling(), 36.1}, {kGaussian2.spelling(), 36.05}, {kBox1.spelling(), 34.9}};
    for (const PixelFilter& filter : {kBlackmanHarris3, kGaussian2, kBox1}) {
        const FilteredTruth t = filteredTruth(decals, filter);
        ASSERT_GT(std::count(t.decal.begin(), t.decal.end(), 1), 2000) << "decals cover too few pixels";
        GBuffer point_frame = t.frame;
        point_frame.pixel_filter = {};
        const GBuffer out = compositeOnCpu(t.frame, t.camera, decals);
        const std::vector<std::uint8_t> silhouette = silhouettePixels(t.frame);
        const double filtered = decalPsnr(out, t), smooth = decalPsnr(out, t, &silhouette, 0);
        const double point = decalPsnr(compositeOnCpu(point_frame, t.camera, decals), t);
        const double beside = decalPsnr(out, t, &silhouette, 1);
        const std::vector<std::uint8_t> creases = creasePixels(t.frame);
        const double crease = decalPsnr(out, t, &creases, 1);
        std::printf("%s: filtered %.2f dB (%.2f away from silhouettes, %.2f beside them, %.2f at creases), "
                    "point-sampled %.2f dB\n",
                    filter.spelling().c_str(), filtered, smooth, beside, crease, point);
        EXPECT_GE(beside, beside_silhouettes.at(filter.spelling()) - 0.3) << filter.spelling();
        RecordProperty("psnr_db_" + filter.spelling(), std::to_string(filtered));
        EXPECT_GE(filtered, 36.0) << filter.spelling();
        EXPECT_GE(smooth, 45.0) << filter.spelling();
        EXPECT_GE(filtered, point + 9.0) << filter.spelling() << " against point-sampled " << point;
    }
}

// The closed form (`:fast`, docs/pixel-filter.md "Integrated evaluation") against the same truth:
// each decal once per pixel, blended one at a time. Measured (this scene, 16^2 texels, half of the
// decals bilinear) away from silhouettes: blackman-harris:3 40.42 dB, gaussian:2 39.05, box:1 41.54
// (whole decals 34.9, 34.1, 35.4; point-sampled 26.9, 26.4, 27.3); the taps' figures above are the ceiling it trades for speed.
TEST(PixelFilterTruth, FastDecalsMatchSupersampledTruth) {
    const DecalScene decals = scatteredDecals(7, 24);
    const std::map<std::string, double> floor_db{{"blackman-harris:3", 40.42}, {"gaussian:2", 39.05}, {"box:1", 41.54}};
    for (PixelFilter filter : {kBlackmanHarris3, kGaussian2, kBox1}) {
        const FilteredTruth t = filteredTruth(decals, filter);
        GBuffer frame = t.frame;
        frame.pixel_filter.fast = true;
        GBuffer point_frame = t.frame;
        point_frame.pixel_filter = {};
        const GBuffer out = compositeOnCpu(frame, t.camera, decals);
        const std::vector<std::uint8_t> silhouette = silhouettePixels(t.frame);
        const double filtered = decalPsnr(out, t), smooth = decalPsnr(out, t, &silhouette, 0);
        const double point = decalPsnr(compositeOnCpu(point_frame, t.camera, decals), t);
        std::printf("%s:fast: filtered %.2f dB (%.2f away from silhouettes), point-sampled %.2f dB\n",
                    filter.spelling().c_str(), filtered, smooth, point);
        EXPECT_GE(smooth, floor_db.at(filter.spelling()) - 0.3) << filter.spelling();
        EXPECT_GE(filtered, point + 6.0) << filter.spelling();
    }
}

// The kernel against the reference on antialiased frames, whose creases and silhouettes split
// their taps between two surfaces: the random frames of FilteredRandomScenes have unit normals.
TEST(PixelFilterTruth, KernelMatchesReferenceOnAntialiasedFrames) {
    const DecalScene decals = scatteredDecals(7, 24);
    for (const PixelFilter& filter : {kBlackmanHarris3, kGaussian2, kBox1}) {
        const FilteredTruth t = filteredTruth(decals, filter);
        const std::vector<std::uint8_t> creases = creasePixels(t.frame);
        ASSERT_GT(std::count(creases.begin(), creases.end(), 1), 100) << filter.spelling();
        const test::RandomFrame f{t.frame, t.camera, synth::demoScene()};
        const auto [out, c] = test::compositeAndCompare(f, decals);
        EXPECT_EQ(c.mismatched, 0u) << filter.spelling() << ": max error " << c.max_error;
        EXPECT_LT(double(c.ambiguous), 0.05 * double(t.frame.pixelCount())) << filter.spelling();
        EXPECT_GT(double(c.changed), 0.1 * double(t.frame.pixelCount())) << filter.spelling();
    }
}

// The window scans of silhouette and crease pixels learn which neighbours are clean from a plane
// filled first (GPUs) or by testing each neighbour (CPUs, the default on PoCL): both give the same
// planes bit for bit, by taps and in closed form, where the decals reach pixels the scans run for.
TEST(PixelFilterTruth, CleanDepthPlaneAndScansGiveTheSamePixels) {
    const DecalScene decals = scatteredDecals(7, 24);
    const FilteredTruth t = filteredTruth(decals, kBlackmanHarris3);
    const std::vector<std::uint8_t> silhouette = silhouettePixels(t.frame), creases = creasePixels(t.frame);
    for (const bool fast : {false, true}) {
        GBuffer frame = t.frame;
        frame.pixel_filter.fast = fast;
        const auto run = [&](CleanDepths clean) {
            Compositor compositor(test::cpuDevice());
            compositor.setScene(decals);
            GBuffer out = frame;
            CompositeOptions options;
            options.clean_depths = clean;
            compositor.composite(out, t.camera, options);
            return out;
        };
        const GBuffer plane = run(CleanDepths::Plane), scans = run(CleanDepths::Scan);
        for (const auto& [attribute, samples] : scans.planes) {
            const auto& other = plane.planes.at(attribute).samples;
            ASSERT_EQ(other.size(), samples.samples.size());
            EXPECT_EQ(0, std::memcmp(other.data(), samples.samples.data(), other.size() * sizeof(float)))
                << "fast " << fast << ", attribute " << int(attribute);
        }
        std::size_t changed_silhouette = 0, changed_crease = 0;
        const Plane& before = frame.planes.at(Attribute::Albedo);
        for (std::size_t i = 0; i < frame.pixelCount(); ++i) {
            bool changed = false;
            for (int c = 0; c < 3; ++c)
                changed = changed || scans.planes.at(Attribute::Albedo).at(i, c) != before.at(i, c);
            changed_silhouette += changed && silhouette[i];
            changed_crease += changed && creases[i];
        }
        EXPECT_GT(changed_silhouette, 50u) << "fast " << fast;
        EXPECT_GT(changed_crease, 50u) << "fast " << fast;
    }
}

// Decals piled on each other (48 of them, each over several others): where their edges cross
// inside one footprint, each tap blends them in order (docs/pixel-filter.md step 3) as the
// renderer's samples do. Measured away from silhouettes, blackman-harris:3: 49.28 dB stacked per
// tap, 45.85 with one filtered decal blended at a time (the kernels of 2211c2f, DECALCOMP_KERNEL_DIR).
TEST(PixelFilterTruth, OverlappingDecalsStackPerTap) {
    DecalScene decals = scatteredDecals(5, 48);
    for (Decal& d : decals.decals) d.world_matrix = glm::scale(d.world_matrix, glm::dvec3(1.5, 1.5, 1.0));
    const FilteredTruth t = filteredTruth(decals, kBlackmanHarris3);
    const GBuffer out = compositeOnCpu(t.frame, t.camera, decals);
    const std::vector<std::uint8_t> silhouette = silhouettePixels(t.frame);
    const double smooth = decalPsnr(out, t, &silhouette, 0);
    std::printf("overlapping decals, blackman-harris:3: %.2f dB away from silhouettes\n", smooth);
    EXPECT_GE(smooth, 48.5);
}

// Temporal stability: a decal panned a quarter pixel per frame. Against each frame's filtered
// truth, the frame-to-frame change of the result follows the truth's: the filtered error of that
// change stays far below the point-sampled one (which jumps a whole texel or edge pixel at once).
TEST(PixelFilterTruth, PannedDecalChangesSmoothly) {
    const DecalScene base = scatteredDecals(11, 1);
    ASSERT_EQ(base.decals.size(), 1u);
    const Camera camera = synth::demoCamera(kWidth, kHeight);
    const glm::dvec3 centre(base.decals[0].world_matrix[3]);
    const double depth = -(camera.world_to_camera * glm::dvec4(centre, 1.0)).z;
    // a quarter of a pixel at the decal's depth, along the camera's right axis
    const double quarter = 0.25 * (2.0 / kWidth) * depth / camera.projection[0][0];
    const glm::dvec3 right = glm::normalize(glm::dvec3(glm::inverse(camera.world_to_camera)[0]));
    const int frames = 5;
    std::vector<FilteredTruth> truths;
    std::vector<GBuffer> filtered, point;
    for (int k = 0; k < frames; ++k) {
        DecalScene scene = base;
        scene.decals[0].world_matrix[3] += glm::dvec4(right * (quarter * k), 0.0);
        truths.push_back(filteredTruth(scene, kBlackmanHarris3));
        filtered.push_back(compositeOnCpu(truths.back().frame, camera, scene));
        GBuffer point_frame = truths.back().frame;
        point_frame.pixel_filter = {};
        point.push_back(compositeOnCpu(point_frame, camera, scene));
    }
    // RMS over the pixels either frame's decal covers of (change of result - change of truth)
    auto temporalError = [&](const std::vector<GBuffer>& out) {
        double squared = 0;
        std::size_t samples = 0;
        for (int k = 0; k + 1 < frames; ++k)
            for (std::size_t i = 0; i < out[0].pixelCount(); ++i) {
                if (!truths[std::size_t(k)].decal[i] && !truths[std::size_t(k) + 1].decal[i]) continue;
                for (int c = 0; c < 3; ++c) {
                    const double change = out[std::size_t(k) + 1].planes.at(Attribute::Albedo).at(i, c) -
                                          out[std::size_t(k)].planes.at(Attribute::Albedo).at(i, c);
                    const double truth_change = truths[std::size_t(k) + 1].truth.at(i, c) - truths[std::size_t(k)].truth.at(i, c);
                    squared += (change - truth_change) * (change - truth_change);
                    ++samples;
                }
            }
        return std::sqrt(squared / double(std::max<std::size_t>(samples, 1)));
    };
    const double filtered_error = temporalError(filtered), point_error = temporalError(point);
    std::printf("frame-to-frame error: filtered %.5f, point-sampled %.5f (RMS)\n", filtered_error, point_error);
    RecordProperty("temporal_rms_filtered", std::to_string(filtered_error));
    EXPECT_LT(filtered_error, 0.2 * point_error);  // measured 0.0033 against 0.068 RMS
    for (int k = 0; k < frames; ++k) EXPECT_GE(decalPsnr(filtered[std::size_t(k)], truths[std::size_t(k)]), 36.0) << k;
}

}  // namespace
}  // namespace decalcomp
