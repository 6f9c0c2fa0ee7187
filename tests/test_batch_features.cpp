// `decalcomp batch` features end to end through the CLI, each checked against single-frame
// `decalcomp composite` where one exists: per-pass files per frame (--pass ATTR=PATTERN), folder
// outputs and --resume with them, -o without a frame token, --add-channels, --preview patterns,
// the contact sheet of the sequence and frames spread over several devices (--device cpu,cpu).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <thread>

#include "io/exr_layout.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::channel;
using test::Png;
using test::readPng;
using test::shellQuote;

constexpr int kWidth = 64, kHeight = 48;
const std::vector<int> kFrames = {1, 2, 3};

// Three frames as two files each: in/depth.####.exr (Z only) and in/albedo.####.exr (albedo.RGB
// and P.XYZ), both with the frame's camera in the header, and a static decal scene.
struct PassSequence {
    test::ScratchDir dir;
    std::string albedo = (dir.path() / "in" / "albedo.####.exr").string();
    std::string depth = (dir.path() / "in" / "depth.####.exr").string();
    std::string scene;

    explicit PassSequence(const std::string& affects = "") {
        fs::create_directories(dir.path() / "in");
        for (int f : kFrames) {
            test::ChannelSamples passes = test::genericPasses(test::renderSequenceFrame(f, kWidth, kHeight));
            const Camera camera = test::sequenceCamera(f, kWidth, kHeight);
            test::writeFloatExr(depthAt(f), kWidth, kHeight, {{"Z", passes.at("Z")}}, camera);
            passes.erase("Z");
            test::writeFloatExr(albedoAt(f), kWidth, kHeight, passes, camera);
        }
        scene = test::writeStaticScene(dir.path(), affects);
    }
    std::string albedoAt(int f) const { return FramePattern(albedo).path(f); }
    std::string depthAt(int f) const { return FramePattern(depth).path(f); }

    test::CommandResult batch(const std::string& output, const std::string& extra = "") const {
        return test::runCli("batch " + shellQuote(albedo) + " --pass depth=" + shellQuote(depth) + " --decals " +
                            shellQuote(scene) + " -o " + shellQuote(output) + " --progress lines " + extra);
    }
    // `decalcomp composite` on frame `f`'s two files, written to `output`.
    ExrImage composite(int f, const std::string& output, const std::string& extra = "") const {
        const auto r =
            test::runCli("composite " + shellQuote(albedoAt(f)) + " --pass depth=" + shellQuote(depthAt(f)) +
                         " --decals " + shellQuote(scene) + " --device cpu -o " + shellQuote(output) + " " + extra);
        EXPECT_EQ(r.exit_code, 0) << r.output;
        return readExr(output);
    }
};

std::set<std::string> filesIn(const fs::path& dir) {
    std::set<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (!e.is_directory()) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

// How many samples of `name` differ between the two images.
std::size_t changedSamples(const ExrImage& a, const ExrImage& b, const std::string& name) {
    const ExrChannel &x = channel(a, name), &y = channel(b, name);
    std::size_t n = 0;
    for (std::size_t i = 0; i < x.bytes.size() / io::sampleSize(x.type); ++i)
        n += io::sampleAsFloat(x, i) != io::sampleAsFloat(y, i);
    return n;
}

// The batch's output of every frame equals `composite`'s of that frame, and the decal landed.
void expectBatchMatchesComposite(const PassSequence& s, const std::function<std::string(int)>& batch_output,
                                 const std::string& extra = "") {
    for (int f : kFrames) {
        const ExrImage batched = readExr(batch_output(f));
        const ExrImage single = s.composite(f, s.dir.file("single." + std::to_string(f) + ".exr"), extra);
        EXPECT_EQ(test::pixelDifference(batched, single), "") << "frame " << f;
        EXPECT_GT(changedSamples(batched, readExr(s.albedoAt(f)), "albedo.R"), 50u) << "frame " << f;
    }
}

TEST(BatchFeatures, PerPassFilesPerFrameMatchSingleFrameComposite) {
    PassSequence s;
    const std::string out = s.dir.file("out/comp.####.exr");
    const auto r = s.batch(out, "--device cpu");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::occurrences(r.output, " written "), 3u) << r.output;
    EXPECT_EQ(filesIn(s.dir.path() / "out"),
              (std::set<std::string>{"comp.0001.exr", "comp.0002.exr", "comp.0003.exr"}));
    for (int f : kFrames)  // the layout of the file holding the albedo: no Z
        EXPECT_EQ(test::qualifiedNames(readExr(FramePattern(out).path(f))),
                  test::qualifiedNames(readExr(s.albedoAt(f))))
            << f;
    expectBatchMatchesComposite(s, [&](int f) { return FramePattern(out).path(f); });
    // Each frame took its own depth file: with frame 1's depth everywhere, frame 3 composites differently.
    const auto wrong =
        test::runCli("composite " + shellQuote(s.albedoAt(3)) + " --pass depth=" + shellQuote(s.depthAt(1)) +
                     " --decals " + shellQuote(s.scene) + " --device cpu -q -o " + shellQuote(s.dir.file("wrong.exr")));
    ASSERT_EQ(wrong.exit_code, 0) << wrong.output;
    EXPECT_NE(test::pixelDifference(readExr(FramePattern(out).path(3)), readExr(s.dir.file("wrong.exr"))), "");
}

