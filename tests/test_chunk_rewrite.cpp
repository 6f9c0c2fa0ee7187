// Issue 13: the output's chunks that no decal changed are the input's compressed chunks byte for
// byte, for every compression, scanline, tiled and multi-part; changed chunks decode to what the
// whole-file encoder writes (and are its bytes, but for libdeflate's ZIP chunks); a frame whose
// decals change nothing is the input file itself.
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/openexr.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "decalcomp/frame.hpp"
#include "decalcomp/scene.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_zip_encode.hpp"
#include "support/batch_fixture.hpp"
#include "support/exr_test_io.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 96, kHeight = 288;  // tall enough for several DWAB (256-line) chunks

enum class Layout { Scanline, Tiled, MultiPart };

const char* layoutName(Layout layout) {
    return layout == Layout::Scanline ? "scanline" : layout == Layout::Tiled ? "tiled" : "multipart";
}

// The generic frame's channels split into parts named after their layer ("albedo.R" -> part
// albedo, channel R; "Z" -> part depth; "R" -> part beauty), so names map the same way.
ExrImage splitIntoParts(const ExrImage& single) {
    ExrImage multi;
    multi.path = single.path;
    const ExrPart& source = single.parts.at(0);
    for (const ExrChannel& channel : source.channels) {
        const auto dot = channel.name.find('.');
        const std::string part_name = dot != std::string::npos ? channel.name.substr(0, dot)
                                      : channel.name == "Z"     ? "depth"
                                      : channel.name.size() == 1 ? "beauty"
                                                                 : channel.name;
        ExrPart* part = nullptr;
        for (ExrPart& p : multi.parts)
            if (p.header.name() == part_name) part = &p;
        if (!part) {
            part = &multi.parts.emplace_back();
            part->header = source.header;
            part->header.channels() = Imf::ChannelList();
            part->header.setName(part_name);
            part->width = source.width, part->height = source.height;
        }
        ExrChannel moved = channel;
        moved.name = dot != std::string::npos ? channel.name.substr(dot + 1) : channel.name;
        part->header.channels().insert(moved.name, Imf::Channel(io::pixelType(moved.type)));
        part->channels.push_back(std::move(moved));
    }
    return multi;
}

// Rewrites `image` (read whole) with `compression` in `layout` through the whole-file writer.
void convert(ExrImage image, Imf::Compression compression, Layout layout, const std::string& out) {
    if (layout == Layout::MultiPart) image = splitIntoParts(image);
    test::writeWithCompression(std::move(image), compression, layout == Layout::Tiled, out);
}

// Bit-exact comparison of every channel's samples inside `box` (absolute pixels); the first
// difference, else "".
std::string differenceIn(const ExrPart& a, const ExrPart& b, const Imath::Box2i& box) {
    const Imath::Box2i dw = a.header.dataWindow();
    const std::size_t width = std::size_t(dw.max.x - dw.min.x + 1);
    for (std::size_t c = 0; c < a.channels.size(); ++c) {
        const std::size_t size = io::sampleSize(a.channels[c].type);
        for (int y = box.min.y; y <= box.max.y; ++y) {
            const std::size_t at = (std::size_t(y - dw.min.y) * width + std::size_t(box.min.x - dw.min.x)) * size;
            const std::size_t n = std::size_t(box.max.x - box.min.x + 1) * size;
            if (std::memcmp(a.channels[c].bytes.data() + at, b.channels[c].bytes.data() + at, n) != 0)
                return a.channels[c].name + " row " + std::to_string(y);
        }
    }
    return "";
}

// exrcheck, where the system has it (Debian 12's openexr 3.1 package does not ship it).
void expectExrcheckAccepts(const std::string& path) {
    if (test::runCommand("command -v exrcheck").exit_code != 0) return;
    const auto check = test::runCommand("exrcheck " + test::shellQuote(path));
    EXPECT_EQ(check.exit_code, 0) << path << ": " << check.output;
}

struct Variant {
    Imf::Compression compression;
    Layout layout;
};

std::string variantName(const testing::TestParamInfo<Variant>& info) {
    static const char* const names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    return std::string(names[int(info.param.compression)]) + "_" + layoutName(info.param.layout);
}

bool lossless(Imf::Compression c) {
    return c == Imf::NO_COMPRESSION || c == Imf::RLE_COMPRESSION || c == Imf::ZIPS_COMPRESSION ||
           c == Imf::ZIP_COMPRESSION || c == Imf::PIZ_COMPRESSION;
}

class ChunkRewrite : public testing::TestWithParam<Variant> {
protected:
    test::ScratchDir dir;
    std::string base = FramePattern(test::writeSequence(dir.path() / "base", {1}, kWidth, kHeight)).path(1);
    std::string input = dir.file("in.exr");
    DecalScene scene = loadScene(test::writeStaticScene(dir.path()));

