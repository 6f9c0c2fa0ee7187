// Frames made of several files (one file per pass with --pass, pooled positional inputs), passes
// of different pixel types and data windows (crop, overscan), and which files are written where.
#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>

#include <cstring>
#include <filesystem>
#include <functional>

#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;
using test::channel;
using test::shellQuote;

const std::string kSize = "--width 96 --height 72";

void gen(const std::string& arguments, const std::string& output, const std::string& camera = "") {
    const auto r = test::runGenerator(arguments, output, camera);
    ASSERT_EQ(r.exit_code, 0) << r.output;
}

test::CommandResult composite(const std::string& inputs, const std::string& camera, const std::string& output,
                              const std::string& extra = "") {
    return test::runCli("composite " + inputs + " --decals " + shellQuote(test::dataPath("sample/boxes.json")) +
                        " --camera " + shellQuote(camera) + " --device cpu -o " + shellQuote(output) + " " + extra);
}

// The sample at display pixel (x, y) of a single-part image, as raw bits (float or half widened).
std::uint32_t bitsAt(const ExrImage& image, const std::string& name, int x, int y) {
    const ExrPart& part = image.parts.at(0);
    const Imath::Box2i dw = part.header.dataWindow();
    const ExrChannel& c = channel(image, name);
    const std::size_t i = std::size_t(y - dw.min.y) * std::size_t(part.width) + std::size_t(x - dw.min.x);
    std::uint32_t bits = 0;
    std::memcpy(&bits, c.bytes.data() + i * io::sampleSize(c.type), io::sampleSize(c.type));
    return bits;
}

bool inside(const ExrImage& image, int x, int y) {
    const Imath::Box2i dw = image.parts.at(0).header.dataWindow();
    return x >= dw.min.x && x <= dw.max.x && y >= dw.min.y && y <= dw.max.y;
}

// A single-part image keeping only the channels `keep` accepts.
ExrImage subset(const ExrImage& image, const std::function<bool(const std::string&)>& keep) {
    ExrImage out;
    out.path = image.path;
    ExrPart part = image.parts.at(0);
    part.channels.clear();
    part.header.channels() = Imf::ChannelList();
    for (const ExrChannel& c : image.parts.at(0).channels)
        if (keep(c.name)) {
            part.header.channels().insert(c.name, *image.parts.at(0).header.channels().findChannel(c.name));
            part.channels.push_back(c);
        }
    out.parts.push_back(part);
    return out;
}

// A single-part image cut down to `window` (inside its data window).
ExrImage crop(const ExrImage& image, const Imath::Box2i& window) {
    ExrImage out = image;
    ExrPart& part = out.parts.at(0);
    const Imath::Box2i dw = image.parts.at(0).header.dataWindow();
    const int w = window.max.x - window.min.x + 1, h = window.max.y - window.min.y + 1;
    for (ExrChannel& c : part.channels) {
        const std::size_t size = io::sampleSize(c.type);
        std::vector<unsigned char> bytes(std::size_t(w) * h * size);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t src = std::size_t(y + window.min.y - dw.min.y) * image.parts[0].width +
                                        std::size_t(x + window.min.x - dw.min.x);
                std::memcpy(bytes.data() + (std::size_t(y) * w + x) * size, c.bytes.data() + src * size, size);
            }
        c.bytes = std::move(bytes);
    }
    part.header.dataWindow() = window;
    part.width = w;
    part.height = h;
    return out;
}

std::size_t filesIn(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& entry : fs::directory_iterator(dir)) n += entry.is_regular_file();
    return n;
}

