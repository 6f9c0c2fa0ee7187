// encodeChunks: a one-part EXR in memory whose data window is exactly the chunks' pixels (so its
// chunk grid lines up with the part's), written by the C++ API, its chunks read back raw.
#include "io/exr_chunk_encode.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTiledOutputPart.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "decalcomp/error.hpp"
#include "io/exr_core.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_zip_encode.hpp"

namespace decalcomp::io {

namespace {

class MemoryStream : public Imf::OStream {
public:
    MemoryStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (position_ + std::size_t(n) > bytes_.size()) bytes_.resize(position_ + std::size_t(n));
        std::memcpy(bytes_.data() + position_, c, std::size_t(n));
        position_ += std::size_t(n);
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t position) override { position_ = std::size_t(position); }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
    std::size_t position_ = 0;
};

std::string encodeInMemory(const ExrPart& part, const Imath::Box2i& box) {
    Imf::Header header = part.header;
    header.dataWindow() = box;
    if (!header.hasType()) header.setType(part.chunks.tiled ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    Imf::FrameBuffer frame_buffer;  // the part's whole-window planes, addressed by absolute pixel
    for (const ExrChannel& channel : part.channels)
        if (header.channels().findChannel(channel.name))
            frame_buffer.insert(channel.name, channelSlice(part.header.dataWindow(), channel));
    MemoryStream stream;
    {
        Imf::MultiPartOutputFile file(stream, &header, 1);
        if (part.chunks.tiled) {
            Imf::TiledOutputPart out(file, 0);
            out.setFrameBuffer(frame_buffer);
            out.writeTiles(0, out.numXTiles(0) - 1, 0, out.numYTiles(0) - 1);
        } else {
            Imf::OutputPart out(file, 0);
            out.setFrameBuffer(frame_buffer);
            out.writePixels(box.max.y - box.min.y + 1);
        }
    }
    return stream.bytes();
}

}  // namespace

std::vector<std::string> encodeChunks(const ExrPart& part, int first, int last, const std::string& path) {
    if (canEncodeZip(part)) return encodeZipChunks(part, first, last, path);
    const ChunkLayout& layout = part.chunks;
    Imath::Box2i box = layout.box(first);
    box.extendBy(layout.box(last));
    std::string file;
    try {
        file = encodeInMemory(part, box);
    } catch (const std::exception& e) {
        throw outputError(fmt::format("{}: cannot encode chunks {}-{}: {}", path, first, last, oneLine(e.what())));
    }
    const CoreContext encoded(path + " (encoded chunks)", file);
    std::vector<std::string> chunks;
    for (int chunk = first; chunk <= last; ++chunk) {
        exr_chunk_info_t info{};
        encoded.require(layout.tiled ? exr_read_tile_chunk_info(encoded.context(), 0, chunk - first, 0, 0, 0, &info)
                                     : exr_read_scanline_chunk_info(encoded.context(), 0, layout.box(chunk).min.y, &info),
                        0, "chunk table");
        std::string& bytes = chunks.emplace_back(std::size_t(info.packed_size), '\0');
        encoded.require(exr_read_chunk(encoded.context(), 0, &info, bytes.data()), 0, "chunk");
    }
    return chunks;
}

}  // namespace decalcomp::io
