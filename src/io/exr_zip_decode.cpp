// ZIP chunks through libdeflate: the inverse of exr_zip_encode.cpp, so that reading a frame, the
// other half of the codec's cost, runs at libdeflate's speed too.
#include "io/exr_zip_decode.hpp"

#include <fmt/format.h>
#include <libdeflate.h>

#include <bit>
#include <cstring>
#include <memory>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "decalcomp/error.hpp"
#include "io/exr_core.hpp"
#include "io/exr_pool.hpp"
#include "io/exr_zip_layout.hpp"

namespace decalcomp::io {

namespace {

static_assert(std::endian::native == std::endian::little, "exr_zip_decode.cpp lays out samples little-endian");

struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// One decompressor per thread (null when it cannot be allocated; tried again on the next chunk).
libdeflate_decompressor* threadDecompressor() {
    thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor;
    if (!decompressor) decompressor.reset(libdeflate_alloc_decompressor());
    return decompressor.get();
}

// Undoes ZIP's predictor in place: each byte becomes the one before plus its stored value minus
// 128 (the first is stored as it is). A running sum, 16 bytes at a time: within a vector by
// shifted adds, across vectors by the last byte carried.
void undoDelta(unsigned char* bytes, std::size_t size) {
    if (size == 0) return;
    unsigned char last = bytes[0];
    std::size_t i = 1;
#ifdef __SSE2__
    const __m128i bias = _mm_set1_epi8(char(128));
    for (; i + 16 <= size; i += 16) {
        __m128i v = _mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i)), bias);
        v = _mm_add_epi8(v, _mm_slli_si128(v, 1));
        v = _mm_add_epi8(v, _mm_slli_si128(v, 2));
        v = _mm_add_epi8(v, _mm_slli_si128(v, 4));
        v = _mm_add_epi8(v, _mm_slli_si128(v, 8));
        v = _mm_add_epi8(v, _mm_set1_epi8(char(last)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(bytes + i), v);
        last = static_cast<unsigned char>(_mm_extract_epi16(v, 7) >> 8);
    }
#endif
    for (; i < size; ++i) bytes[i] = last = static_cast<unsigned char>(last + bytes[i] - 128);
}

// A row of `bytes` (even) back from its halves: its even bytes from `even`, its odd ones from `odd`.
void interleave(const unsigned char* even, const unsigned char* odd, std::size_t bytes, unsigned char* row) {
    std::size_t i = 0;
#ifdef __SSE2__
    for (; i + 32 <= bytes; i += 32) {
        const __m128i e = _mm_loadu_si128(reinterpret_cast<const __m128i*>(even + i / 2));
        const __m128i o = _mm_loadu_si128(reinterpret_cast<const __m128i*>(odd + i / 2));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(row + i), _mm_unpacklo_epi8(e, o));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(row + i + 16), _mm_unpackhi_epi8(e, o));
    }
#endif
    for (; i < bytes; i += 2) {
        row[i] = even[i / 2];
        row[i + 1] = odd[i / 2];
    }
}

// One chunk to decode: where its stored bytes lie (read from the chunk table up front, on the
// calling thread) and the pixels they hold.
struct ChunkJob {
    exr_chunk_info_t info;
    Imath::Box2i box;
};

class ChunkDecoder {
public:
    ChunkDecoder(const CoreContext& file, int index, ExrPart& part, std::vector<ExrChannel*> channels)
        : file_(file), index_(index), part_(part), channels_(std::move(channels)) {}

    void decode(const ChunkJob& job) const {
        thread_local std::vector<unsigned char> packed, predicted;
        const std::size_t size = zipChunkBytes(part_, channels_, job.box);
        if (job.info.packed_size > size)
            fail(job, fmt::format("{} stored bytes for {} bytes of samples; the file is corrupt", job.info.packed_size,
                                  size));
        packed.resize(std::size_t(job.info.packed_size));
        file_.require(exr_read_chunk(file_.context(), index_, &job.info, packed.data()), index_,
                      fmt::format("chunk at line {}", job.box.min.y));
        if (job.info.packed_size == size) {  // stored raw: the rows as they are
            std::size_t offset = 0;
            forEachZipRow(part_, channels_, job.box, [&](unsigned char* row, std::size_t bytes) {
                std::memcpy(row, packed.data() + offset, bytes);
                offset += bytes;
            });
            return;
        }
        libdeflate_decompressor* decompressor = threadDecompressor();
        if (!decompressor) throw std::bad_alloc();
        predicted.resize(size);
        // Exactly `size` bytes, or the chunk is refused (libdeflate checks the zlib checksum too).
        const libdeflate_result result =
            libdeflate_zlib_decompress(decompressor, packed.data(), packed.size(), predicted.data(), size, nullptr);
        if (result != LIBDEFLATE_SUCCESS)
            fail(job, result == LIBDEFLATE_BAD_DATA ? std::string("corrupt ZIP data")
                                                    : fmt::format("does not inflate to its {} bytes of samples", size));
        undoDelta(predicted.data(), size);
        const unsigned char* even = predicted.data();
        const unsigned char* odd = predicted.data() + size / 2;
        forEachZipRow(part_, channels_, job.box, [&](unsigned char* row, std::size_t bytes) {
            interleave(even, odd, bytes, row);
            even += bytes / 2;
            odd += bytes / 2;
        });
    }

private:
    [[noreturn]] void fail(const ChunkJob& job, const std::string& reason) const {
        throw inputError(fmt::format("{}: part {}: chunk at line {}: {}", file_.path(), index_, job.box.min.y, reason));
    }

    const CoreContext& file_;
    int index_;
    ExrPart& part_;
    std::vector<ExrChannel*> channels_;
};

}  // namespace

bool canDecodeZip(const ExrPart& part) { return !zipChannels(part).empty(); }

void decodeZipChunks(const std::string& path, int index, ExrPart& part) {
    std::vector<ExrChannel*> channels;
    for (const ExrChannel* channel : zipChannels(part))
        channels.push_back(&part.channels[std::size_t(channel - part.channels.data())]);
    const CoreContext file(path, CoreContext::Mode::ReadAsStored);
    std::vector<ChunkJob> jobs;
    for (int chunk = 0; chunk < part.chunks.count(); ++chunk) {
        if (!part.isDecoded(chunk)) continue;
        ChunkJob& job = jobs.emplace_back();
        job.box = part.chunks.box(chunk);
        file.require(exr_read_scanline_chunk_info(file.context(), index, job.box.min.y, &job.info), index,
                     fmt::format("chunk table at line {}", job.box.min.y));
        if (job.info.start_y != job.box.min.y || job.info.height != job.box.max.y - job.box.min.y + 1)
            throw inputError(
                fmt::format("{}: part {}: chunk table at line {}: the chunk holds lines {}-{}; the file "
                            "is corrupt",
                            path, index, job.box.min.y, job.info.start_y, job.info.start_y + job.info.height - 1));
    }
    const ChunkDecoder decoder(file, index, part, std::move(channels));
    runOnExrPool(PoolWork::Decode, jobs.size(), [&](std::size_t j) { decoder.decode(jobs[j]); });
}

}  // namespace decalcomp::io
