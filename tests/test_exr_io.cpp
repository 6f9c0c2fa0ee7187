// readExr / writeExrAtomic / extractGBuffer / storeAttribute on small EXRs written here with the
// plain OpenEXR API, so the reader is checked against bytes it did not produce itself.
#include <gtest/gtest.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineOutputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <OpenEXR/ImfTiledOutputPart.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "io/exr_layout.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;

// ---- fixtures written with OpenEXR directly ----

struct FixtureChannel {
    FixtureChannel(std::string name_, Imf::PixelType type_, int xs = 1, int ys = 1,
                   std::vector<unsigned char> bytes_ = {})
        : name(std::move(name_)), type(type_), x_sampling(xs), y_sampling(ys), bytes(std::move(bytes_)) {}
    std::string name;
    Imf::PixelType type;
    int x_sampling, y_sampling;
    std::vector<unsigned char> bytes;  // filled by fillRandom or from values
};

struct FixturePart {
    Imf::Header header;
    std::vector<FixtureChannel> channels;
};

std::size_t bytesPerSample(Imf::PixelType type) { return type == Imf::HALF ? 2 : 4; }

std::size_t sampleCount(const Imath::Box2i& dw, const FixtureChannel& c) {
    // Test windows start at multiples of the sampling, so plain division is exact.
    const std::size_t w = std::size_t(dw.max.x - dw.min.x + 1) / c.x_sampling;
    const std::size_t h = std::size_t(dw.max.y - dw.min.y + 1) / c.y_sampling;
    return w * h;
}

// Arbitrary bit patterns, NaN payloads and infinities included: the I/O must not interpret them.
void fillRandom(const Imath::Box2i& dw, FixtureChannel& c, unsigned seed) {
    std::mt19937 rng(seed);
    c.bytes.resize(sampleCount(dw, c) * bytesPerSample(c.type));
    for (unsigned char& b : c.bytes) b = static_cast<unsigned char>(rng());
}

template <typename T>
std::vector<unsigned char> toBytes(const std::vector<T>& values) {
    std::vector<unsigned char> bytes(values.size() * sizeof(T));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

Imf::Header makeHeader(int width, int height, Imf::Compression compression) {
    Imf::Header header(width, height);
    header.compression() = compression;
    return header;
}

Imf::FrameBuffer fixtureFrameBuffer(const FixturePart& part) {
    const Imath::Box2i dw = part.header.dataWindow();
    Imf::FrameBuffer fb;
    for (const FixtureChannel& c : part.channels) {
        const std::size_t xs = bytesPerSample(c.type);
        const std::size_t ys = xs * std::size_t(dw.max.x - dw.min.x + 1) / c.x_sampling;
        fb.insert(c.name, Imf::Slice::Make(c.type, c.bytes.data(), dw, xs, ys, c.x_sampling, c.y_sampling));
    }
    return fb;
}

void writeFixture(const std::string& path, std::vector<FixturePart> parts) {
    std::vector<Imf::Header> headers;
    for (FixturePart& part : parts) {
        for (const FixtureChannel& c : part.channels)
            part.header.channels().insert(c.name, Imf::Channel(c.type, c.x_sampling, c.y_sampling));
        if (!part.header.hasType())
            part.header.setType(part.header.hasTileDescription() ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
        headers.push_back(part.header);
    }
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), int(headers.size()));
    for (int i = 0; i < int(parts.size()); ++i) {
        if (parts[i].header.hasTileDescription()) {
            Imf::TiledOutputPart out(file, i);
            out.setFrameBuffer(fixtureFrameBuffer(parts[i]));
            out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
        } else {
            Imf::OutputPart out(file, i);
            out.setFrameBuffer(fixtureFrameBuffer(parts[i]));
            const Imath::Box2i dw = parts[i].header.dataWindow();
            out.writePixels(dw.max.y - dw.min.y + 1);
        }
    }
}

