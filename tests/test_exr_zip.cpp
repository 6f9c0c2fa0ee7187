// ZIP and ZIPS chunks through libdeflate. Deflated (src/io/exr_zip_encode.cpp): OpenEXR's reader
// gives back every sample of every pixel type, a chunk that would not shrink is stored raw exactly
// as OpenEXR stores it, the others are no bigger than OpenEXR's own, and parts the encoder cannot
// lay out stay with OpenEXR's writer. Inflated (src/io/exr_zip_decode.cpp): every sample OpenEXR
// wrote comes back, raw chunks included, a region reads only its chunks, and a corrupt chunk is
// refused naming the file, the part and the chunk's first line. Both spread their chunks over
// OpenEXR's pool (src/io/exr_pool.cpp): every chunk once, the first failure after all have ended.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/openexr.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <future>
#include <iterator>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_pool.hpp"
#include "io/exr_zip_decode.hpp"
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

std::string variantName(const testing::TestParamInfo<Variant>& param) {
    return std::string(std::get<0>(param.param) == Imf::ZIP_COMPRESSION ? "zip" : "zips") + "_threads" +
           std::to_string(std::get<1>(param.param));
}

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
                         variantName);


std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeFileBytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// Where the chunk starting at `first_line` of the file's first part lies: its stored bytes' offset and size.
exr_chunk_info_t chunkInfo(const std::string& path, int first_line) {
    exr_context_t context = nullptr;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    EXPECT_EQ(exr_start_read(&context, path.c_str(), &init), EXR_ERR_SUCCESS) << path;
    exr_chunk_info_t info{};
    EXPECT_EQ(exr_read_scanline_chunk_info(context, 0, first_line, &info), EXR_ERR_SUCCESS);
    exr_finish(&context);
    return info;
}

class ZipDecode : public ZipEncode {};

// Written by OpenEXR (zlib, its own predictor), read by ours: the noise lines' chunk is stored
// raw, the others deflated; the channels differ in type and the data window is off the origin.
TEST_P(ZipDecode, EverySampleOpenExrWroteComesBack) {
    const ExrImage written = threeTypeImage(compression());
    const std::string path = dir.file("in.exr");
    test::writeWithCompression(written, compression(), false, path);
    const ExrImage read = readExr(path);
    ASSERT_TRUE(io::canDecodeZip(read.parts.at(0)));
    for (const ExrChannel& channel : written.parts[0].channels)
        EXPECT_EQ(test::channel(read, channel.name).bytes, channel.bytes) << channel.name;
}

