// readExr / writeExrAtomic: whole EXR files in memory, raw samples, headers untouched.
#include "decalcomp/exr_file.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <OpenEXR/ImfTiledOutputPart.h>
#include <OpenEXR/ImfVersion.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "decalcomp/error.hpp"
#include "decalcomp/input_file.hpp"
#include "decalcomp/memory_limit.hpp"
#include "decalcomp/temporary_files.hpp"
#include "io/exr_chunk_copy.hpp"
#include "io/exr_layout.hpp"
#include "io/exr_plausibility.hpp"
#include "io/exr_zip_decode.hpp"

namespace decalcomp {

namespace {

std::string partLabel(const Imf::Header& header, int index) {
    return header.hasName() ? fmt::format("part {} ({})", index, header.name())
                            : fmt::format("part {}", index);
}

// Checks the magic number first so a text file gets a plain answer, not a library message.
void requireExrMagic(const std::string& path) {
    requireInputFile(path, "EXR file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw inputError(fmt::format("{}: cannot open ({})", path, std::strerror(errno)));
    char magic[4] = {};
    if (!in.read(magic, sizeof magic) || !Imf::isImfMagic(magic))
        throw inputError(fmt::format("{}: not an OpenEXR file", path));
}

// Deep and multi-resolution parts cannot be kept as one flat plane per channel.
void requireFlatSingleLevel(const Imf::Header& header, int index, const std::string& path) {
    if (header.hasType() && Imf::isDeepData(header.type()))
        throw inputError(fmt::format("{}: {}: deep data is not supported", path, partLabel(header, index)));
    if (header.hasTileDescription() && header.tileDescription().mode != Imf::ONE_LEVEL)
        throw inputError(fmt::format("{}: {}: mipmapped or ripmapped tiles are not supported",
                                     path, partLabel(header, index)));
}

void readChunks(Imf::MultiPartInputFile& file, int index, const ExrPart& part, const Imf::FrameBuffer& frame_buffer);

// The planes readPart allocates, from the headers it allocates them by, against the memory limit.
// requirePlausibleExr checked the core reader's view first; this one is the C++ reader's, so a
// header the two read differently cannot slip past (defence in depth).
void requireDecodableSize(const Imf::MultiPartInputFile& file, const std::string& path) {
    std::uint64_t total = 0;
    for (int i = 0; i < file.parts(); ++i) {
        const Imath::Box2i dw = file.header(i).dataWindow();
        const std::uint64_t width = std::uint64_t(std::int64_t(dw.max.x) - dw.min.x + 1);
        const std::uint64_t height = std::uint64_t(std::int64_t(dw.max.y) - dw.min.y + 1);
        const std::string what = fmt::format("part {}: dataWindow {}x{}", i, width, height);
        const Imf::ChannelList& channels = file.header(i).channels();
        for (auto it = channels.begin(); it != channels.end(); ++it) {
            const auto bytes = io::decodedChannelBytes(width, height, it.channel().xSampling, it.channel().ySampling,
                                                       it.channel().type == Imf::HALF ? 2 : 4);
            if (!bytes || total + *bytes < total)
                throw inputError(fmt::format("{}: {}: overflows; the header is corrupt", path, what));
            total += *bytes;
        }
        requireWithinMemoryLimit(total, path, what);
    }
}

ExrPart readPart(Imf::MultiPartInputFile& file, int index, const std::string& path, const ExrReadRegion& region) {
    const Imf::Header& header = file.header(index);
    requireFlatSingleLevel(header, index, path);
    const bool multi_part = Imf::isMultiPart(file.version());
    const std::string part_name = header.hasName() ? header.name() : std::string();
    const Imath::Box2i dw = header.dataWindow();

    ExrPart part;
    part.header = header;
    part.width = dw.max.x - dw.min.x + 1;
    part.height = dw.max.y - dw.min.y + 1;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
        ExrChannel channel;
        channel.name = it.name();
        channel.qualified = io::qualifiedChannelName(part_name, multi_part, channel.name);
        channel.type = io::sampleType(it.channel().type);
        channel.x_sampling = it.channel().xSampling;
        channel.y_sampling = it.channel().ySampling;
        channel.bytes.resize(io::channelByteCount(dw, channel));
        part.channels.push_back(std::move(channel));
    }

    part.chunks = chunkLayoutOf(header);
    if (!region.everything) {
        for (const Imath::Box2i& box : region.boxes) part.chunks.chunksIn(box, part.decoded);
        part.decoded.resize(std::size_t(part.chunks.count()), 0);
    }
    if (io::canDecodeZip(part)) {  // the common case, at libdeflate's speed
        io::decodeZipChunks(path, index, part);
        return part;
    }
    // OpenEXR's reader for everything else: it decodes into slices over the channels' samples.
    Imf::FrameBuffer frame_buffer;
    for (const ExrChannel& channel : part.channels)
        frame_buffer.insert(channel.name, io::channelSlice(dw, channel));
    if (region.everything) {
        // InputPart reads tiled parts too, presenting level 0 as scanlines.
        Imf::InputPart input(file, index);
        input.setFrameBuffer(frame_buffer);
        input.readPixels(dw.min.y, dw.max.y);
        return part;
    }
    readChunks(file, index, part, frame_buffer);
    return part;
}

// Decodes the chunks marked in part.decoded: runs of scanline blocks at once, tiles one by one.
void readChunks(Imf::MultiPartInputFile& file, int index, const ExrPart& part, const Imf::FrameBuffer& frame_buffer) {
    const ChunkLayout& layout = part.chunks;
    if (layout.tiled) {
        Imf::TiledInputPart input(file, index);
        input.setFrameBuffer(frame_buffer);
        for (int chunk = 0; chunk < layout.count(); ++chunk)
            if (part.decoded[std::size_t(chunk)]) input.readTile(layout.tileX(chunk), layout.tileY(chunk));
        return;
    }
    Imf::InputPart input(file, index);
    input.setFrameBuffer(frame_buffer);
    for (int first = 0; first < layout.count();) {
        if (!part.decoded[std::size_t(first)]) {
            ++first;
            continue;
        }
        int last = first;
        while (last + 1 < layout.count() && part.decoded[std::size_t(last + 1)]) ++last;
        input.readPixels(layout.box(first).min.y, layout.box(last).max.y);
        first = last + 1;
    }
}

// The bytes the writer hands to OpenEXR must match the header they are written under.
void validatePart(const ExrPart& part, int index, const std::string& path) {
    const Imath::Box2i dw = part.header.dataWindow();
    const Imf::ChannelList& list = part.header.channels();
    for (auto it = list.begin(); it != list.end(); ++it) {
        const ExrChannel* found = nullptr;
        for (const ExrChannel& channel : part.channels)
            if (channel.name == it.name()) found = &channel;
        if (!found)
            throw outputError(fmt::format("{}: {}: channel {}: no samples to write", path,
                                          partLabel(part.header, index), it.name()));
        if (io::pixelType(found->type) != it.channel().type || found->x_sampling != it.channel().xSampling ||
            found->y_sampling != it.channel().ySampling)
            throw outputError(fmt::format("{}: {}: channel {}: type or sampling differs from the header",
                                          path, partLabel(part.header, index), it.name()));
        if (found->bytes.size() != io::channelByteCount(dw, *found))
            throw outputError(fmt::format("{}: {}: channel {}: {} bytes, expected {}", path,
                                          partLabel(part.header, index), it.name(), found->bytes.size(),
                                          io::channelByteCount(dw, *found)));
    }
}

Imf::FrameBuffer frameBufferOf(const ExrPart& part) {
    const Imath::Box2i dw = part.header.dataWindow();
    Imf::FrameBuffer frame_buffer;
    for (const ExrChannel& channel : part.channels)
        if (part.header.channels().findChannel(channel.name))
            frame_buffer.insert(channel.name, io::channelSlice(dw, channel));
    return frame_buffer;
}

void writePart(Imf::MultiPartOutputFile& file, const ExrPart& part, int index) {
    if (part.header.hasTileDescription()) {
        Imf::TiledOutputPart out(file, index);
        out.setFrameBuffer(frameBufferOf(part));
        out.writeTiles(0, out.numXTiles(0) - 1, 0, out.numYTiles(0) - 1);
    } else {
        Imf::OutputPart out(file, index);
        out.setFrameBuffer(frameBufferOf(part));
        out.writePixels(part.height);
    }
}

void writeParts(const ExrImage& image, const std::string& path) {
    std::vector<Imf::Header> headers;
    for (const ExrPart& part : image.parts) {
        headers.push_back(part.header);
        // Single-part files may omit "type"; MultiPartOutputFile insists on it, and it is harmless.
        if (!headers.back().hasType())
            headers.back().setType(part.header.hasTileDescription() ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
        for (const auto& [name, value] : image.added_attributes) headers.back().insert(name, Imf::StringAttribute(value));
    }
    // Scoped so the file is closed (and complete) before the rename.
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), int(headers.size()));
    for (int i = 0; i < int(image.parts.size()); ++i) writePart(file, image.parts[i], i);
}

bool anyChunkChanged(const ExrImage& image) {
    for (const ExrPart& part : image.parts)
        if (part.anyChanged()) return true;
    return false;
}

std::size_t chunkCount(const ExrImage& image) {
    std::size_t count = 0;
    for (const ExrPart& part : image.parts) count += std::size_t(chunkLayoutOf(part.header).count());
    return count;
}

// The cheapest faithful write: the input file itself when no chunk changed, its unchanged chunks
// copied when some did, every chunk encoded when the image has no input to copy from.
ChunkWriteStats writeFile(const ExrImage& image, const std::string& path, const std::string& temporary) {
    for (const ExrPart& part : image.parts)
        if (!image.copy_unchanged_chunks && !part.decoded.empty())
            throw outputError(fmt::format("{}: part of the input {} was never read (internal error)", path, image.path));
    ChunkWriteStats stats;
    if (image.copy_unchanged_chunks && !anyChunkChanged(image)) {
        std::error_code ec;
        std::filesystem::copy_file(image.path, temporary, std::filesystem::copy_options::overwrite_existing, ec);
        if (ec) throw outputError(fmt::format("{}: cannot copy {}: {}", path, image.path, ec.message()));
        stats.copied = chunkCount(image);
        return stats;
    }
    if (image.copy_unchanged_chunks) return io::writeCopyingUnchangedChunks(image, temporary, path);
    writeParts(image, temporary);
    stats.reencoded = chunkCount(image);
    for (const ExrPart& part : image.parts) stats.pixels_reencoded += std::size_t(part.width) * std::size_t(part.height);
    return stats;
}

}  // namespace