// Every display pixel both images cover holds the same bits in the two channels.
std::size_t compareOverlap(const ExrImage& a, const std::string& a_channel, const ExrImage& b,
                           const std::string& b_channel) {
    std::size_t compared = 0;
    const Imath::Box2i dw = a.parts.at(0).header.dataWindow();
    for (int y = dw.min.y; y <= dw.max.y; ++y)
        for (int x = dw.min.x; x <= dw.max.x; ++x) {
            if (!inside(b, x, y)) continue;
            EXPECT_EQ(bitsAt(a, a_channel, x, y), bitsAt(b, b_channel, x, y))
                << a.path << " " << a_channel << " vs " << b.path << " " << b_channel << " at " << x << "," << y;
            if (bitsAt(a, a_channel, x, y) != bitsAt(b, b_channel, x, y)) return compared;
            ++compared;
        }
    return compared;
}

struct Reference {
    std::string input, output, camera;
};

// The full-frame multilayer render composited: what every other layout must reproduce.
Reference fullFrame(const ScratchDir& dir, const std::string& extra = "") {
    Reference r{dir.file("full.exr"), dir.file("full_out.exr"), dir.file("cam.json")};
    gen(kSize + " --naming generic " + extra, r.input, r.camera);
    const auto c = composite(shellQuote(r.input), r.camera, r.output);
    EXPECT_EQ(c.exit_code, 0) << c.output;
    return r;
}

// Pixels the decals changed in the full frame (so comparisons are not vacuous).
std::size_t changedPixels(const Reference& ref) {
    const ExrImage in = readExr(ref.input), out = readExr(ref.output);
    std::size_t n = 0;
    const ExrChannel &a = channel(in, "albedo.R"), &b = channel(out, "albedo.R");
    for (std::size_t i = 0; i < a.bytes.size(); i += 4) n += std::memcmp(&a.bytes[i], &b.bytes[i], 4) != 0;
    return n;
}

TEST(PerPassFiles, OneFilePerPassCompositesLikeOneMultilayerFile) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir);
    ASSERT_GT(changedPixels(ref), 200u);
    const std::string shot = dir.file("shot.exr");
    gen(kSize + " --per-pass", shot);
    fs::create_directories(dir.file("out"));
    const std::string out = dir.file("out/albedo_out.exr");
    const auto r = composite(shellQuote(shot) + " --pass depth=" + shellQuote(dir.file("shot.depth.exr")) +
                                 " --pass albedo=" + shellQuote(dir.file("shot.albedo.exr")),
                             ref.camera, out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(out + ": "), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(dir.file("out")), 1u) << "only the albedo file is written";

    const ExrImage result = readExr(out), input = readExr(dir.file("shot.albedo.exr")), full = readExr(ref.output);
    ASSERT_EQ(result.parts.size(), 1u);
    ASSERT_EQ(result.parts[0].channels.size(), 3u) << "the albedo file's layout";
    for (const char* c : {"R", "G", "B"}) {
        EXPECT_EQ(compareOverlap(result, c, full, std::string("albedo.") + c), 96u * 72u) << c;
        EXPECT_EQ(channel(result, c).type, channel(input, c).type);
    }
}

TEST(PerPassFiles, PassesOfDifferentPixelTypes) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir, "--half");
    const std::string shot = dir.file("shot.exr");
    gen(kSize + " --per-pass --half", shot);
    const ExrImage albedo_in = readExr(dir.file("shot.albedo.exr"));
    ASSERT_EQ(channel(albedo_in, "R").type, SampleType::Half);
    ASSERT_EQ(channel(readExr(dir.file("shot.depth.exr")), "Z").type, SampleType::Float);
    const std::string out = dir.file("albedo_out.exr");
    const auto r = composite(shellQuote(shot) + " --pass albedo=" + shellQuote(dir.file("shot.albedo.exr")) +
                                 " --pass depth=" + shellQuote(dir.file("shot.depth.exr")) + " --pass position=" +
                                 shellQuote(dir.file("shot.position.exr")),
                             ref.camera, out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const ExrImage result = readExr(out), full = readExr(ref.output);
    EXPECT_EQ(channel(result, "G").type, SampleType::Half);
    for (const char* c : {"R", "G", "B"}) EXPECT_EQ(compareOverlap(result, c, full, std::string("albedo.") + c), 96u * 72u);
    // With the position pass given, the depth check ran.
    EXPECT_NE(r.output.find("depth check: planar"), std::string::npos) << r.output;
}

