#pragma once
// How ZIP and ZIPS compression lay out a scanline chunk's samples before deflate (OpenEXR's file
// format): per line, each channel's row of samples in the header's channel order; then the bytes
// split into even and odd halves, each byte stored as its difference to the one before plus 128.
// Shared by the encoder and the decoder (internal).
#include <cstddef>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp::io {

// The channels of a ZIP or ZIPS scanline part in the header's order, when every one is full
// resolution and held in `part.channels`; empty otherwise (OpenEXR's own codec handles the part).
std::vector<const ExrChannel*> zipChannels(const ExrPart& part);

// The rows of the chunk over `box` as one run of bytes, through `each(row, bytes)`: `row` points
// into the channel's samples. Rows hold whole samples of 2 or 4 bytes, so each starts at an even
// offset of the run.
template <typename Row, typename Each>
void forEachZipRow(const ExrPart& part, const std::vector<Row*>& channels, const Imath::Box2i& box, Each&& each) {
    const int y0 = part.header.dataWindow().min.y;
    for (int y = box.min.y; y <= box.max.y; ++y)
        for (Row* channel : channels) {
            const std::size_t row_bytes = sampleSize(channel->type) * std::size_t(part.width);
            each(channel->bytes.data() + std::size_t(y - y0) * row_bytes, row_bytes);
        }
}

// The bytes of the chunk over `box` (the channels' rows, before the predictor).
template <typename Row>
std::size_t zipChunkBytes(const ExrPart& part, const std::vector<Row*>& channels, const Imath::Box2i& box) {
    std::size_t pixel_bytes = 0;
    for (Row* channel : channels) pixel_bytes += sampleSize(channel->type);
    return pixel_bytes * std::size_t(part.width) * std::size_t(box.max.y - box.min.y + 1);
}

}  // namespace decalcomp::io
