// Issue 13, "decode only what can change": compositing after decoding only the chunks that the
// decals' projected volumes can touch gives the same result as decoding the whole file. Every
// frame in data/ (with the scene and camera the CLI and the other tests use) and random generated
// scenes with scattered decals, each converted to several compressions (every one of OpenEXR's ten
// at least once over the cases, scanline and tiled, single- and multi-part), are composited both
// ways; the two outputs must decode to the same bits on every sample of every channel, and be the
// same file. The data/ frames are small (at most 320x240) and kept whole; the random frames, where
// the decals leave rows and tiles undecoded, take every compression. About 20 s on 2 cores.
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "decalcomp/frame.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/synth.hpp"
#include "io/exr_layout.hpp"
#include "support/batch_fixture.hpp"
#include "support/exr_test_io.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

enum class Layout { Scanline, Tiled };

const char* compressionName(Imf::Compression c) {
    static const char* const names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    return names[int(c)];
}

// Rewrites `image` (read whole) with `compression` in `layout`, every part, through the
// whole-file writer, as test_chunk_rewrite converts its frames.
void convert(ExrImage image, Imf::Compression compression, Layout layout, const std::string& out) {
    test::writeWithCompression(std::move(image), compression, layout == Layout::Tiled, out);
}

// One frame to composite: a data/ sample, or a generated random scene (seed > 0).
struct Case {
    std::string name;
    std::string folder, scene, camera;  // data/ sample: gbuffer.exr in `folder`, scene and camera files
    std::uint32_t seed = 0;             // random: decalcomp-gbuffer-gen --scene random --seed
    std::string generator_arguments;    // random: naming, depth convention, size, parts
    bool leaves_chunks = false;         // the decals cannot reach some chunks in any compression
};

struct Variant {
    Case frame;
    Imf::Compression compression;
    Layout layout;
};

// The data/ frames as tools/demo.sh, test_blender_truth and test_beauty composite them (the beauty
// datasets take blender-kinds' scene with their own camera), and random scenes in several namings,
// depth conventions, sample types and part layouts. Each gets a few compressions; over all cases
// every compression appears in scanline and in tiled files.
std::vector<Variant> variants() {
    const auto data = [](const std::string& folder, const std::string& scene_folder) {
        return Case{folder, folder, scene_folder + "/scene.json", folder + "/camera.json", 0, "", false};
    };
    const auto random = [](const std::string& name, std::uint32_t seed, const std::string& arguments) {
        return Case{name, "", "", "", seed, arguments, false};
    };
    const Case sample = data("sample", "sample"), blender = data("blender", "blender"),
               kinds = data("blender-kinds", "blender-kinds"), beauty = data("blender-beauty", "blender-kinds"),
               direct = data("blender-beauty-direct", "blender-kinds");
    Case generic = random("random_generic", 11, "--naming generic --depth radial --width 200 --height 150");
    Case half = random("random_half", 14, "--naming blender --half --depth ndc --width 176 --height 132");
    Case ndc = random("random_ndc", 15, "--naming arnold --depth ndc --reversed-z --width 160 --height 120");
    Case multipart = random("random_multipart", 13, "--naming generic --multipart --depth planar --width 192 --height 144");
    generic.leaves_chunks = half.leaves_chunks = ndc.leaves_chunks = multipart.leaves_chunks = true;
    using C = Imf::Compression;
    const auto S = Layout::Scanline, T = Layout::Tiled;
    std::vector<Variant> all;
    const auto add = [&](const Case& c, std::vector<std::pair<C, Layout>> list) {
        for (const auto& [compression, layout] : list) all.push_back({c, compression, layout});
    };
    add(sample, {{Imf::NO_COMPRESSION, S}, {Imf::PIZ_COMPRESSION, S}, {Imf::DWAB_COMPRESSION, T}});
    add(blender, {{Imf::RLE_COMPRESSION, S}, {Imf::ZIP_COMPRESSION, T}, {Imf::PXR24_COMPRESSION, S}});
    add(kinds, {{Imf::ZIPS_COMPRESSION, S}, {Imf::DWAA_COMPRESSION, S}, {Imf::B44A_COMPRESSION, T}});
    add(beauty, {{Imf::ZIP_COMPRESSION, S}, {Imf::DWAA_COMPRESSION, T}, {Imf::B44_COMPRESSION, S}});
    add(direct, {{Imf::PIZ_COMPRESSION, T}, {Imf::DWAB_COMPRESSION, S}, {Imf::PXR24_COMPRESSION, T}});
    add(generic, {{Imf::DWAA_COMPRESSION, S}});
    add(half, {{Imf::B44_COMPRESSION, T}, {Imf::B44A_COMPRESSION, S}, {Imf::PXR24_COMPRESSION, S},
               {Imf::DWAB_COMPRESSION, T}});
    add(ndc, {{Imf::PIZ_COMPRESSION, S}, {Imf::DWAA_COMPRESSION, T}});
    add(multipart, {{Imf::ZIPS_COMPRESSION, T}});
    // Two frames where the decals leave chunks undecoded in every compression (checked below):
    // tiled single-part, scanline multi-part.
    for (int c = 0; c <= int(Imf::DWAB_COMPRESSION); ++c) {
        all.push_back({generic, C(c), T});
        if (C(c) != Imf::DWAB_COMPRESSION) all.push_back({multipart, C(c), S});  // 256 lines: one chunk
    }
    return all;
}