    void SetUp() override { convert(readExr(base), GetParam().compression, GetParam().layout, input); }
};

// Composites `input` into `output`; `decode_all` reads every chunk first (the full-decode path).
std::unique_ptr<Frame> composite(const std::string& input, const std::string& output, const DecalScene& scene,
                                 ComputeDevice& device, bool decode_all) {
    FrameSources sources;
    sources.inputs = {input};
    auto frame = std::make_unique<Frame>(sources, FrameTargets{output, "", false}, FrameOptions{});
    if (decode_all) frame->read();
    frame->prepare(scene);
    Compositor compositor(device);
    compositor.setScene(scene);
    frame->composite(compositor);
    frame->writeBack();
    return frame;
}

TEST_P(ChunkRewrite, UntouchedChunksAreTheInputsBytesAndChangedOnesDecodeAsTheWholeFileWriter) {
    ComputeDevice device("cpu");
    const std::string out = dir.file("out.exr"), out_full = dir.file("full.exr");
    const auto frame = composite(input, out, scene, device, false);
    const auto full = composite(input, out_full, scene, device, true);
    const FrameReport& report = frame->report();
    ASSERT_GT(report.changed_samples, 0u);
    EXPECT_EQ(report.changed_samples, full->report().changed_samples);
    // Decoding only the reachable chunks changes nothing: same samples there, same changed chunks,
    // the same output file.
    const ExrImage& partial = frame->files().at(0);
    const ExrImage& decoded = full->files().at(0);
    for (std::size_t p = 0; p < partial.parts.size(); ++p) {
        EXPECT_EQ(partial.parts[p].changed, decoded.parts[p].changed) << "part " << p;
        for (int c = 0; c < partial.parts[p].chunks.count(); ++c)
            if (partial.parts[p].isDecoded(c)) {
                EXPECT_EQ(differenceIn(partial.parts[p], decoded.parts[p], partial.parts[p].chunks.box(c)), "") << c;
            }
    }
    EXPECT_EQ(test::readFileBytes(out), test::readFileBytes(out_full));

    // The whole-file writer's output of the same composited samples: the path before issue 13.
    ExrImage whole = decoded;
    whole.copy_unchanged_chunks = false;
    const std::string reference = dir.file("whole.exr");
    writeExrAtomic(whole, reference);

    const auto in_chunks = test::rawChunks(input), out_chunks = test::rawChunks(out),
               ref_chunks = test::rawChunks(reference);
    const ExrImage in_image = readExr(input), out_image = readExr(out);
    ASSERT_EQ(out_chunks.size(), in_chunks.size());
    std::size_t copied = 0, reencoded = 0, pixels = 0;
    for (std::size_t p = 0; p < in_chunks.size(); ++p) {
        const ExrPart& composited = decoded.parts.at(p);
        ASSERT_EQ(out_chunks[p].size(), in_chunks[p].size());
        for (std::size_t c = 0; c < in_chunks[p].size(); ++c) {
            const bool changed = c < composited.changed.size() && composited.changed[c];
            const Imath::Box2i box = composited.chunks.box(int(c));
            if (!changed) {
                ++copied;
                EXPECT_EQ(out_chunks[p][c], in_chunks[p][c]) << "part " << p << " chunk " << c;
                EXPECT_EQ(differenceIn(out_image.parts[p], in_image.parts[p], box), "") << "part " << p << " chunk " << c;
                continue;
            }
            ++reencoded;
            pixels += std::size_t(box.max.x - box.min.x + 1) * std::size_t(box.max.y - box.min.y + 1);
            // A changed chunk is what the whole-file writer stores for it (ZIP through libdeflate:
            // other deflate bytes, no bigger), and lossless codecs give the composited samples back.
            if (io::canEncodeZip(composited)) {
                EXPECT_LE(out_chunks[p][c].size(), ref_chunks[p][c].size() + ref_chunks[p][c].size() / 20 + 16)
                    << "part " << p << " chunk " << c;
            } else {
                EXPECT_EQ(out_chunks[p][c], ref_chunks[p][c]) << "part " << p << " chunk " << c;
            }
            if (lossless(GetParam().compression)) {
                EXPECT_EQ(differenceIn(out_image.parts[p], composited, box), "") << "part " << p << " chunk " << c;
            }
        }
    }
    EXPECT_EQ(report.chunks_copied, copied);
    EXPECT_EQ(report.chunks_reencoded, reencoded);
    EXPECT_EQ(report.pixels_reencoded, pixels);
    EXPECT_GT(reencoded, 0u);
    const bool big_blocks = GetParam().compression == Imf::DWAB_COMPRESSION && GetParam().layout != Layout::Tiled;
    if (!big_blocks) {
        EXPECT_GT(copied, reencoded) << "the decal covers a small part of the frame";
    }
    if (GetParam().layout == Layout::MultiPart)  // only the albedo part has changed channels
        for (std::size_t p = 0; p < in_chunks.size(); ++p)
            if (decoded.parts[p].header.name() != "albedo") {
                EXPECT_EQ(out_chunks[p], in_chunks[p]) << p;
            }
    expectExrcheckAccepts(out);
}