TEST(PerPassFiles, InfoExplainsPassFiles) {
    ScratchDir dir;
    const std::string shot = dir.file("shot.exr");
    gen("--width 32 --height 24 --per-pass", shot);
    const auto r = test::runCli("info " + shellQuote(shot) + " --pass depth=" + shellQuote(dir.file("shot.depth.exr")) +
                                " --pass albedo=" + shellQuote(dir.file("shot.albedo.exr")) + " --pass id=" +
                                shellQuote(dir.file("shot.id.exr")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    for (const std::string& needle :
         {"depth <- Z (--pass " + dir.file("shot.depth.exr") + ", profile generic)",
          "albedo <- R, G, B (--pass " + dir.file("shot.albedo.exr") + ", by component names)",
          "object_id <- id (--pass " + dir.file("shot.id.exr") + ", profile generic)"})
        EXPECT_NE(r.output.find(needle), std::string::npos) << needle << "\n" << r.output;
}

TEST(PerPassFiles, PassFileWithoutTheAttributeIsAnInputError) {
    ScratchDir dir;
    const std::string shot = dir.file("shot.exr");
    gen("--width 32 --height 24 --per-pass", shot, dir.file("cam.json"));
    const std::string depth = dir.file("shot.depth.exr");
    const auto r = composite(shellQuote(shot) + " --pass depth=" + shellQuote(depth) + " --pass albedo=" +
                                 shellQuote(dir.file("shot.albedo.exr")) + " --pass normal=" + shellQuote(depth),
                             dir.file("cam.json"), dir.file("out.exr"));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find(depth + ": --pass normal: no normal channels found (channels: Z)"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));

    const auto bad_flag = composite(shellQuote(shot) + " --pass colour=" + shellQuote(depth), dir.file("cam.json"),
                                    dir.file("out.exr"));
    EXPECT_EQ(bad_flag.exit_code, 2) << bad_flag.output;
    EXPECT_NE(bad_flag.output.find("--pass colour="), std::string::npos) << bad_flag.output;
}

TEST(PerPassFiles, PooledPositionalInputs) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir);
    const ExrImage full = readExr(ref.input);
    ExrImage geometry = subset(full, [](const std::string& n) { return n == "Z" || n.rfind("P.", 0) == 0 || n.rfind("N.", 0) == 0; });
    ExrImage shading = subset(full, [](const std::string& n) { return n.rfind("albedo.", 0) == 0 || n.size() == 1; });
    // "Z" has one letter too: keep it only in the geometry file.
    shading = subset(shading, [](const std::string& n) { return n != "Z"; });
    writeExrAtomic(geometry, dir.file("geo.exr"));
    writeExrAtomic(shading, dir.file("shading.exr"));
    fs::create_directories(dir.file("out"));
    const std::string out = dir.file("out/shading_out.exr");
    const auto r = composite(shellQuote(dir.file("geo.exr")) + " " + shellQuote(dir.file("shading.exr")), ref.camera, out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(filesIn(dir.file("out")), 1u);
    const ExrImage result = readExr(out), reference = readExr(ref.output);
    EXPECT_EQ(result.parts[0].channels.size(), shading.parts[0].channels.size()) << "the shading file's layout";
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "R", "A"})
        EXPECT_EQ(compareOverlap(result, c, reference, c), 96u * 72u) << c;
}