// A single-part scanline file: half, float and uint channels, one of them subsampled, PIZ,
// a custom string attribute and a data window inside a larger display window.
FixturePart mixedPart() {
    FixturePart part{makeHeader(64, 48, Imf::PIZ_COMPRESSION), {}};
    part.header.dataWindow() = Imath::Box2i({10, 6}, {41, 29});
    part.header.insert("studio:note", Imf::StringAttribute("keep me"));
    part.channels = {{"albedo.R", Imf::HALF}, {"albedo.G", Imf::HALF}, {"albedo.B", Imf::HALF},
                     {"Z", Imf::FLOAT},       {"id", Imf::UINT},        {"chroma", Imf::HALF, 2, 2}};
    unsigned seed = 1;
    for (FixtureChannel& c : part.channels) fillRandom(part.header.dataWindow(), c, seed++);
    return part;
}

const ExrChannel& channelNamed(const ExrPart& part, const std::string& name) {
    for (const ExrChannel& c : part.channels)
        if (c.name == name) return c;
    throw std::runtime_error("no channel " + name);
}

const FixtureChannel& fixtureNamed(const FixturePart& part, const std::string& name) {
    for (const FixtureChannel& c : part.channels)
        if (c.name == name) return c;
    throw std::runtime_error("no fixture channel " + name);
}

void expectSameChannels(const ExrImage& a, const ExrImage& b) {
    ASSERT_EQ(a.parts.size(), b.parts.size());
    for (std::size_t p = 0; p < a.parts.size(); ++p) {
        ASSERT_EQ(a.parts[p].channels.size(), b.parts[p].channels.size());
        for (std::size_t c = 0; c < a.parts[p].channels.size(); ++c) {
            const ExrChannel& x = a.parts[p].channels[c];
            const ExrChannel& y = b.parts[p].channels[c];
            EXPECT_EQ(x.name, y.name);
            EXPECT_EQ(x.type, y.type) << x.name;
            EXPECT_EQ(x.x_sampling, y.x_sampling) << x.name;
            EXPECT_TRUE(x.bytes == y.bytes) << "part " << p << " channel " << x.name << " differs";
        }
    }
}

template <typename Fn>
Error expectError(ErrorKind kind, Fn&& fn) {
    try {
        fn();
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(kind)) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "message must be one line";
        return e;
    }
    ADD_FAILURE() << "expected decalcomp::Error";
    return Error(kind, "");
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// ---- reading ----

TEST(ExrIo, ReadsRawSamplesOfEveryType) {
    ScratchDir dir;
    const FixturePart fixture = mixedPart();
    writeFixture(dir.file("in.exr"), {fixture});

    const ExrImage image = readExr(dir.file("in.exr"));
    ASSERT_EQ(image.parts.size(), 1u);
    const ExrPart& part = image.parts[0];
    EXPECT_EQ(part.width, 32);
    EXPECT_EQ(part.height, 24);
    ASSERT_EQ(part.channels.size(), fixture.channels.size());
    for (const FixtureChannel& expected : fixture.channels) {
        const ExrChannel& got = channelNamed(part, expected.name);
        EXPECT_EQ(got.qualified, expected.name) << "single-part names are used as they are";
        EXPECT_EQ(got.x_sampling, expected.x_sampling);
        EXPECT_EQ(got.y_sampling, expected.y_sampling);
        EXPECT_TRUE(got.bytes == expected.bytes) << expected.name;
    }
    EXPECT_EQ(channelNamed(part, "albedo.R").type, SampleType::Half);
    EXPECT_EQ(channelNamed(part, "Z").type, SampleType::Float);
    EXPECT_EQ(channelNamed(part, "id").type, SampleType::Uint);
    EXPECT_EQ(channelNamed(part, "chroma").bytes.size(), 16u * 12u * 2u);
}

