#pragma once
// EXR helpers the chunk and beauty tests share: a FLOAT channel's samples as floats, a file
// rewritten with another compression (and tiling) through the whole-file writer, and a file's
// stored chunks.
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/openexr.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "support/test_support.hpp"

namespace decalcomp::test {

inline std::vector<float> floatSamples(const ExrImage& image, const std::string& qualified) {
    const ExrChannel& c = channel(image, qualified);
    std::vector<float> out(c.bytes.size() / sizeof(float));
    std::memcpy(out.data(), c.bytes.data(), c.bytes.size());
    return out;
}

// Every part of `image` (read whole) written to `out` with `compression`, in 32x32 tiles when
// `tiled`; DWA at level 45, as oiiotool writes it.
inline void writeWithCompression(ExrImage image, Imf::Compression compression, bool tiled, const std::string& out) {
    for (ExrPart& part : image.parts) {
        part.header.compression() = compression;
        if (tiled) {
            part.header.setTileDescription(Imf::TileDescription(32, 32, Imf::ONE_LEVEL));
            part.header.setType(Imf::TILEDIMAGE);
        }
        if (compression == Imf::DWAA_COMPRESSION || compression == Imf::DWAB_COMPRESSION)
            part.header.insert("dwaCompressionLevel", Imf::FloatAttribute(45.0f));
    }
    image.copy_unchanged_chunks = false;
    writeExrAtomic(image, out);
}

// Reads every chunk's stored bytes through OpenEXR's core API: [part][chunk].
inline std::vector<std::vector<std::string>> rawChunks(const std::string& path) {
    exr_context_t context = nullptr;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    EXPECT_EQ(exr_start_read(&context, path.c_str(), &init), EXR_ERR_SUCCESS) << path;
    int parts = 0;
    exr_get_count(context, &parts);
    std::vector<std::vector<std::string>> chunks{std::size_t(parts)};
    for (int p = 0; p < parts; ++p) {
        exr_storage_t storage{};
        exr_get_storage(context, p, &storage);
        exr_attr_box2i_t dw{};
        exr_get_data_window(context, p, &dw);
        std::vector<exr_chunk_info_t> infos;
        if (storage == EXR_STORAGE_TILED) {
            int32_t tw = 0, th = 0, lw = 0, lh = 0;
            exr_get_tile_sizes(context, p, 0, 0, &tw, &th);
            exr_get_level_sizes(context, p, 0, 0, &lw, &lh);
            for (int ty = 0; ty < (lh + th - 1) / th; ++ty)
                for (int tx = 0; tx < (lw + tw - 1) / tw; ++tx) {
                    exr_chunk_info_t info{};
                    EXPECT_EQ(exr_read_tile_chunk_info(context, p, tx, ty, 0, 0, &info), EXR_ERR_SUCCESS);
                    infos.push_back(info);
                }
        } else {
            int32_t lines = 0;
            exr_get_scanlines_per_chunk(context, p, &lines);
            for (int y = dw.min.y; y <= dw.max.y; y += lines) {
                exr_chunk_info_t info{};
                EXPECT_EQ(exr_read_scanline_chunk_info(context, p, y, &info), EXR_ERR_SUCCESS);
                infos.push_back(info);
            }
        }
        for (const exr_chunk_info_t& info : infos) {
            std::string bytes(std::size_t(info.packed_size), '\0');
            EXPECT_EQ(exr_read_chunk(context, p, &info, bytes.data()), EXR_ERR_SUCCESS);
            chunks[std::size_t(p)].push_back(std::move(bytes));
        }
    }
    exr_finish(&context);
    return chunks;
}

}  // namespace decalcomp::test
