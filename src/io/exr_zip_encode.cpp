// ZIP chunks through libdeflate: the layout OpenEXR's file format gives ZIP compression, written
// here so that the deflating, the codec's cost in every frame, runs at libdeflate's speed.
#include "io/exr_zip_encode.hpp"

#include <OpenEXR/IlmThreadPool.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <fmt/format.h>
#include <libdeflate.h>

#include <atomic>
#include <bit>
#include <cstring>
#include <memory>

#include "decalcomp/error.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp::io {

namespace {

// zlib's default level, which OpenEXR 3.1's writer uses: the same file sizes as before.
constexpr int kDeflateLevel = 6;

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

// The channels in the order the header lists them (the order of the samples in a chunk).
std::vector<const ExrChannel*> channelsInHeaderOrder(const ExrPart& part) {
    std::vector<const ExrChannel*> ordered;
    for (auto it = part.header.channels().begin(); it != part.header.channels().end(); ++it) {
        const ExrChannel* found = nullptr;
        for (const ExrChannel& channel : part.channels)
            if (channel.name == it.name()) found = &channel;
        ordered.push_back(found);
    }
    return ordered;
}

// Chunk `chunk`'s stored bytes (see encodeZipChunks). The rows and their deflated form go through
// buffers each thread keeps, so a frame's chunks allocate only what they return: per-chunk buffers
// on the pool's threads grew each thread's heap by megabytes (batch --io-only's peak memory).
std::string encodeChunk(const ExrPart& part, const std::vector<const ExrChannel*>& channels, int chunk) {
    thread_local std::string rows, split, packed;
    const Imath::Box2i box = part.chunks.box(chunk);
    const int y0 = part.header.dataWindow().min.y;
    rows.clear();
    for (int y = box.min.y; y <= box.max.y; ++y)
        for (const ExrChannel* channel : channels) {
            const std::size_t row_bytes = sampleSize(channel->type) * std::size_t(part.width);
            rows.append(reinterpret_cast<const char*>(channel->bytes.data()) + std::size_t(y - y0) * row_bytes,
                        row_bytes);
        }
    // Even bytes, then odd ones, each stored as its difference to the one before plus 128.
    split.resize(rows.size());
    const std::size_t half = (rows.size() + 1) / 2;
    for (std::size_t i = 0; i < rows.size(); ++i) split[(i % 2 == 0) ? i / 2 : half + i / 2] = rows[i];
    for (std::size_t i = split.size(); i-- > 1;)
        split[i] = char(static_cast<unsigned char>(static_cast<unsigned char>(split[i]) -
                                                   static_cast<unsigned char>(split[i - 1]) + 128));
    libdeflate_compressor* compressor = threadCompressor();
    if (!compressor) throw std::bad_alloc();
    packed.resize(libdeflate_zlib_compress_bound(compressor, split.size()));
    const std::size_t size =
        libdeflate_zlib_compress(compressor, split.data(), split.size(), packed.data(), packed.size());
    // A reader takes a chunk no smaller than its samples as stored raw.
    if (size == 0 || size >= rows.size()) return rows;
    return packed.substr(0, size);
}

class ChunkTask : public IlmThread::Task {
public:
    ChunkTask(IlmThread::TaskGroup* group, const ExrPart& part, const std::vector<const ExrChannel*>& channels,
              int chunk, std::string& out, std::atomic<bool>& failed)
        : Task(group), part_(part), channels_(channels), chunk_(chunk), out_(out), failed_(failed) {}
    void execute() override {
        try {
            out_ = encodeChunk(part_, channels_, chunk_);
        } catch (...) {  // out of memory: reported once the group is done
            failed_ = true;
        }
    }

private:
    const ExrPart& part_;
    const std::vector<const ExrChannel*>& channels_;
    int chunk_;
    std::string& out_;
    std::atomic<bool>& failed_;
};

}  // namespace

bool canEncodeZip(const ExrPart& part) {
    const Imf::Compression compression = part.header.compression();
    if (part.chunks.tiled || (compression != Imf::ZIP_COMPRESSION && compression != Imf::ZIPS_COMPRESSION))
        return false;
    for (const ExrChannel* channel : channelsInHeaderOrder(part))
        if (!channel || channel->x_sampling != 1 || channel->y_sampling != 1) return false;
    return true;
}

std::vector<std::string> encodeZipChunks(const ExrPart& part, int first, int last, const std::string& path) {
    const std::vector<const ExrChannel*> channels = channelsInHeaderOrder(part);
    std::vector<std::string> chunks(std::size_t(last - first + 1));
    std::atomic<bool> failed{false};
    {
        IlmThread::TaskGroup group;  // waits for its tasks when it goes out of scope
        for (int chunk = first; chunk <= last; ++chunk)
            IlmThread::ThreadPool::addGlobalTask(
                new ChunkTask(&group, part, channels, chunk, chunks[std::size_t(chunk - first)], failed));
    }
    if (failed) throw outputError(fmt::format("{}: cannot encode chunks {}-{}: out of memory", path, first, last));
    return chunks;
}

}  // namespace decalcomp::io