TEST(ExrIo, MultiPartNamesQualifyChannelsWithoutDots) {
    ScratchDir dir;
    FixturePart depth{makeHeader(8, 4, Imf::ZIP_COMPRESSION), {{"Z", Imf::FLOAT}}};
    depth.header.setName("RenderLayer.Depth");
    FixturePart colour{makeHeader(8, 4, Imf::ZIP_COMPRESSION), {{"R", Imf::HALF}, {"extra.A", Imf::HALF}}};
    colour.header.setName("RenderLayer.DiffCol");
    for (FixturePart* part : {&depth, &colour})
        for (FixtureChannel& c : part->channels) fillRandom(part->header.dataWindow(), c, 7);
    writeFixture(dir.file("parts.exr"), {depth, colour});

    const ExrImage image = readExr(dir.file("parts.exr"));
    ASSERT_EQ(image.parts.size(), 2u);
    EXPECT_EQ(image.parts[0].channels[0].qualified, "RenderLayer.Depth.Z");
    EXPECT_EQ(channelNamed(image.parts[1], "R").qualified, "RenderLayer.DiffCol.R");
    EXPECT_EQ(channelNamed(image.parts[1], "extra.A").qualified, "extra.A");
}

// ---- round trips ----

TEST(ExrIo, RoundTripIsBitExactAndKeepsHeader) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    const ExrImage original = readExr(dir.file("in.exr"));
    writeExrAtomic(original, dir.file("out.exr"));

    EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"in.exr", "out.exr"})) << "temporary file left";
    const ExrImage copy = readExr(dir.file("out.exr"));
    expectSameChannels(original, copy);
    const Imf::Header& h = copy.parts[0].header;
    EXPECT_EQ(h.compression(), Imf::PIZ_COMPRESSION);
    EXPECT_EQ(h.dataWindow(), Imath::Box2i({10, 6}, {41, 29}));
    EXPECT_EQ(h.displayWindow(), Imath::Box2i({0, 0}, {63, 47}));
    const auto* note = h.findTypedAttribute<Imf::StringAttribute>("studio:note");
    ASSERT_NE(note, nullptr);
    EXPECT_EQ(note->value(), "keep me");
    EXPECT_EQ(h.channels().findChannel("chroma")->xSampling, 2);
}

TEST(ExrIo, RoundTripMultiPartKeepsPartsAndBits) {
    ScratchDir dir;
    FixturePart a{makeHeader(16, 8, Imf::ZIP_COMPRESSION), {{"Z", Imf::FLOAT}}};
    a.header.setName("RenderLayer.Depth");
    FixturePart b{makeHeader(16, 8, Imf::RLE_COMPRESSION), {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}};
    b.header.setName("RenderLayer.DiffCol");
    b.header.dataWindow() = Imath::Box2i({2, 1}, {11, 6});
    unsigned seed = 20;
    for (FixturePart* part : {&a, &b})
        for (FixtureChannel& c : part->channels) fillRandom(part->header.dataWindow(), c, seed++);
    writeFixture(dir.file("in.exr"), {a, b});

    const ExrImage original = readExr(dir.file("in.exr"));
    writeExrAtomic(original, dir.file("out.exr"));
    const ExrImage copy = readExr(dir.file("out.exr"));
    expectSameChannels(original, copy);
    EXPECT_EQ(copy.parts[0].header.name(), "RenderLayer.Depth");
    EXPECT_EQ(copy.parts[1].header.name(), "RenderLayer.DiffCol");
    EXPECT_EQ(copy.parts[1].header.compression(), Imf::RLE_COMPRESSION);
    EXPECT_EQ(copy.parts[1].header.dataWindow(), b.header.dataWindow());
}

