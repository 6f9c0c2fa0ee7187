// decalcomp-bench-zip: what the EXR codec would cost through libdeflate instead of zlib. Reads a
// scanline EXR's pixels, lays each 16-line chunk out as ZIP compression does (the channels' rows,
// the bytes split into even and odd halves, then each byte as its difference to the previous one,
// OpenEXR's file-format document), and times compressing and decompressing every chunk with zlib
// (what OpenEXR 3.1 uses) and with libdeflate, each at several levels, checking the round trip.
// A measurement for docs/benchmarks.md (stop 44), not part of the product; build it with
// `cmake --build build --target decalcomp-bench-zip` where libdeflate-dev is installed.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <fmt/format.h>
#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace {

using Bytes = std::vector<unsigned char>;
constexpr int kZipLines = 16;  // scanlines per ZIP chunk

// Every chunk of the file's pixels, as ZIP lays it out before deflate.
std::vector<Bytes> zipChunks(const char* path) {
    Imf::InputFile in(path);
    const Imath::Box2i window = in.header().dataWindow();
    const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
    struct Plane {
        std::string name;
        int size;  // bytes per sample
        Bytes samples;
    };
    std::vector<Plane> planes;
    Imf::FrameBuffer frame_buffer;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
        const int size = it.channel().type == Imf::HALF ? 2 : 4;
        planes.push_back({it.name(), size, Bytes(std::size_t(width) * height * std::size_t(size))});
    }
    for (Plane& plane : planes) {
        const Imf::PixelType type = in.header().channels().findChannel(plane.name)->type;
        char* origin = reinterpret_cast<char*>(plane.samples.data()) -
                       (std::ptrdiff_t(window.min.y) * width + window.min.x) * plane.size;
        frame_buffer.insert(plane.name, Imf::Slice(type, origin, std::size_t(plane.size),
                                                   std::size_t(plane.size) * std::size_t(width)));
    }
    in.setFrameBuffer(frame_buffer);
    in.readPixels(window.min.y, window.max.y);

    std::vector<Bytes> chunks;
    for (int y0 = 0; y0 < height; y0 += kZipLines) {
        Bytes rows;
        for (int y = y0; y < std::min(height, y0 + kZipLines); ++y)
            for (const Plane& plane : planes) {
                const auto row = plane.samples.begin() + std::ptrdiff_t(y) * width * plane.size;
                rows.insert(rows.end(), row, row + std::ptrdiff_t(width) * plane.size);
            }
        Bytes split(rows.size());
        const std::size_t half = (rows.size() + 1) / 2;
        for (std::size_t i = 0; i < rows.size(); ++i) split[i % 2 == 0 ? i / 2 : half + i / 2] = rows[i];
        for (std::size_t i = split.size() - 1; i > 0; --i)
            split[i] = static_cast<unsigned char>(split[i] - split[i - 1] + 128);
        chunks.push_back(std::move(split));
    }
    return chunks;
}

using Compress = std::function<Bytes(const Bytes&)>;
using Decompress = std::function<bool(const Bytes&, Bytes&)>;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void timeCodec(const std::string& name, const std::vector<Bytes>& chunks, const Compress& compress,
               const Decompress& decompress) {
    std::size_t raw = 0, packed = 0;
    std::vector<Bytes> out;
    auto start = std::chrono::steady_clock::now();
    for (const Bytes& chunk : chunks) {
        out.push_back(compress(chunk));
        raw += chunk.size();
        packed += out.back().size();
    }
    const double encode_ms = millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    Bytes back;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        back.assign(chunks[i].size(), 0);
        if (!decompress(out[i], back) || back != chunks[i]) {
            fmt::print("{}: chunk {} does not round-trip\n", name, i);
            return;
        }
    }
    const double decode_ms = millisecondsSince(start);
    fmt::print("{:<14} encode {:8.1f} ms  decode {:7.1f} ms  {:.1f} MB -> {:.1f} MB\n", name, encode_ms, decode_ms,
               double(raw) / 1e6, double(packed) / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        fmt::print(stderr, "usage: decalcomp-bench-zip FILE.exr [LEVEL ...] (levels: 6 4 1)\n");
        return 2;
    }
    std::vector<int> levels;
    for (int i = 2; i < argc; ++i) levels.push_back(std::stoi(argv[i]));
    if (levels.empty()) levels = {6, 4, 1};
    const std::vector<Bytes> chunks = zipChunks(argv[1]);
    for (int level : levels) {
        timeCodec(
            fmt::format("zlib-{}", level), chunks,
            [&](const Bytes& in) {
                uLongf size = compressBound(uLong(in.size()));
                Bytes out(size);
                compress2(out.data(), &size, in.data(), uLong(in.size()), level);
                out.resize(size);
                return out;
            },
            [](const Bytes& in, Bytes& out) {
                uLongf size = uLongf(out.size());
                return uncompress(out.data(), &size, in.data(), uLong(in.size())) == Z_OK && size == out.size();
            });
        libdeflate_compressor* compressor = libdeflate_alloc_compressor(level);
        libdeflate_decompressor* decompressor = libdeflate_alloc_decompressor();
        timeCodec(
            fmt::format("libdeflate-{}", level), chunks,
            [&](const Bytes& in) {
                Bytes out(libdeflate_zlib_compress_bound(compressor, in.size()));
                out.resize(libdeflate_zlib_compress(compressor, in.data(), in.size(), out.data(), out.size()));
                return out;
            },
            [&](const Bytes& in, Bytes& out) {
                return libdeflate_zlib_decompress(decompressor, in.data(), in.size(), out.data(), out.size(),
                                                  nullptr) == LIBDEFLATE_SUCCESS;
            });
        libdeflate_free_compressor(compressor);
        libdeflate_free_decompressor(decompressor);
    }
    return 0;
}