// Only the chunks a region overlaps are decoded; the others keep zero samples.
TEST_P(ZipDecode, ARegionReadsOnlyItsChunks) {
    const ExrImage written = threeTypeImage(compression());
    const std::string path = dir.file("in.exr");
    test::writeWithCompression(written, compression(), false, path);
    const int y0 = written.parts[0].header.dataWindow().min.y, x0 = written.parts[0].header.dataWindow().min.x;
    const int line = y0 + 20;  // the second ZIP chunk, lines y0+16 to y0+31
    ExrReadRegion region;
    region.everything = false;
    region.boxes.push_back(Imath::Box2i(Imath::V2i(x0 + 2, line), Imath::V2i(x0 + 4, line)));
    const ExrImage read = readExr(path, region);
    const ExrPart& part = read.parts.at(0);
    const int lines = compression() == Imf::ZIP_COMPRESSION ? 16 : 1;
    for (int y = 0; y < kHeight; ++y)
        EXPECT_EQ(part.isDecodedAt(x0, y0 + y), y / lines == (line - y0) / lines) << "line " << y;
    for (const ExrChannel& channel : written.parts[0].channels) {
        const ExrChannel& got = test::channel(read, channel.name);
        const std::size_t row = got.bytes.size() / kHeight;
        for (int y = 0; y < kHeight; ++y) {
            const auto begin = std::ptrdiff_t(row) * y, end = begin + std::ptrdiff_t(row);
            const bool decoded = part.isDecodedAt(x0, y0 + y);
            for (auto i = begin; i < end; ++i)
                ASSERT_EQ(got.bytes[std::size_t(i)], decoded ? channel.bytes[std::size_t(i)] : 0)
                    << channel.name << " line " << y;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(ZipAndZips, ZipDecode,
                         testing::Combine(testing::Values(Imf::ZIP_COMPRESSION, Imf::ZIPS_COMPRESSION),
                                          testing::Values(0, 3)),
                         variantName);

// A deflated chunk with bytes flipped inside its data, and one whose stored size claims more than
// its samples: each is refused with the file, the part and the chunk's first line.
TEST(ZipDecodeErrors, ACorruptChunkIsRefusedNamingTheFileAndTheChunk) {
    test::ScratchDir dir;
    const ExrImage written = threeTypeImage(Imf::ZIP_COMPRESSION);
    const std::string path = dir.file("in.exr");
    test::writeWithCompression(written, Imf::ZIP_COMPRESSION, false, path);
    const int second_chunk = written.parts[0].header.dataWindow().min.y + 16;  // deflated (not noise)
    const exr_chunk_info_t info = chunkInfo(path, second_chunk);
    ASSERT_LT(info.packed_size, info.unpacked_size);
    const std::string original = fileBytes(path);

    std::string flipped = original;
    for (std::size_t i = 2; i < std::size_t(info.packed_size); ++i)
        flipped[std::size_t(info.data_offset) + i] = char(~flipped[std::size_t(info.data_offset) + i]);
    writeFileBytes(path, flipped);
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { (void)readExr(path); });
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("chunk at line " + std::to_string(second_chunk)), std::string::npos) << message;

    std::string oversized = original;  // the chunk's size field precedes its data
    const std::uint32_t claimed = std::uint32_t(info.unpacked_size) + 4;
    std::memcpy(oversized.data() + info.data_offset - 4, &claimed, 4);
    writeFileBytes(path, oversized);
    const std::string refused = test::errorMessage(ErrorKind::Input, [&] { (void)readExr(path); });
    EXPECT_NE(refused.find(path), std::string::npos) << refused;
    EXPECT_NE(refused.find(std::to_string(second_chunk)), std::string::npos) << refused;
}

// Both directions take the same parts; everything else stays with OpenEXR's codecs.
TEST(ZipScope, OtherCodecsTilesAndSubsampledChannelsStayWithOpenExr) {
    const auto ours = [](const ExrImage& image) {
        const bool encoded = io::canEncodeZip(image.parts[0]), decoded = io::canDecodeZip(image.parts[0]);
        EXPECT_EQ(encoded, decoded);
        return encoded && decoded;
    };
    const ExrImage zip = threeTypeImage(Imf::ZIP_COMPRESSION);
    EXPECT_TRUE(ours(zip));
    EXPECT_TRUE(ours(threeTypeImage(Imf::ZIPS_COMPRESSION)));
    EXPECT_FALSE(ours(threeTypeImage(Imf::PIZ_COMPRESSION)));

    ExrImage tiled = zip;
    tiled.parts[0].chunks.tiled = true;
    EXPECT_FALSE(ours(tiled));

    ExrImage subsampled = zip;
    subsampled.parts[0].channels[1].x_sampling = 2;
    EXPECT_FALSE(ours(subsampled));
    subsampled.parts[0].channels[1].x_sampling = 1;
    subsampled.parts[0].channels[2].y_sampling = 2;
    EXPECT_FALSE(ours(subsampled));

    ExrImage missing = zip;  // a header channel the part does not hold
    missing.parts[0].channels.pop_back();
    EXPECT_FALSE(ours(missing));
}

// With no pool threads (calls inline), one, and several: each index runs exactly once, and a
// failure is rethrown only after every call has ended, the others having run.
TEST(ExrPool, RunsEveryIndexOnceAndRethrowsAFailureAfterAllHaveRun) {
    for (int threads : {0, 1, 4}) {
        SCOPED_TRACE(threads);
        Imf::setGlobalThreadCount(threads);
        constexpr std::size_t kCalls = 200;
        std::vector<std::atomic<int>> runs(kCalls);
        io::runOnExrPool(io::PoolWork::Decode, kCalls, [&](std::size_t i) { ++runs[i]; });
        EXPECT_TRUE(std::all_of(runs.begin(), runs.end(), [](const std::atomic<int>& r) { return r == 1; }));

        std::vector<std::atomic<int>> again(kCalls);
        try {
            io::runOnExrPool(io::PoolWork::Encode, kCalls, [&](std::size_t i) {
                ++again[i];
                if (i == 17 || i == 150) throw std::runtime_error("call " + std::to_string(i));
            });
            ADD_FAILURE() << "no failure rethrown";
        } catch (const std::runtime_error& e) {
            EXPECT_TRUE(std::string(e.what()) == "call 17" || std::string(e.what()) == "call 150") << e.what();
        }
        EXPECT_TRUE(std::all_of(again.begin(), again.end(), [](const std::atomic<int>& r) { return r == 1; }));
    }
    Imf::setGlobalThreadCount(0);
}

// A caller whose indices the pool's threads cannot take (each is busy with another call's) runs
// them itself instead of waiting.
TEST(ExrPool, ACallerProgressesWhileEveryPoolThreadIsBusy) {
    Imf::setGlobalThreadCount(2);
    std::mutex mutex;
    std::condition_variable changed;
    int blocked = 0;
    bool release = false;
    // Another call holds both pool threads (and its own caller) until released.
    std::thread other([&] {
        io::runOnExrPool(io::PoolWork::Decode, 3, [&](std::size_t) {
            std::unique_lock lock(mutex);
            ++blocked;
            changed.notify_all();
            changed.wait(lock, [&] { return release; });
        });
    });
    {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return blocked == 3; });
    }
    std::atomic<int> ran{0}, on_caller{0};
    auto call = std::async(std::launch::async, [&] {
        const std::thread::id self = std::this_thread::get_id();
        io::runOnExrPool(io::PoolWork::Decode, 50, [&](std::size_t) {
            ++ran;
            on_caller += std::this_thread::get_id() == self;
        });
    });
    const bool finished = call.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
    EXPECT_TRUE(finished) << "the call waited for the busy pool";
    if (finished) {
        EXPECT_EQ(on_caller.load(), 50) << "every index ran on the calling thread";
    }
    {
        const std::lock_guard lock(mutex);
        release = true;
    }
    changed.notify_all();
    other.join();
    call.get();
    EXPECT_EQ(ran.load(), 50);
    Imf::setGlobalThreadCount(0);
}