TEST(ExrIo, RoundTripTiledKeepsTilingAndBits) {
    ScratchDir dir;
    FixturePart part{makeHeader(37, 23, Imf::ZIP_COMPRESSION), {{"R", Imf::HALF}, {"Z", Imf::FLOAT}}};
    part.header.setTileDescription(Imf::TileDescription(16, 8, Imf::ONE_LEVEL));  // partial edge tiles
    unsigned seed = 40;
    for (FixtureChannel& c : part.channels) fillRandom(part.header.dataWindow(), c, seed++);
    writeFixture(dir.file("tiled.exr"), {part});

    const ExrImage original = readExr(dir.file("tiled.exr"));
    EXPECT_TRUE(channelNamed(original.parts[0], "R").bytes == fixtureNamed(part, "R").bytes);
    writeExrAtomic(original, dir.file("out.exr"));
    const ExrImage copy = readExr(dir.file("out.exr"));
    expectSameChannels(original, copy);
    ASSERT_TRUE(copy.parts[0].header.hasTileDescription());
    EXPECT_EQ(copy.parts[0].header.tileDescription().xSize, 16u);
    EXPECT_EQ(copy.parts[0].header.tileDescription().ySize, 8u);
    EXPECT_EQ(copy.parts[0].header.compression(), Imf::ZIP_COMPRESSION);
}

TEST(ExrIo, WriteOverItsOwnInputReplacesIt) {
    ScratchDir dir;
    writeFixture(dir.file("frame.exr"), {mixedPart()});
    ExrImage image = readExr(dir.file("frame.exr"));
    for (ExrChannel& c : image.parts[0].channels)
        if (c.name == "Z") std::fill(c.bytes.begin(), c.bytes.end(), 0);
    writeExrAtomic(image, dir.file("frame.exr"));
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"frame.exr"});
    const ExrImage again = readExr(dir.file("frame.exr"));
    const auto& z = channelNamed(again.parts[0], "Z").bytes;
    EXPECT_TRUE(std::all_of(z.begin(), z.end(), [](unsigned char b) { return b == 0; }));
}

TEST(ExrIo, WriteToMissingDirectoryThrowsAndLeavesNothing) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    const ExrImage image = readExr(dir.file("in.exr"));
    const std::string target = dir.file("no-such-dir/out.exr");
    const Error e = expectError(ErrorKind::Output, [&] { writeExrAtomic(image, target); });
    EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"in.exr"});
}

TEST(ExrIo, WriteRefusesChannelBytesOfTheWrongSize) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    ExrImage image = readExr(dir.file("in.exr"));
    for (ExrChannel& c : image.parts[0].channels)
        if (c.name == "albedo.R") c.bytes.pop_back();
    const Error e = expectError(ErrorKind::Output, [&] { writeExrAtomic(image, dir.file("out.exr")); });
    EXPECT_NE(std::string(e.what()).find("albedo.R"), std::string::npos) << e.what();
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"in.exr"});
}

// ---- refused and broken inputs ----