std::string variantName(const testing::TestParamInfo<Variant>& info) {
    std::string name = info.param.frame.name + "_" + compressionName(info.param.compression) +
                       (info.param.layout == Layout::Tiled ? "_tiled" : "_scanline");
    for (char& c : name)
        if (c == '-') c = '_';
    return name;
}

// Composites `input` into `output`; `decode_all` reads every chunk before prepare() (the
// full-decode path), else prepare() decodes only the chunks the decals can reach.
std::unique_ptr<Frame> composite(const std::string& input, const std::string& camera_json, const std::string& output,
                                 const DecalScene& scene, const FrameOptions& options, bool decode_all) {
    FrameSources sources;
    sources.inputs = {input};
    sources.camera_json = camera_json;
    auto frame = std::make_unique<Frame>(sources, FrameTargets{output, "", false}, options);
    if (decode_all) frame->read();
    frame->prepare(scene);
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    frame->composite(compositor);
    frame->writeBack();
    return frame;
}

// The first sample whose bits differ between two decoded files: "part P channel C pixel (x, y)",
// else "".
std::string firstDifference(const ExrImage& a, const ExrImage& b) {
    if (a.parts.size() != b.parts.size()) return "part counts differ";
    for (std::size_t p = 0; p < a.parts.size(); ++p) {
        const ExrPart& pa = a.parts[p];
        const ExrPart& pb = b.parts[p];
        if (pa.channels.size() != pb.channels.size()) return "part " + std::to_string(p) + ": channel counts differ";
        const Imath::Box2i dw = pa.header.dataWindow();
        for (std::size_t c = 0; c < pa.channels.size(); ++c) {
            const ExrChannel& ca = pa.channels[c];
            const ExrChannel& cb = pb.channels[c];
            if (ca.name != cb.name || ca.type != cb.type || ca.bytes.size() != cb.bytes.size())
                return "part " + std::to_string(p) + " channel " + ca.name + ": differs in name, type or size";
            const std::size_t size = io::sampleSize(ca.type);
            for (std::size_t i = 0; i * size < ca.bytes.size(); ++i)
                if (std::memcmp(ca.bytes.data() + i * size, cb.bytes.data() + i * size, size) != 0) {
                    const int x = dw.min.x + int(i % std::size_t(pa.width)), y = dw.min.y + int(i / std::size_t(pa.width));
                    return "part " + std::to_string(p) + " (" + pa.header.name() + ") channel " + ca.qualified +
                           " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " +
                           std::to_string(io::sampleAsFloat(ca, i)) + " vs " + std::to_string(io::sampleAsFloat(cb, i));
                }
        }
    }
    return "";
}

// NDC depth is not recognised from the pixels: it is stated, as with --depth ndc [--reversed-z].
FrameOptions frameOptions(const Case& c) {
    FrameOptions options;
    if (c.generator_arguments.find("--depth ndc") != std::string::npos) {
        options.mapping.depth_convention = DepthConvention::Ndc;
        options.mapping.reversed_z = c.generator_arguments.find("--reversed-z") != std::string::npos;
    }
    return options;
}

class ChunkEquivalence : public testing::TestWithParam<Variant> {
protected:
    FrameOptions options() const { return frameOptions(GetParam().frame); }
    test::ScratchDir dir;
    std::string source, camera_json;  // the frame as stored (data/, or generated)
    DecalScene scene;

