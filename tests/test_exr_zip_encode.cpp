// ZIP and ZIPS chunks deflated by libdeflate (src/io/exr_zip_encode.cpp): OpenEXR's reader gives
// back every sample of every pixel type, a chunk that would not shrink is stored raw exactly as
// OpenEXR stores it, the others are no bigger than OpenEXR's own, and parts the encoder cannot lay
// out stay with OpenEXR's writer.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfThreading.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_zip_encode.hpp"
#include "support/exr_test_io.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

constexpr int kWidth = 37, kHeight = 40;  // ZIP: chunks of 16, 16 and 8 lines
constexpr int kNoiseLines = 16;           // the first lines hold random bytes: they do not shrink

// A half, a float and a uint channel (bytes per pixel: 2 + 4 + 4) over kWidth x kHeight: random
// bytes on the first kNoiseLines lines, then a constant, then a ramp.
ExrImage threeTypeImage(Imf::Compression compression) {
    ExrImage image;
    ExrPart& part = image.parts.emplace_back();
    // a data window away from the origin, as crops and overscan have
    const Imath::V2i origin(-3, 5);
    const Imath::Box2i window(origin, origin + Imath::V2i(kWidth - 1, kHeight - 1));
    part.header = Imf::Header(window, window);
    part.header.compression() = compression;
    part.width = kWidth, part.height = kHeight;
    std::mt19937 random(7);
    for (auto [name, type] : {std::pair{"A", SampleType::Half}, {"B", SampleType::Float}, {"C", SampleType::Uint}}) {
        ExrChannel channel;
        channel.name = channel.qualified = name;
        channel.type = type;
        const std::size_t size = io::sampleSize(type), row = size * kWidth;
        channel.bytes.resize(row * kHeight);
        for (int y = 0; y < kHeight; ++y)
            for (std::size_t b = 0; b < row; ++b)
                channel.bytes[std::size_t(y) * row + b] =
                    y < kNoiseLines ? static_cast<unsigned char>(random())
                    : y < 32        ? 0x3c
                                    : static_cast<unsigned char>((b / size + std::size_t(y)) % 7);
        part.header.channels().insert(name, Imf::Channel(io::pixelType(type)));
        part.channels.push_back(std::move(channel));
    }
    return image;
}

// The compression, and the threads of OpenEXR's pool (0: the chunks are deflated on the caller).
using Variant = std::tuple<Imf::Compression, int>;

class ZipEncode : public testing::TestWithParam<Variant> {
protected:
    void SetUp() override { Imf::setGlobalThreadCount(std::get<1>(GetParam())); }
    void TearDown() override { Imf::setGlobalThreadCount(0); }
    Imf::Compression compression() const { return std::get<0>(GetParam()); }
    test::ScratchDir dir;
};

// The input is written whole by OpenEXR; every chunk is then marked changed and written again
// through the chunk writer, so each is deflated here. The part's channels are held in the reverse
// of the header's order: a chunk lays them out in the header's.
TEST_P(ZipEncode, EveryChunkDecodesByOpenExrAndIsNoBiggerThanItsOwn) {
    const std::string input = dir.file("in.exr"), output = dir.file("out.exr");
    test::writeWithCompression(threeTypeImage(compression()), compression(), false, input);
    ExrImage image = readExr(input);
    ASSERT_TRUE(io::canEncodeZip(image.parts.at(0)));
    std::reverse(image.parts[0].channels.begin(), image.parts[0].channels.end());
    image.copy_unchanged_chunks = true;
    const int y0 = image.parts[0].header.dataWindow().min.y;
    for (int y = y0; y < y0 + kHeight; ++y) image.parts[0].markChanged(-3, y);
    writeExrAtomic(image, output);

    const ExrImage back = readExr(output);
    ASSERT_EQ(back.parts.at(0).channels.size(), 3u);
    for (const ExrChannel& written : image.parts[0].channels) {
        EXPECT_EQ(test::channel(back, written.name).bytes, written.bytes) << written.name;
    }
    const auto theirs = test::rawChunks(input)[0], ours = test::rawChunks(output)[0];
    ASSERT_EQ(ours.size(), theirs.size());
    const int lines = compression() == Imf::ZIP_COMPRESSION ? 16 : 1;
    for (std::size_t k = 0; k < ours.size(); ++k) {
        const int first_line = int(k) * lines;
        const std::size_t raw = std::size_t(std::min(lines, kHeight - first_line)) * kWidth * (2 + 4 + 4);
        if (first_line < kNoiseLines) {  // random bytes: stored raw, as OpenEXR stores them
            EXPECT_EQ(ours[k].size(), raw) << "chunk " << k;
            EXPECT_EQ(ours[k], theirs[k]) << "chunk " << k;
        } else {
            EXPECT_LT(ours[k].size(), raw) << "chunk " << k;
            EXPECT_LE(ours[k].size(), theirs[k].size() + theirs[k].size() / 20 + 16) << "chunk " << k;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(ZipAndZips, ZipEncode,
                         testing::Combine(testing::Values(Imf::ZIP_COMPRESSION, Imf::ZIPS_COMPRESSION),
                                          testing::Values(0, 3)),
                         [](const testing::TestParamInfo<Variant>& param) {
                             return std::string(std::get<0>(param.param) == Imf::ZIP_COMPRESSION ? "zip" : "zips") +
                                    "_threads" + std::to_string(std::get<1>(param.param));
                         });

TEST(ZipEncodeScope, OtherCodecsTilesAndSubsampledChannelsStayWithOpenExr) {
    ExrImage zip = threeTypeImage(Imf::ZIP_COMPRESSION);
    EXPECT_TRUE(io::canEncodeZip(zip.parts[0]));

    ExrImage piz = threeTypeImage(Imf::PIZ_COMPRESSION);
    EXPECT_FALSE(io::canEncodeZip(piz.parts[0]));

    ExrImage tiled = zip;
    tiled.parts[0].chunks.tiled = true;
    EXPECT_FALSE(io::canEncodeZip(tiled.parts[0]));

    ExrImage subsampled = zip;
    subsampled.parts[0].channels[1].x_sampling = 2;
    EXPECT_FALSE(io::canEncodeZip(subsampled.parts[0]));

    ExrImage missing = zip;  // a header channel the part does not hold
    missing.parts[0].channels.pop_back();
    EXPECT_FALSE(io::canEncodeZip(missing.parts[0]));
}

}  // namespace
}  // namespace decalcomp