TEST(ExrIo, TruncatedFileIsAnInputErrorNamingTheFile) {
    ScratchDir dir;
    writeFixture(dir.file("good.exr"), {mixedPart()});
    std::ifstream in(dir.file("good.exr"), std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (std::size_t keep : {content.size() / 2, std::size_t(200), std::size_t(10)}) {
        const std::string path = dir.file("cut.exr");
        std::ofstream(path, std::ios::binary | std::ios::trunc).write(content.data(), std::streamsize(keep));
        const Error e = expectError(ErrorKind::Input, [&] { readExr(path); });
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << "kept " << keep << ": " << e.what();
    }
}

TEST(ExrIo, TextFileIsNotAnExr) {
    ScratchDir dir;
    std::ofstream(dir.file("notes.exr")) << "this is not an image\n";
    const Error e = expectError(ErrorKind::Input, [&] { readExr(dir.file("notes.exr")); });
    EXPECT_EQ(std::string(e.what()), dir.file("notes.exr") + ": not an OpenEXR file");
}

TEST(ExrIo, MissingFileNamesTheFile) {
    ScratchDir dir;
    const Error e = expectError(ErrorKind::Input, [&] { readExr(dir.file("absent.exr")); });
    EXPECT_EQ(std::string(e.what()).rfind(dir.file("absent.exr") + ": cannot open", 0), 0u) << e.what();
}

TEST(ExrIo, DeepFileIsRefused) {
    ScratchDir dir;
    const std::string path = dir.file("deep.exr");
    {
        Imf::Header header(4, 2);
        header.compression() = Imf::ZIPS_COMPRESSION;
        header.setType(Imf::DEEPSCANLINE);
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        std::vector<unsigned> counts(8, 1);
        std::vector<float> depths(8, 1.5f);
        std::vector<float*> pointers(8);
        for (int i = 0; i < 8; ++i) pointers[i] = &depths[i];
        Imf::DeepFrameBuffer fb;
        fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()), sizeof(unsigned),
                                             4 * sizeof(unsigned)));
        fb.insert("Z", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(pointers.data()), sizeof(float*),
                                      4 * sizeof(float*), sizeof(float)));
        Imf::DeepScanLineOutputFile out(path.c_str(), header);
        out.setFrameBuffer(fb);
        out.writePixels(2);
    }
    const Error e = expectError(ErrorKind::Input, [&] { readExr(path); });
    EXPECT_NE(std::string(e.what()).find("deep"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
}

TEST(ExrIo, MipmappedTilesAreRefused) {
    ScratchDir dir;
    const std::string path = dir.file("mip.exr");
    {
        Imf::Header header(16, 16);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        header.setTileDescription(Imf::TileDescription(8, 8, Imf::MIPMAP_LEVELS));
        Imf::TiledOutputFile out(path.c_str(), header);
        for (int level = 0; level < out.numLevels(); ++level) {
            const Imath::Box2i dw = out.dataWindowForLevel(level);
            std::vector<float> values(std::size_t(out.levelWidth(level)) * out.levelHeight(level), 0.25f);
            Imf::FrameBuffer fb;
            fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, values.data(), dw));
            out.setFrameBuffer(fb);
            out.writeTiles(0, out.numXTiles(level) - 1, 0, out.numYTiles(level) - 1, level);
        }
    }
    const Error e = expectError(ErrorKind::Input, [&] { readExr(path); });
    EXPECT_NE(std::string(e.what()).find("mipmapped"), std::string::npos) << e.what();
}

// ---- G-buffer extraction and storing back ----

ChannelMapping explicitMapping(const ExrImage& image, std::map<Attribute, std::vector<std::string>> channels) {
    MappingOptions options;
    options.profile = "generic";
    options.explicit_channels = std::move(channels);
    return mapChannels(image, options);
}

TEST(ExrIo, ExtractUsesDataAndDisplayWindows) {
    ScratchDir dir;
    FixturePart part{makeHeader(64, 48, Imf::ZIP_COMPRESSION), {}};
    part.header.dataWindow() = Imath::Box2i({10, 6}, {41, 29});
    const std::size_t n = 32 * 24;
    std::vector<Imath::half> r(n), g(n), b(n);
    std::vector<float> z(n);
    std::vector<std::uint32_t> id(n);
    for (std::size_t i = 0; i < n; ++i) {
        r[i] = Imath::half(float(i) / n);
        g[i] = Imath::half(0.5f);
        b[i] = Imath::half(-float(i % 7));
        z[i] = 1.0f + float(i) * 0.001f;
        id[i] = std::uint32_t(i % 5);
    }
    part.channels = {{"albedo.R", Imf::HALF, 1, 1, toBytes(r)},
                     {"albedo.G", Imf::HALF, 1, 1, toBytes(g)},
                     {"albedo.B", Imf::HALF, 1, 1, toBytes(b)},
                     {"Z", Imf::FLOAT, 1, 1, toBytes(z)},
                     {"id", Imf::UINT, 1, 1, toBytes(id)}};
    writeFixture(dir.file("in.exr"), {part});
    const ExrImage image = readExr(dir.file("in.exr"));
    const GBuffer gb = extractGBuffer(image, mapChannels(image, MappingOptions{}));

    EXPECT_EQ(gb.width, 32);
    EXPECT_EQ(gb.height, 24);
    EXPECT_EQ(gb.origin_x, 10);
    EXPECT_EQ(gb.origin_y, 6);
    EXPECT_EQ(gb.display_width, 64);
    EXPECT_EQ(gb.display_height, 48);
    EXPECT_EQ(gb.depth_convention, DepthConvention::Planar);
    ASSERT_TRUE(gb.has(Attribute::Albedo) && gb.has(Attribute::Depth) && gb.has(Attribute::ObjectId));
    const Plane& albedo = gb.planes.at(Attribute::Albedo);
    ASSERT_EQ(albedo.components, 3);
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(albedo.at(i, 0), float(r[i])) << i;
        ASSERT_EQ(albedo.at(i, 1), 0.5f);
        ASSERT_EQ(albedo.at(i, 2), float(b[i]));
        ASSERT_EQ(gb.planes.at(Attribute::Depth).at(i, 0), z[i]);
        ASSERT_EQ(gb.planes.at(Attribute::ObjectId).at(i, 0), float(id[i]));
    }
}