// The pool's thread takes a decode call's indices before those of an encode call that came first
// (in a batch, the reader's frame before the workers' encodes).
TEST(ExrPool, DecodingGoesBeforeEncoding) {
    Imf::setGlobalThreadCount(1);
    std::mutex mutex;
    std::vector<char> pool_order;  // 'e' or 'd' per index the pool's thread ran after the decode began
    std::atomic<bool> decoding{false};
    std::thread encode([&] {
        const std::thread::id self = std::this_thread::get_id();
        io::runOnExrPool(io::PoolWork::Encode, 40, [&](std::size_t) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            if (std::this_thread::get_id() != self && decoding) {
                const std::lock_guard lock(mutex);
                pool_order.push_back('e');
            }
        });
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(35));  // the pool's thread is on the encode
    std::thread decode([&] {
        const std::thread::id self = std::this_thread::get_id();
        decoding = true;
        io::runOnExrPool(io::PoolWork::Decode, 20, [&](std::size_t) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            if (std::this_thread::get_id() != self) {
                const std::lock_guard lock(mutex);
                pool_order.push_back('d');
            }
        });
    });
    decode.join();
    encode.join();
    // At most the encode index it was running when the decode came ('e' first), then decoding.
    ASSERT_GE(pool_order.size(), 3u);
    const std::size_t first_decode =
        std::size_t(std::find(pool_order.begin(), pool_order.end(), 'd') - pool_order.begin());
    EXPECT_LE(first_decode, 1u) << std::string(pool_order.begin(), pool_order.end());
    const auto decodes = std::count(pool_order.begin(), pool_order.end(), 'd');
    EXPECT_GE(decodes, 5) << std::string(pool_order.begin(), pool_order.end());
    EXPECT_TRUE(std::all_of(pool_order.begin() + std::ptrdiff_t(first_decode),
                            pool_order.begin() + std::ptrdiff_t(first_decode) + decodes,
                            [](char c) { return c == 'd'; }))
        << std::string(pool_order.begin(), pool_order.end());
    Imf::setGlobalThreadCount(0);
}

// codecCpuSeconds counts the CPU the calls took, by kind, whichever thread ran them.
TEST(ExrPool, CountsTheCallsCpuTimeByKind) {
    Imf::setGlobalThreadCount(2);
    const CodecCpu before = codecCpuSeconds();
    const auto spin = [](std::size_t) {  // 30 ms of CPU each
        timespec start{}, now{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &start);
        do clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
        while ((now.tv_sec - start.tv_sec) * 1e3 + (now.tv_nsec - start.tv_nsec) * 1e-6 < 30.0);
    };
    io::runOnExrPool(io::PoolWork::Encode, 4, spin);
    const CodecCpu after = codecCpuSeconds();
    EXPECT_GE(after.encode_s - before.encode_s, 0.119);
    EXPECT_LT(after.encode_s - before.encode_s, 1.0);
    EXPECT_EQ(after.decode_s, before.decode_s);
    io::runOnExrPool(io::PoolWork::Decode, 2, spin);
    EXPECT_GE(codecCpuSeconds().decode_s - after.decode_s, 0.059);
    Imf::setGlobalThreadCount(0);
}

}  // namespace
}  // namespace decalcomp