TEST(PerPassFiles, SeveralChangedFilesNeedAnOutputFolder) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir);
    const ExrImage full = readExr(ref.input);
    fs::create_directories(dir.file("a"));
    fs::create_directories(dir.file("b"));
    // albedo.R in one file, albedo.G/B in the other (both hold other channels too).
    writeExrAtomic(subset(full, [](const std::string& n) { return n != "albedo.G" && n != "albedo.B"; }),
                   dir.file("a/first.exr"));
    writeExrAtomic(subset(full, [](const std::string& n) { return n == "albedo.G" || n == "albedo.B"; }),
                   dir.file("b/second.exr"));
    const std::string inputs = shellQuote(dir.file("a/first.exr")) + " " + shellQuote(dir.file("b/second.exr"));

    const auto to_file = composite(inputs, ref.camera, dir.file("out.exr"));
    EXPECT_EQ(to_file.exit_code, 2) << to_file.output;
    EXPECT_NE(to_file.output.find("give -o an output folder"), std::string::npos) << to_file.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));

    const std::string folder = dir.file("outputs") + "/";
    const auto to_folder = composite(inputs, ref.camera, folder);
    ASSERT_EQ(to_folder.exit_code, 0) << to_folder.output;
    EXPECT_EQ(filesIn(dir.file("outputs")), 2u);
    const ExrImage first = readExr(folder + "first.exr"), second = readExr(folder + "second.exr");
    const ExrImage reference = readExr(ref.output);
    EXPECT_EQ(compareOverlap(first, "albedo.R", reference, "albedo.R"), 96u * 72u);
    EXPECT_EQ(compareOverlap(first, "Z", reference, "Z"), 96u * 72u);
    EXPECT_EQ(compareOverlap(second, "albedo.G", reference, "albedo.G"), 96u * 72u);
    EXPECT_EQ(compareOverlap(second, "albedo.B", reference, "albedo.B"), 96u * 72u);

    // Two inputs of one name cannot share a folder.
    fs::copy_file(dir.file("b/second.exr"), dir.file("b/first.exr"));
    const auto clash = composite(shellQuote(dir.file("a/first.exr")) + " " + shellQuote(dir.file("b/first.exr")),
                                 ref.camera, dir.file("clash") + "/");
    EXPECT_EQ(clash.exit_code, 2) << clash.output;
    EXPECT_NE(clash.output.find("would both be written as first.exr"), std::string::npos) << clash.output;

    // Writing over any input is refused.
    const auto over = composite(inputs, ref.camera, dir.file("a") + "/");
    EXPECT_EQ(over.exit_code, 2) << over.output;
    EXPECT_NE(over.output.find("--overwrite-input"), std::string::npos) << over.output;
}

// ---- data windows ----

TEST(DataWindows, CropAndOverscanMatchTheFullFrame) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir);
    const ExrImage full = readExr(ref.output);
    struct Case {
        std::string name, window;
    };
    for (const Case& c : {Case{"crop", "20,10,79,59"}, Case{"overscan", "-8,-6,103,77"}, Case{"corner", "-5,40,30,90"}}) {
        const std::string in = dir.file(c.name + ".exr"), out = dir.file(c.name + "_out.exr");
        gen(kSize + " --naming generic --data-window " + c.window, in);
        const auto r = composite(shellQuote(in), ref.camera, out);
        ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.output;
        const ExrImage result = readExr(out), input = readExr(in);
        EXPECT_EQ(result.parts[0].header.dataWindow(), input.parts[0].header.dataWindow());
        EXPECT_EQ(result.parts[0].header.displayWindow(), Imath::Box2i({0, 0}, {95, 71}));
        std::size_t compared = 0;
        for (const char* channel_name : {"albedo.R", "albedo.G", "albedo.B"})
            compared += compareOverlap(result, channel_name, full, channel_name);
        EXPECT_GT(compared, 3u * 30u * 30u) << c.name;
        // Untouched channels are bit-exact.
        for (const char* channel_name : {"Z", "N.X", "R"}) EXPECT_EQ(channel(result, channel_name).bytes, channel(input, channel_name).bytes);
    }
    const auto info = test::runCli("info " + shellQuote(dir.file("overscan.exr")) + " --camera " + shellQuote(ref.camera));
    EXPECT_EQ(info.exit_code, 0) << info.output;
    EXPECT_NE(info.output.find("data window (-8,-6)-(103,77) (display window (0,0)-(95,71))"), std::string::npos)
        << info.output;
}