TEST(ExrIo, StoringUnchangedValuesKeepsEveryBit) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});  // random bits: NaN payloads, infinities, denormals
    ExrImage image = readExr(dir.file("in.exr"));
    const ExrImage original = image;
    const ChannelMapping mapping = explicitMapping(
        image, {{Attribute::Albedo, {"albedo.R", "albedo.G", "albedo.B"}}, {Attribute::Depth, {"Z"}},
                {Attribute::ObjectId, {"id"}}});
    const GBuffer gb = extractGBuffer(image, mapping);
    for (const auto& [attribute, plane] : gb.planes) storeAttribute(image, mapping, attribute, plane);
    expectSameChannels(original, image);
}

TEST(ExrIo, StoringConvertsToEachChannelType) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    ExrImage image = readExr(dir.file("in.exr"));
    const ChannelMapping mapping = explicitMapping(
        image, {{Attribute::Albedo, {"albedo.R", "albedo.G", "albedo.B"}}, {Attribute::ObjectId, {"id"}}});
    GBuffer gb = extractGBuffer(image, mapping);
    Plane& albedo = gb.planes.at(Attribute::Albedo);
    const std::size_t n = gb.pixelCount();
    // Every value changes: finite halves from a formula, so the conversion itself is exercised.
    for (std::size_t i = 0; i < n; ++i) {
        albedo.at(i, 0) = float(Imath::half(float(i) * 0.37f - 50.0f));
        albedo.at(i, 1) = 1.0f / 3.0f;
        albedo.at(i, 2) = 70000.0f;  // beyond half's range
    }
    Plane& ids = gb.planes.at(Attribute::ObjectId);
    for (std::size_t i = 0; i < n; ++i) ids.at(i, 0) = float(i) + 0.6f;
    storeAttribute(image, mapping, Attribute::Albedo, albedo);
    storeAttribute(image, mapping, Attribute::ObjectId, ids);

    const auto halfBits = [&](const std::string& name, std::size_t i) {
        std::uint16_t bits;
        std::memcpy(&bits, channelNamed(image.parts[0], name).bytes.data() + 2 * i, 2);
        return bits;
    };
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(halfBits("albedo.R", i), Imath::half(float(i) * 0.37f - 50.0f).bits()) << i;
        ASSERT_EQ(halfBits("albedo.G", i), Imath::half(1.0f / 3.0f).bits());
        Imath::half overflowed;
        overflowed.setBits(halfBits("albedo.B", i));
        ASSERT_TRUE(overflowed.isInfinity());
        std::uint32_t id;
        std::memcpy(&id, channelNamed(image.parts[0], "id").bytes.data() + 4 * i, 4);
        ASSERT_EQ(id, std::uint32_t(i + 1));
    }
}