TEST(BatchFeatures, FolderOutputKeepsTheAlbedoFilesNameAndResumeSkipsEveryFrame) {
    PassSequence s;
    const std::string folder = s.dir.file("outdir") + "/";
    const auto r = s.batch(folder, "--device cpu");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(filesIn(s.dir.path() / "outdir"),
              (std::set<std::string>{"albedo.0001.exr", "albedo.0002.exr", "albedo.0003.exr"}))
        << "only the file holding the albedo is written, under its input's name; never the depth file";
    for (int f : kFrames)
        EXPECT_NE(r.output.find("frame " + std::to_string(f) + " written " + folder + "albedo.000" + std::to_string(f) +
                                ".exr"),
                  std::string::npos)
            << r.output;
    expectBatchMatchesComposite(s, [&](int f) { return folder + fs::path(s.albedoAt(f)).filename().string(); });

    std::map<std::string, fs::file_time_type> before;
    for (const std::string& name : filesIn(s.dir.path() / "outdir")) before[name] = fs::last_write_time(folder + name);
    const auto again = s.batch(folder, "--device cpu --resume");
    ASSERT_EQ(again.exit_code, 0) << again.output;
    for (int f : kFrames)
        EXPECT_NE(again.output.find("frame " + std::to_string(f) + " skipped"), std::string::npos) << again.output;
    EXPECT_EQ(test::occurrences(again.output, " written "), 0u) << again.output;
    EXPECT_NE(again.output.find("0 written, 3 skipped, 0 failed of 3 frames"), std::string::npos) << again.output;
    for (const auto& [name, time] : before) EXPECT_EQ(fs::last_write_time(folder + name), time) << name << " rewritten";
    EXPECT_EQ(filesIn(s.dir.path() / "outdir").size(), 3u);
}

