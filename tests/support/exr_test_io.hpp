#pragma once
// EXR helpers the chunk and beauty tests share: a FLOAT channel's samples as floats, and a file
// rewritten with another compression (and tiling) through the whole-file writer.
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>

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

}  // namespace decalcomp::test
