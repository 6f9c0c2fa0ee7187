// ZIP chunks through libdeflate: the layout OpenEXR's file format gives ZIP compression, written
// here so that the deflating, the codec's cost in every frame, runs at libdeflate's speed.
#include "io/exr_zip_encode.hpp"

#include <fmt/format.h>
#include <libdeflate.h>

#include <bit>
#include <cstring>
#include <memory>
#include <new>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "decalcomp/error.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_pool.hpp"
#include "io/exr_zip_layout.hpp"

namespace decalcomp::io {

namespace {

// OpenEXR 3.1.5 deflates at zlib's level 4, and so does this encoder, at libdeflate's. Level 6
// packed render passes 0.5-1 % tighter, but took 20-25 % longer on composited frames, whose
// decal textures compress worse (decalcomp-bench-zip, docs/benchmarks.md, stop 48).
constexpr int kDeflateLevel = 4;

struct CompressorDeleter {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

// The samples are copied as they lie in memory, and EXR stores them little-endian.
static_assert(std::endian::native == std::endian::little, "exr_zip_encode.cpp lays out samples little-endian");

// One compressor per thread: allocating one costs more than deflating a small chunk. Null when it
// cannot be allocated (tried again on the next chunk).
libdeflate_compressor* threadCompressor() {
    thread_local std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor;
    if (!compressor) compressor.reset(libdeflate_alloc_compressor(kDeflateLevel));
    return compressor.get();
}

// ZIP's predictor in one pass over a row of `bytes` (even): its even bytes to `even`, its odd ones
// to `odd`, each stored as its difference to the byte before it in its half plus 128. `prev_even`
// and `prev_odd` carry the last byte of each half from row to row. (A split and then a delta pass
// over the whole chunk, byte by byte, cost a third of the chunk's deflating.)
void splitAndDelta(const unsigned char* row, std::size_t bytes, unsigned char* even, unsigned char* odd,
                   unsigned char& prev_even, unsigned char& prev_odd) {
    std::size_t i = 0;
#ifdef __SSE2__
    const __m128i low_bytes = _mm_set1_epi16(0x00ff);
    const __m128i bias = _mm_set1_epi8(char(128));
    __m128i last_even = _mm_set1_epi8(char(prev_even)), last_odd = _mm_set1_epi8(char(prev_odd));
    for (; i + 32 <= bytes; i += 32) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i + 16));
        const __m128i e = _mm_packus_epi16(_mm_and_si128(a, low_bytes), _mm_and_si128(b, low_bytes));
        const __m128i o = _mm_packus_epi16(_mm_srli_epi16(a, 8), _mm_srli_epi16(b, 8));
        // each byte's predecessor: the vector shifted up one byte, the previous vector's last byte in
        const __m128i e_before = _mm_or_si128(_mm_slli_si128(e, 1), _mm_srli_si128(last_even, 15));
        const __m128i o_before = _mm_or_si128(_mm_slli_si128(o, 1), _mm_srli_si128(last_odd, 15));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(even + i / 2), _mm_add_epi8(_mm_sub_epi8(e, e_before), bias));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(odd + i / 2), _mm_add_epi8(_mm_sub_epi8(o, o_before), bias));
        last_even = e;
        last_odd = o;
    }
    prev_even = static_cast<unsigned char>(_mm_extract_epi16(last_even, 7) >> 8);
    prev_odd = static_cast<unsigned char>(_mm_extract_epi16(last_odd, 7) >> 8);
#endif
    for (; i < bytes; i += 2) {
        even[i / 2] = static_cast<unsigned char>(row[i] - prev_even + 128);
        odd[i / 2] = static_cast<unsigned char>(row[i + 1] - prev_odd + 128);
        prev_even = row[i];
        prev_odd = row[i + 1];
    }
}

// Chunk `chunk`'s stored bytes (see encodeZipChunks). The predicted bytes and their deflated form
// go through buffers each thread keeps, so a frame's chunks allocate only what they return:
// per-chunk buffers on the pool's threads grew each thread's heap by megabytes (batch --io-only's
// peak memory).
std::string encodeChunk(const ExrPart& part, const std::vector<const ExrChannel*>& channels, int chunk) {
    thread_local std::vector<unsigned char> predicted, packed;
    const Imath::Box2i box = part.chunks.box(chunk);
    const std::size_t total = zipChunkBytes(part, channels, box);
    predicted.resize(total);
    // The even half's first byte has no predecessor and is stored as it is (prev 128 leaves it);
    // the odd half's first byte follows the even half's last, fixed up below.
    unsigned char* even = predicted.data();
    unsigned char* odd = predicted.data() + total / 2;
    unsigned char prev_even = 128, prev_odd = 0;
    forEachZipRow(part, channels, box, [&](const unsigned char* row, std::size_t bytes) {
        splitAndDelta(row, bytes, even, odd, prev_even, prev_odd);
        even += bytes / 2;
        odd += bytes / 2;
    });
    if (total > 0) predicted[total / 2] = static_cast<unsigned char>(predicted[total / 2] - prev_even);
    libdeflate_compressor* compressor = threadCompressor();
    if (!compressor) throw std::bad_alloc();
    packed.resize(libdeflate_zlib_compress_bound(compressor, total));
    const std::size_t size =
        libdeflate_zlib_compress(compressor, predicted.data(), total, packed.data(), packed.size());
    std::string stored;
    if (size == 0 || size >= total) {  // a reader takes a chunk no smaller than its samples as stored raw
        stored.reserve(total);
        forEachZipRow(part, channels, box, [&](const unsigned char* row, std::size_t bytes) {
            stored.append(reinterpret_cast<const char*>(row), bytes);
        });
        return stored;
    }
    return std::string(reinterpret_cast<const char*>(packed.data()), size);
}

}  // namespace

bool canEncodeZip(const ExrPart& part) { return !zipChannels(part).empty(); }

std::vector<std::string> encodeZipChunks(const ExrPart& part, int first, int last, const std::string& path) {
    const std::vector<const ExrChannel*> channels = zipChannels(part);
    std::vector<std::string> chunks(std::size_t(last - first + 1));
    try {
        runOnExrPool(PoolWork::Encode, chunks.size(),
                     [&](std::size_t i) { chunks[i] = encodeChunk(part, channels, first + int(i)); });
    } catch (const std::bad_alloc&) {
        throw outputError(fmt::format("{}: cannot encode chunks {}-{}: out of memory", path, first, last));
    }
    return chunks;
}

}  // namespace decalcomp::io