// --io-only is the batch bench's yardstick, the I/O of frames whose decals change everything: it
// reads every chunk and re-encodes every chunk (a copy of the input would measure no encoding).
TEST(BatchFeatures, IoOnlyReencodesEveryChunkAndKeepsEveryPixel) {
    PassSequence s;
    const std::string out = s.dir.file("out/io.####.exr");
    const auto r = s.batch(out, "--io-only --stats");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::size_t pixels = kFrames.size() * std::size_t(kWidth) * kHeight;  // the albedo file of each frame
    EXPECT_NE(r.output.find("chunks copied 0, chunks re-encoded"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("pixels re-encoded " + std::to_string(pixels)), std::string::npos) << r.output;
    for (int f : kFrames) EXPECT_EQ(test::pixelDifference(readExr(FramePattern(out).path(f)), readExr(s.albedoAt(f))), "") << f;
}

// --timing's second line: CPU time per frame of the workers' stages and of the chunk codecs (the
// frames are ZIP: every chunk is inflated on read and the changed ones deflated on write).
TEST(BatchFeatures, TimingGivesTheStagesAndTheCodecsCpuTime) {
    PassSequence s;
    const auto r = s.batch(s.dir.file("out/comp.####.exr"), "--device cpu -q --timing");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("timing, ms per frame (thread time): read "), std::string::npos) << r.output;
    const std::string cpu_line = "timing, ms per frame (CPU time): prepare ";
    const std::size_t at = r.output.find(cpu_line);
    ASSERT_NE(at, std::string::npos) << r.output;
    double prepare = -1, composite = -1, decode = -1, encode = -1;
    ASSERT_EQ(std::sscanf(r.output.c_str() + at + cpu_line.size(),
                          "%lf, composite %lf (the workers' threads); decode %lf, encode %lf (every thread)", &prepare,
                          &composite, &decode, &encode),
              4)
        << r.output;
    EXPECT_GT(prepare, 0.0) << r.output;
    EXPECT_GT(composite, 0.0) << r.output;
    EXPECT_GT(decode, 0.0) << r.output;
    EXPECT_GT(encode, 0.0) << r.output;
    EXPECT_LT(prepare + composite + decode + encode, 60'000.0) << r.output;  // ms per frame of 64 x 48 pixels
}

TEST(BatchFeatures, OutputWithoutFrameTokenThatIsNoFolderIsAUsageError) {
    PassSequence s;
    const std::string out = s.dir.file("out.exr");
    const auto r = s.batch(out, "--device cpu");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("-o " + out + ": give a frame pattern"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // An existing folder without a trailing '/' is a folder output.
    fs::create_directories(s.dir.file("existing"));
    const auto folder = s.batch(s.dir.file("existing"), "--device cpu -q");
    ASSERT_EQ(folder.exit_code, 0) << folder.output;
    EXPECT_EQ(filesIn(s.dir.path() / "existing").size(), 3u);
    EXPECT_TRUE(fs::exists(s.dir.file("existing/albedo.0002.exr")));
}

TEST(BatchFeatures, AddChannelsGivesEveryFrameARoughnessChannelLikeComposite) {
    PassSequence s(R"({"albedo": 1, "roughness": {"value": 0.2}})");
    ASSERT_FALSE(test::qualifiedNames(readExr(s.albedoAt(1))).count("roughness"));
    const std::string out = s.dir.file("out/comp.####.exr");
    const auto r = s.batch(out, "--device cpu --add-channels roughness");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("no roughness channels"), std::string::npos) << r.output;
    for (int f : kFrames) {
        const ExrImage result = readExr(FramePattern(out).path(f));
        std::set<std::string> expected = test::qualifiedNames(readExr(s.albedoAt(f)));
        expected.insert("roughness");  // the generic profile's spelling
        ASSERT_EQ(test::qualifiedNames(result), expected) << "frame " << f;
        const ExrChannel& roughness = channel(result, "roughness");
        EXPECT_EQ(roughness.type, channel(result, "albedo.R").type);
        const float fill = addedChannelDefault(Attribute::Roughness);
        ASSERT_EQ(fill, 0.5f);
        std::size_t outside = 0, inside = 0, wrong = 0;
        const std::size_t samples = roughness.bytes.size() / io::sampleSize(roughness.type);
        for (std::size_t i = 0; i < samples; ++i) {
            const float v = io::sampleAsFloat(roughness, i);
            if (v == fill)
                ++outside;
            else if (std::abs(v - 0.2f) < 1e-4f)
                ++inside;
            else if (!(v > 0.2f && v < 0.5f))  // values between are the decal's filtered edge
                ++wrong;
        }
        EXPECT_GT(outside, samples / 2) << "frame " << f;
        EXPECT_GT(inside, 50u) << "frame " << f;
        EXPECT_EQ(wrong, 0u) << "frame " << f;
        // Roughness changed exactly where the albedo did.
        const ExrImage input = readExr(s.albedoAt(f));  // kept: the channel refers into it
        const ExrChannel& albedo_in = channel(input, "albedo.R");
        for (std::size_t i = 0; i < samples; ++i)
            if (io::sampleAsFloat(roughness, i) != fill) {
                ASSERT_NE(io::sampleAsFloat(channel(result, "albedo.R"), i), io::sampleAsFloat(albedo_in, i)) << i;
            }
    }
    expectBatchMatchesComposite(
        s, [&](int f) { return FramePattern(out).path(f); }, "--add-channels roughness");
}

TEST(BatchFeatures, PreviewPatternWritesOnePngPerFrame) {
    PassSequence s;
    const std::string out = s.dir.file("out/comp.####.exr"), preview = s.dir.file("prev/prev.####.png");
    const auto r = s.batch(out, "--device cpu --preview " + shellQuote(preview));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(filesIn(s.dir.path() / "prev"),
              (std::set<std::string>{"prev.0001.png", "prev.0002.png", "prev.0003.png"}))
        << "one preview per frame, no partial files left";
    std::vector<std::vector<std::uint8_t>> pixels;
    for (int f : kFrames) {
        const Png p = readPng(FramePattern(preview).path(f));
        ASSERT_EQ(p.width, 2 * kWidth + 4) << "before | after with a 4 pixel gap";
        ASSERT_EQ(p.height, kHeight) << "no normal pass: one row";
        // The after panel shows the decal the before panel lacks.
        std::size_t changed = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int c = 0; c < 3; ++c)
                    changed += p.rgb[(std::size_t(y) * p.width + x) * 3 + c] !=
                               p.rgb[(std::size_t(y) * p.width + x + kWidth + 4) * 3 + c];
        EXPECT_GT(changed, 50u) << "frame " << f;
        pixels.push_back(p.rgb);
    }
    EXPECT_NE(pixels[0], pixels[2]) << "each frame's own preview (the camera moves)";

    const auto bad =
        s.batch(s.dir.file("out2/comp.####.exr"), "--device cpu --preview " + shellQuote(s.dir.file("prev.png")));
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find(s.dir.file("prev.png") + ": no frame number in the pattern"), std::string::npos)
        << bad.output;
    EXPECT_FALSE(fs::exists(s.dir.file("prev.png")));
    EXPECT_FALSE(fs::exists(s.dir.file("out2")));
}

