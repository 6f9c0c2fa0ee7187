#include "io/exr_zip_layout.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>

namespace decalcomp::io {

std::vector<const ExrChannel*> zipChannels(const ExrPart& part) {
    const Imf::Compression compression = part.header.compression();
    if (part.chunks.tiled || (compression != Imf::ZIP_COMPRESSION && compression != Imf::ZIPS_COMPRESSION)) return {};
    std::vector<const ExrChannel*> ordered;
    for (auto it = part.header.channels().begin(); it != part.header.channels().end(); ++it) {
        const ExrChannel* found = nullptr;
        for (const ExrChannel& channel : part.channels)
            if (channel.name == it.name()) found = &channel;
        if (!found || found->x_sampling != 1 || found->y_sampling != 1) return {};
        ordered.push_back(found);
    }
    return ordered;
}

}  // namespace decalcomp::io