TEST(ExrIo, UintChannelMappedToDepthIsTheWrongType) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    const ExrImage image = readExr(dir.file("in.exr"));
    const ChannelMapping mapping = explicitMapping(image, {{Attribute::Depth, {"id"}}});
    const Error e = expectError(ErrorKind::Input, [&] { extractGBuffer(image, mapping); });
    const std::string message = e.what();
    EXPECT_NE(message.find(dir.file("in.exr") + ": channel id:"), std::string::npos) << message;
    EXPECT_NE(message.find("wrong type"), std::string::npos) << message;
}

TEST(ExrIo, SubsampledChannelCannotBeMapped) {
    ScratchDir dir;
    writeFixture(dir.file("in.exr"), {mixedPart()});
    const ExrImage image = readExr(dir.file("in.exr"));
    const ChannelMapping mapping = explicitMapping(image, {{Attribute::Roughness, {"chroma"}}});
    const Error e = expectError(ErrorKind::Input, [&] { extractGBuffer(image, mapping); });
    EXPECT_NE(std::string(e.what()).find("channel chroma: subsampled"), std::string::npos) << e.what();
}

// A pass with another data window is resampled onto the depth pass's window (background where it
// has no data) and stored back into its own window.
TEST(ExrIo, PassesWithOtherDataWindowsAreResampledOntoTheDepthWindow) {
    ScratchDir dir;
    FixturePart a{makeHeader(16, 8, Imf::ZIP_COMPRESSION), {{"Z", Imf::FLOAT}}};
    a.header.setName("depth");
    FixturePart b{makeHeader(16, 8, Imf::ZIP_COMPRESSION), {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}};
    b.header.setName("albedo");
    b.header.dataWindow() = Imath::Box2i({4, 2}, {11, 9});  // reaches below the display window
    for (FixturePart* part : {&a, &b})
        for (FixtureChannel& c : part->channels) fillRandom(part->header.dataWindow(), c, 3);
    writeFixture(dir.file("in.exr"), {a, b});
    ExrImage image = readExr(dir.file("in.exr"));
    const ExrImage original = image;
    const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    ASSERT_TRUE(mapping.attributes.count(Attribute::Depth) && mapping.attributes.count(Attribute::Albedo));
    GBuffer gb = extractGBuffer(image, mapping);
    EXPECT_EQ(gb.width, 16);
    EXPECT_EQ(gb.height, 8);
    EXPECT_EQ(gb.origin_x, 0);
    const Plane& albedo = gb.planes.at(Attribute::Albedo);
    const ExrChannel& red = channelNamed(image.parts[1], "R");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            const std::size_t i = std::size_t(y) * 16 + x;
            const bool covered = x >= 4 && x <= 11 && y >= 2;
            const float expected = covered ? io::sampleAsFloat(red, std::size_t(y - 2) * 8 + (x - 4)) : 0.0f;
            if (std::isnan(expected)) EXPECT_TRUE(std::isnan(albedo.at(i, 0)));
            else EXPECT_EQ(albedo.at(i, 0), expected) << x << "," << y;
        }

    // Storing: every G-buffer pixel changes; the albedo rows below the G-buffer keep their bits.
    for (float& v : gb.planes.at(Attribute::Albedo).samples) v = 0.25f;
    storeAttribute(image, mapping, Attribute::Albedo, gb.planes.at(Attribute::Albedo));
    const ExrChannel& stored = channelNamed(image.parts[1], "R");
    const ExrChannel& before = channelNamed(original.parts[1], "R");
    for (int y = 2; y <= 9; ++y)
        for (int x = 4; x <= 11; ++x) {
            const std::size_t i = std::size_t(y - 2) * 8 + (x - 4);
            if (y <= 7) EXPECT_EQ(io::sampleAsFloat(stored, i), 0.25f);
            else EXPECT_EQ(std::memcmp(stored.bytes.data() + 2 * i, before.bytes.data() + 2 * i, 2), 0) << x << "," << y;
        }
}

}  // namespace
}  // namespace decalcomp