TEST(BatchFeatures, TwoDevicesGiveTheSameBytesAsOne) {
    PassSequence s;
    const std::string one = s.dir.file("one/comp.####.exr"), two = s.dir.file("two/comp.####.exr");
    const auto r1 = s.batch(one, "--device cpu");
    ASSERT_EQ(r1.exit_code, 0) << r1.output;
    const auto r2 = s.batch(two, "--device cpu,cpu");
    ASSERT_EQ(r2.exit_code, 0) << r2.output;
    for (int f : kFrames) {
        EXPECT_EQ(test::readFileBytes(FramePattern(one).path(f)), test::readFileBytes(FramePattern(two).path(f)))
            << "frame " << f;
        EXPECT_EQ(test::pixelDifference(readExr(FramePattern(one).path(f)), readExr(FramePattern(two).path(f))), "");
    }
    const std::string name = selectDevice("cpu").name;
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    EXPECT_NE(r1.output.find(fmt::format("batch: 3 frames on {} ({} workers); cameras: ", name,
                                         defaultCompositeWorkers(threads, 1))),
              std::string::npos)
        << r1.output;
    EXPECT_NE(r2.output.find(fmt::format("batch: 3 frames on {}, {} ({} workers each); cameras: ", name, name,
                                         defaultCompositeWorkers(threads, 2))),
              std::string::npos)
        << r2.output;
    const auto r3 = s.batch(s.dir.file("three/comp.####.exr"), "--device cpu --workers 3");
    ASSERT_EQ(r3.exit_code, 0) << r3.output;
    EXPECT_NE(r3.output.find("batch: 3 frames on " + name + " (3 workers); cameras: "), std::string::npos)
        << r3.output;

    for (const std::string bad : {"cpu,", ",cpu", "cpu,,cpu"}) {
        const std::string out = s.dir.file("bad/comp.####.exr");
        const auto r = s.batch(out, "--device " + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find("--device " + bad + ": empty device in the list"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(s.dir.file("bad"))) << bad;
    }
}

// The contact sheet tiles every frame's composited albedo in frame order: with frames smaller than
// a thumbnail, each cell is exactly the "after" half of that frame's preview (the same sRGB
// encoding); 3 frames make a 2x2 grid whose fourth cell, no frame's, stays black.
TEST(BatchFeatures, ContactSheetShowsEveryCompositedFrameInOrder) {
    PassSequence s;
    const std::string preview = s.dir.file("prev/prev.####.png"), sheet = s.dir.file("sheets/seq.png");
    const auto r = s.batch(s.dir.file("out/comp.####.exr"),
                           "--device cpu --preview " + shellQuote(preview) + " --contact-sheet " + shellQuote(sheet));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("contact sheet: " + sheet), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(s.dir.path() / "sheets"), (std::set<std::string>{"seq.png"})) << "no temporary left";
    const Png p = readPng(sheet);
    constexpr int kGap = 4, kColumns = 2;
    ASSERT_EQ(p.width, kColumns * kWidth + 3 * kGap);
    ASSERT_EQ(p.height, 2 * kHeight + 3 * kGap);
    for (std::size_t i = 0; i < kFrames.size(); ++i) {
        const Png frame = readPng(FramePattern(preview).path(kFrames[i]));
        const int x0 = kGap + int(i % kColumns) * (kWidth + kGap), y0 = kGap + int(i / kColumns) * (kHeight + kGap);
        std::size_t differing = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int c = 0; c < 3; ++c) differing += p.at(x0 + x, y0 + y)[c] != frame.at(kWidth + kGap + x, y)[c];
        EXPECT_EQ(differing, 0u) << "frame " << kFrames[i] << " in cell " << i;
    }
    const int x3 = kGap + (kWidth + kGap), y3 = kGap + (kHeight + kGap);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(p.at(x3 + 5, y3 + 5)[c], 0) << "the cell after the last frame";
    EXPECT_EQ(p.at(1, 1)[0], 0) << "black gaps between cells";
}