bool ExrPart::anyChanged() const {
    for (std::uint8_t c : changed)
        if (c) return true;
    return false;
}

ExrImage readExr(const std::string& path, const ExrReadRegion& region) {
    requireExrMagic(path);
    io::requirePlausibleExr(path);
    ExrImage image;
    image.path = path;
    try {
        Imf::MultiPartInputFile file(path.c_str());
        requireDecodableSize(file, path);
        for (int i = 0; i < file.parts(); ++i) image.parts.push_back(readPart(file, i, path, region));
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw inputError(fmt::format("{}: cannot read: {}", path, io::oneLine(e.what())));
    }
    return image;
}

std::vector<Imf::Header> readExrHeaders(const std::string& path) {
    requireExrMagic(path);
    io::requirePlausibleExr(path);  // hostile headers fail here, naming the field, as in readExr
    std::vector<Imf::Header> headers;
    try {
        Imf::MultiPartInputFile file(path.c_str());
        for (int i = 0; i < file.parts(); ++i) headers.push_back(file.header(i));
    } catch (const std::exception& e) {
        throw inputError(fmt::format("{}: cannot read: {}", path, io::oneLine(e.what())));
    }
    return headers;
}

std::string writeExrTemporary(const ExrImage& image, const std::string& path, ChunkWriteStats* stats) {
    if (image.parts.empty()) throw outputError(fmt::format("{}: nothing to write (no parts)", path));
    for (int i = 0; i < int(image.parts.size()); ++i) validatePart(image.parts[i], i, path);

    // Registered before the file exists, so a termination signal removes it (temporary_files.hpp).
    const std::string temporary = temporaryPathFor(path);
    const std::string opening_name = createTemporary(temporary, path);
    try {
        const ChunkWriteStats written = writeFile(image, path, opening_name);
        if (stats) *stats += written;
    } catch (const Error&) {
        discardTemporary(temporary);
        throw;
    } catch (const std::exception& e) {
        discardTemporary(temporary);
        throw outputError(fmt::format("{}: cannot write: {}", path, io::oneLine(e.what())));
    }
    return temporary;
}

void commitExrTemporary(const std::string& temporary, const std::string& path) {
    commitTemporaries({{temporary, path}});
}

void discardExrTemporary(const std::string& temporary) noexcept { discardTemporary(temporary); }

void writeExrAtomic(const ExrImage& image, const std::string& path) {
    commitExrTemporary(writeExrTemporary(image, path), path);
}

}  // namespace decalcomp