TEST(DataWindows, PassesWithDifferentWindows) {
    ScratchDir dir;
    const Reference ref = fullFrame(dir);
    const ExrImage full = readExr(ref.output);
    const std::string shot = dir.file("shot.exr");
    gen(kSize + " --per-pass --data-window -8,-6,103,77", shot);  // every pass with overscan

    // Albedo cropped inside the depth pass's window: composited there like the full frame.
    const ExrImage albedo = readExr(dir.file("shot.albedo.exr"));
    writeExrAtomic(crop(albedo, Imath::Box2i({20, 10}, {79, 59})), dir.file("albedo_crop.exr"));
    const auto r = composite(shellQuote(shot) + " --pass depth=" + shellQuote(dir.file("shot.depth.exr")) +
                                 " --pass albedo=" + shellQuote(dir.file("albedo_crop.exr")),
                             ref.camera, dir.file("crop_out.exr"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const ExrImage result = readExr(dir.file("crop_out.exr"));
    EXPECT_EQ(result.parts[0].header.dataWindow(), Imath::Box2i({20, 10}, {79, 59}));
    for (const char* c : {"R", "G", "B"}) EXPECT_EQ(compareOverlap(result, c, full, std::string("albedo.") + c), 60u * 50u);

    // Depth cropped smaller than the albedo: albedo pixels without depth pass through bit-exact.
    const ExrImage depth = readExr(dir.file("shot.depth.exr"));
    writeExrAtomic(crop(depth, Imath::Box2i({30, 20}, {70, 50})), dir.file("depth_crop.exr"));
    const auto r2 = composite(shellQuote(shot) + " --pass depth=" + shellQuote(dir.file("depth_crop.exr")) +
                                  " --pass albedo=" + shellQuote(dir.file("shot.albedo.exr")),
                              ref.camera, dir.file("depth_crop_out.exr"));
    ASSERT_EQ(r2.exit_code, 0) << r2.output;
    const ExrImage result2 = readExr(dir.file("depth_crop_out.exr"));
    std::size_t outside = 0, inside_depth = 0;
    for (int y = -6; y <= 77; ++y)
        for (int x = -8; x <= 103; ++x)
            for (const char* c : {"R", "G", "B"}) {
                const bool has_depth = x >= 30 && x <= 70 && y >= 20 && y <= 50;
                if (has_depth) {
                    ASSERT_EQ(bitsAt(result2, c, x, y), bitsAt(full, std::string("albedo.") + c, x, y)) << x << "," << y;
                    ++inside_depth;
                } else {
                    ASSERT_EQ(bitsAt(result2, c, x, y), bitsAt(albedo, c, x, y)) << x << "," << y;
                    ++outside;
                }
            }
    EXPECT_GT(inside_depth, 0u);
    EXPECT_GT(outside, 0u);
}

TEST(DataWindows, DisplayWindowsMustAgree) {
    ScratchDir dir;
    const std::string shot = dir.file("shot.exr");
    gen("--width 32 --height 24 --per-pass", shot, dir.file("cam.json"));
    gen("--width 40 --height 24 --per-pass", dir.file("wide.exr"));
    const auto r = composite(shellQuote(shot) + " --pass depth=" + shellQuote(dir.file("wide.depth.exr")) +
                                 " --pass albedo=" + shellQuote(dir.file("shot.albedo.exr")),
                             dir.file("cam.json"), dir.file("out.exr"));
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("display window (0,0)-(31,23) differs from (0,0)-(39,23) of depth"), std::string::npos)
        << r.output;
}

}  // namespace
}  // namespace decalcomp