TEST_P(ChunkRewrite, AFrameWhoseDecalsChangeNothingIsTheInputFile) {
    ComputeDevice device("cpu");
    // Far off screen: nothing lands.
    std::ofstream(dir.file("away.json")) << R"({"textures": {"red": "red.png"}, "decals": [{"name": "away", )"
                                         << R"("texture": "red", "translate": [500, 500, 500]}]})";
    const DecalScene away = loadScene(dir.file("away.json"));
    const std::string out = dir.file("out.exr");
    FrameSources sources;
    sources.inputs = {input};
    Frame frame(sources, FrameTargets{out, "", false}, FrameOptions{});
    frame.prepare(away);
    Compositor compositor(device);
    compositor.setScene(away);
    frame.composite(compositor);
    frame.writeBack();
    EXPECT_EQ(frame.report().chunks_reencoded, 0u);
    EXPECT_GT(frame.report().chunks_copied, 0u);
    EXPECT_EQ(test::readFileBytes(out), test::readFileBytes(input));
}

std::vector<Variant> variants() {
    std::vector<Variant> all;
    for (Imf::Compression c : {Imf::NO_COMPRESSION, Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION,
                               Imf::PIZ_COMPRESSION, Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION,
                               Imf::B44A_COMPRESSION, Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION})
        for (Layout layout : {Layout::Scanline, Layout::Tiled, Layout::MultiPart}) all.push_back({c, layout});
    return all;
}

INSTANTIATE_TEST_SUITE_P(EveryCompression, ChunkRewrite, testing::ValuesIn(variants()), variantName);

// The issue's case: the Blender sample stored DWAA (level 45) keeps its beauty outside the
// re-encoded chunks bit for bit (the whole-file path changed 76% of it).
TEST(ChunkRewriteDwaa, BeautyOutsideReencodedChunksIsUnchanged) {
    test::ScratchDir dir;
    const std::string input = dir.file("dwaa.exr"), out = dir.file("out.exr");
    convert(readExr(test::dataPath("blender-kinds/gbuffer.exr")), Imf::DWAA_COMPRESSION, Layout::Scanline, input);
    const auto run = test::runCli("composite " + test::shellQuote(input) + " --decals " +
                                  test::shellQuote(test::dataPath("blender-kinds/scene.json")) + " --camera " +
                                  test::shellQuote(test::dataPath("blender-kinds/camera.json")) +
                                  " --device cpu --stats -o " + test::shellQuote(out));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("stats: chunks copied "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("chunks: "), std::string::npos) << run.output;

    const ExrImage before = readExr(input), after = readExr(out);
    const auto in_chunks = test::rawChunks(input), out_chunks = test::rawChunks(out);
    const ExrPart& a = before.parts.at(0);
    const ExrPart& b = after.parts.at(0);
    const ExrChannel* beauty_in = nullptr;
    const ExrChannel* beauty_out = nullptr;
    for (std::size_t c = 0; c < a.channels.size(); ++c)
        if (a.channels[c].name == "ViewLayer.Combined.R") beauty_in = &a.channels[c], beauty_out = &b.channels[c];
    ASSERT_TRUE(beauty_in && beauty_out);
    const Imath::Box2i dw = a.header.dataWindow();
    std::size_t outside = 0, changed = 0, copied = 0;
    for (int chunk = 0; chunk < a.chunks.count(); ++chunk) {
        const bool reencoded = out_chunks[0][std::size_t(chunk)] != in_chunks[0][std::size_t(chunk)];
        copied += !reencoded;
        const Imath::Box2i box = a.chunks.box(chunk);
        for (int y = box.min.y; y <= box.max.y; ++y)
            for (int x = box.min.x; x <= box.max.x; ++x) {
                const std::size_t i = std::size_t(y - dw.min.y) * std::size_t(a.width) + std::size_t(x - dw.min.x);
                const bool differs = io::sampleAsFloat(*beauty_in, i) != io::sampleAsFloat(*beauty_out, i);
                changed += differs;
                outside += differs && !reencoded;
            }
    }
    std::printf("DWAA beauty: %zu of %d pixels changed, all in re-encoded chunks (%zu of %d chunks copied)\n", changed,
                a.width * a.height, copied, a.chunks.count());
    EXPECT_GT(copied, 0u);
    EXPECT_EQ(outside, 0u) << "beauty pixels changed outside re-encoded chunks";
}

}  // namespace
}  // namespace decalcomp
