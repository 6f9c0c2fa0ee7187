// Hostile sizes fail before allocation: EXR data windows and chunk tables checked against the
// file, textures against their file size, everything against the memory limit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/memory_limit.hpp"
#include "decalcomp/textures.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;

void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// The sample EXR with its dataWindow attribute replaced (the box2i follows name, type and size).
std::string withDataWindow(const std::string& exr, int x0, int y0, int x1, int y1) {
    const std::string key("dataWindow\0box2i\0", 17);
    std::string bytes = exr;
    const std::size_t at = bytes.find(key);
    EXPECT_NE(at, std::string::npos);
    const int box[4] = {x0, y0, x1, y1};
    std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);
    return bytes;
}

// Sets an environment variable for one scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
    ~ScopedEnv() { ::unsetenv(name_); }

private:
    const char* name_;
};

struct Fixture {
    test::ScratchDir dir;
    std::string sample = test::readFileBytes(test::dataPath("sample/gbuffer.exr"));
    std::string write(const std::string& name, const std::string& bytes) const {
        writeBytes(dir.file(name), bytes);
        return dir.file(name);
    }
};

TEST(InputLimits, WindowLargerThanTheFileHoldsIsRefusedAtTheChunkTable) {
    Fixture f;
    const std::string path = f.write("big.exr", withDataWindow(f.sample, 0, 0, 5999, 5999));
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { readExr(path); });
    EXPECT_TRUE(message.starts_with(path + ": part 0: dataWindow (0,0)-(5999,5999) with 14 channels: chunk "))
        << message;
    EXPECT_NE(message.find("claims more pixels than it holds"), std::string::npos) << message;
}

TEST(InputLimits, WindowBeyondTheMemoryLimitIsRefusedWithTheVariableToRaise) {
    Fixture f;
    const std::string path = f.write("huge.exr", withDataWindow(f.sample, 0, 0, 99999, 99999));
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { readExr(path); });
    EXPECT_TRUE(message.starts_with(path + ": part 0: dataWindow 100000x100000: decodes to ")) << message;
    EXPECT_NE(message.find("DECALCOMP_MAX_MEMORY"), std::string::npos) << message;
}

TEST(InputLimits, OverflowingAndInvertedWindowsAreRefused) {
    Fixture f;
    for (const auto& [x0, x1] : {std::pair{INT32_MIN, INT32_MAX}, std::pair{10, 5}}) {
        const std::string path = f.write("bad.exr", withDataWindow(f.sample, x0, 0, x1, 359));
        const std::string message = test::errorMessage(ErrorKind::Input, [&] { readExr(path); });
        EXPECT_TRUE(message.starts_with(path + ": ")) << message;
        EXPECT_NE(message.find("ata window"), std::string::npos) << message;  // "dataWindow" or "data window"
    }
}

TEST(InputLimits, MemoryLimitIsOverridable) {
    Fixture f;
    const std::string path = f.write("ok.exr", f.sample);
    {
        ScopedEnv limit("DECALCOMP_MAX_MEMORY", "1M");  // the sample decodes to 12.3 MiB
        const std::string message = test::errorMessage(ErrorKind::Input, [&] { readExr(path); });
        EXPECT_NE(message.find("more than the memory limit of 1 MiB"), std::string::npos) << message;
    }
    {
        ScopedEnv limit("DECALCOMP_MAX_MEMORY", "64M");
        EXPECT_EQ(readExr(path).parts.size(), 1u);
    }
    ScopedEnv limit("DECALCOMP_MAX_MEMORY", "lots");
    const std::string message = test::errorMessage(ErrorKind::Usage, [&] { readExr(path); });
    EXPECT_NE(message.find("DECALCOMP_MAX_MEMORY=lots: not a size"), std::string::npos) << message;
}

TEST(InputLimits, ByteSizesParse) {
    EXPECT_EQ(parseByteSize("1073741824"), std::uint64_t(1) << 30);
    EXPECT_EQ(parseByteSize("8G"), std::uint64_t(8) << 30);
    EXPECT_EQ(parseByteSize("512m"), std::uint64_t(512) << 20);
    EXPECT_EQ(parseByteSize("2T"), std::uint64_t(2) << 40);
    for (const char* bad : {"", "G", "-1", "1.5G", "8GB", "0", "99999999999999999999", "20000000000T"})
        EXPECT_FALSE(parseByteSize(bad).has_value()) << bad;
    EXPECT_FALSE(checkedProduct(std::uint64_t(1) << 40, std::uint64_t(1) << 30).has_value());
    EXPECT_EQ(readableBytes(1536), "1.5 KiB");
    EXPECT_EQ(readableBytes(7), "7 bytes");
}

TEST(InputLimits, TruncatedChunksAreRefusedBeforeDecoding) {
    Fixture f;
    const std::string path = f.write("cut.exr", f.sample.substr(0, f.sample.size() / 2));
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { readExr(path); });
    EXPECT_TRUE(message.starts_with(path + ": part 0: dataWindow (0,0)-(639,359) with 14 channels: chunk "))
        << message;
}

TEST(InputLimits, EveryShippedFileIsPlausible) {
    for (const auto& entry : fs::recursive_directory_iterator(test::dataPath(""))) {
        if (entry.path().extension() != ".exr") continue;
        EXPECT_NO_THROW(readExr(entry.path().string())) << entry.path();
    }
}

// A PNG whose IHDR claims 60000 x 60000 texels in a file of a few hundred bytes.
TEST(InputLimits, TextureHeaderClaimingMoreThanTheFileHoldsIsRefused) {
    Fixture f;
    std::string png = test::readFileBytes(test::dataPath("blender/decal_letter.png"));
    const std::size_t ihdr = png.find("IHDR");
    ASSERT_NE(ihdr, std::string::npos);
    const unsigned char size[8] = {0, 0, 0xEA, 0x60, 0, 0, 0xEA, 0x60};  // big-endian 60000, 60000
    std::memcpy(&png[ihdr + 4], size, sizeof size);
    // The chunk's CRC covers type and data; recompute it so only the size is wrong.
    std::uint32_t crc = 0xFFFFFFFFu;
    for (std::size_t i = ihdr; i < ihdr + 4 + 13; ++i) {
        crc ^= static_cast<unsigned char>(png[i]);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    crc ^= 0xFFFFFFFFu;
    const unsigned char crc_bytes[4] = {static_cast<unsigned char>(crc >> 24), static_cast<unsigned char>(crc >> 16),
                                        static_cast<unsigned char>(crc >> 8), static_cast<unsigned char>(crc)};
    std::memcpy(&png[ihdr + 4 + 13], crc_bytes, sizeof crc_bytes);
    const std::string path = f.write("huge.png", png);
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { loadTexture2D(path); });
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("60000x60000"), std::string::npos) << message;
}

}  // namespace
}  // namespace decalcomp