    void SetUp() override {
        const Case& c = GetParam().frame;
        if (c.seed == 0) {
            source = test::dataPath(c.folder + "/gbuffer.exr");
            camera_json = test::dataPath(c.camera);
            scene = loadScene(test::dataPath(c.scene));
            return;
        }
        source = dir.file("generated.exr"), camera_json = dir.file("generated.json");
        const auto gen = test::runGenerator("--scene random --seed " + std::to_string(c.seed) + " " +
                                                c.generator_arguments,
                                            source, camera_json);
        ASSERT_EQ(gen.exit_code, 0) << gen.output;
        // The generated frame's planes and camera (a full read: a decal at the origin needs them),
        // then decals scattered on its visible surfaces, small enough to leave chunks untouched,
        // in every kind.
        DecalScene probe;
        probe.decals.emplace_back().name = "probe";
        probe.textures.push_back(synth::proceduralTexture(0, 8, 1));
        probe.decals.back().albedo_texture = 0;
        FrameSources sources;
        sources.inputs = {source};
        sources.camera_json = camera_json;
        Frame frame(sources, FrameTargets{dir.file("probe.exr"), "", false}, options());
        frame.read();
        frame.prepare(probe);
        synth::ScatterOptions scatter;
        scatter.count = 10;
        scatter.min_size = 0.2;
        scatter.max_size = 1.2;
        scatter.texture_size = 16;
        scatter.seed = c.seed;
        const int rows = frame.gbuffer().height;
        scatter.first_row = rows / 4, scatter.last_row = rows / 2;  // leave rows (and tiles) no decal reaches
        scene = synth::scatterDecals(frame.gbuffer(), frame.camera(), scatter);
        ASSERT_FALSE(scene.decals.empty());
        const DecalKind kinds[] = {DecalKind::Box, DecalKind::Volume, DecalKind::Frustum, DecalKind::Cube};
        if (c.seed % 4 != 0) synth::convertDecals(scene, kinds[c.seed % 4], c.seed);
    }
};

TEST_P(ChunkEquivalence, PartialDecodeGivesTheFullDecodeOutputOnEverySample) {
    const Variant& v = GetParam();
    const std::string input = dir.file("in.exr");
    convert(readExr(source), v.compression, v.layout, input);
    const std::string out = dir.file("partial.exr"), out_full = dir.file("full.exr");
    const auto partial = composite(input, camera_json, out, scene, options(), false);
    const auto full = composite(input, camera_json, out_full, scene, options(), true);

    // The partial path did skip chunks somewhere (else this compares the full path with itself),
    // and decoded every chunk it changed.
    std::size_t chunks = 0, decoded = 0;
    for (const ExrImage& image : partial->files())
        for (const ExrPart& part : image.parts)
            for (int c = 0; c < part.chunks.count(); ++c) {
                ++chunks;
                decoded += part.isDecoded(c);
                if (c < int(part.changed.size()) && part.changed[std::size_t(c)]) {
                    EXPECT_TRUE(part.isDecoded(c)) << part.header.name() << " chunk " << c;
                }
            }
    std::printf("%s %s: decoded %zu of %zu chunks; %zu copied, %zu re-encoded; %zu samples changed\n", v.frame.name.c_str(),
                compressionName(v.compression), decoded, chunks, partial->report().chunks_copied,
                partial->report().chunks_reencoded, partial->report().changed_samples);
    if (v.frame.leaves_chunks) {
        EXPECT_LT(decoded, chunks) << "the decals reach every chunk: the partial path is not exercised";
    }
    RecordProperty("chunks", int(chunks));
    RecordProperty("decoded_chunks", int(decoded));

    const FrameReport& a = partial->report();
    const FrameReport& b = full->report();
    EXPECT_GT(a.changed_samples, 0u);
    EXPECT_EQ(a.changed_samples, b.changed_samples);
    EXPECT_EQ(a.chunks_copied, b.chunks_copied);
    EXPECT_EQ(a.chunks_reencoded, b.chunks_reencoded);
    EXPECT_EQ(a.pixels_reencoded, b.pixels_reencoded);
    EXPECT_EQ(a.beauty.rebuilt, b.beauty.rebuilt);

    // Every sample of every channel of the written files, decoded, bit for bit; then the files.
    const ExrImage result = readExr(out), reference = readExr(out_full);
    EXPECT_EQ(firstDifference(result, reference), "")
        << v.frame.name << " " << compressionName(v.compression) << ": partial vs full decode";
    EXPECT_TRUE(test::readFileBytes(out) == test::readFileBytes(out_full)) << "the output files differ";
}

INSTANTIATE_TEST_SUITE_P(DataAndRandomScenes, ChunkEquivalence, testing::ValuesIn(variants()), variantName);

// Over the variants, every compression in scanline and in tiled files.
TEST(ChunkEquivalenceCases, CoverEveryCompressionInBothLayouts) {
    bool seen[2][Imf::NUM_COMPRESSION_METHODS] = {};
    for (const Variant& v : variants()) seen[int(v.layout)][int(v.compression)] = true;
    for (int c = 0; c <= int(Imf::DWAB_COMPRESSION); ++c) {
        EXPECT_TRUE(seen[0][c]) << compressionName(Imf::Compression(c)) << " scanline";
        EXPECT_TRUE(seen[1][c]) << compressionName(Imf::Compression(c)) << " tiled";
    }
}

}  // namespace
}  // namespace decalcomp