// Frames a run did not composite keep their place as grey cells: one skipped by --resume here.
TEST(BatchFeatures, ContactSheetKeepsSkippedFramesInPlace) {
    PassSequence s;
    const std::string out = s.dir.file("out/comp.####.exr"), sheet = s.dir.file("seq.png");
    ASSERT_EQ(s.batch(out, "--device cpu --frames 2").exit_code, 0);
    const auto r = s.batch(out, "--device cpu --resume --contact-sheet " + shellQuote(sheet));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Png p = readPng(sheet);
    constexpr int kGap = 4;
    ASSERT_EQ(p.width, 2 * kWidth + 3 * kGap);
    const auto cellIsGrey = [&](int cell) {
        const int x0 = kGap + (cell % 2) * (kWidth + kGap), y0 = kGap + (cell / 2) * (kHeight + kGap);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int c = 0; c < 3; ++c)
                    if (p.at(x0 + x, y0 + y)[c] != 64) return false;
        return true;
    };
    EXPECT_FALSE(cellIsGrey(0)) << "frame 1 composited";
    EXPECT_TRUE(cellIsGrey(1)) << "frame 2 skipped by --resume";
    EXPECT_FALSE(cellIsGrey(2)) << "frame 3 composited";
}

// A sharded run writes one sheet per shard; a sheet that would replace something the batch reads
// or writes is refused before any frame is written.
TEST(BatchFeatures, ContactSheetPerShardAndNeverOverAnInput) {
    PassSequence s;
    const auto sharded = s.batch(s.dir.file("out/comp.####.exr"),
                                 "--device cpu --shard 2/2 --contact-sheet " + shellQuote(s.dir.file("seq.png")));
    ASSERT_EQ(sharded.exit_code, 0) << sharded.output;
    EXPECT_TRUE(fs::exists(s.dir.file("seq.shard-2-of-2.png")));
    EXPECT_FALSE(fs::exists(s.dir.file("seq.png")));

    const std::string texture = (s.dir.path() / "red.png").string();
    const std::string before = test::readFileBytes(texture);
    struct Case {
        std::string sheet, message;
    };
    for (const Case& c : {Case{texture, "the contact sheet would replace a texture of the scene"},
                          Case{s.albedoAt(2), "give it a .png name"},
                          Case{s.dir.file("prev/p.0003.png"), "the contact sheet would replace frame 3's preview"}}) {
        const auto r = s.batch(s.dir.file("bad/comp.####.exr"), "--device cpu --preview " +
                                                                     shellQuote(s.dir.file("prev/p.####.png")) +
                                                                     " --contact-sheet " + shellQuote(c.sheet));
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(s.dir.file("bad"))) << "nothing written: " << c.sheet;
    }
    EXPECT_EQ(test::readFileBytes(texture), before);
}

}  // namespace
}  // namespace decalcomp
