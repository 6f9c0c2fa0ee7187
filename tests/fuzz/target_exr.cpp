// EXR: the input as a G-buffer file, through what composite does with one before the device:
// readExr (header, parts, pixels), the header camera of each part, the inline Cryptomatte
// manifests, channel mapping through the profiles, G-buffer extraction onto the frame window, then
// every plane stored back into its channels and the file written out again with its own header.
#include <OpenEXR/ImfThreading.h>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/masks.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace {

void readHeaderMetadata(const ExrImage& image) {
    for (const ExrPart& part : image.parts)
        inputErrorsAllowed([&] { (void)cameraFromExrHeader(part.header, image.path); });
    // Sidecar manifests (manif_file) name other files: not part of the input, left out.
    for (CryptomatteLayer& layer : cryptomatteLayers({image})) {
        layer.manif_file.clear();
        inputErrorsAllowed([&] { (void)cryptomatteManifest(layer); });
    }
}

// Writing back may also refuse (Error(Output)) a header the writer cannot honour.
void writeBack(ExrImage& image, const ChannelMapping& mapping, const GBuffer& gbuffer) {
    for (const auto& entry : gbuffer.planes)  // not a structured binding: clang 15 cannot capture one
        inputErrorsAllowed([&] { storeAttribute(image, mapping, entry.first, entry.second); });
    try {
        discardExrTemporary(writeExrTemporary(image, (scratchDir() / "written.exr").string()));
    } catch (const Error& e) {
        if (e.kind() != ErrorKind::Output) throw;
    }
}

}  // namespace

void fuzzExr(const std::uint8_t* data, std::size_t size) {
    static const bool single_threaded = [] {  // reproducible runs: no OpenEXR worker threads
        Imf::setGlobalThreadCount(0);
        return true;
    }();
    (void)single_threaded;
    const std::string path = writeScratchFile("frame.exr", asText(data, size));
    ExrImage image;
    if (!inputErrorsAllowed([&] { image = readExr(path); })) return;
    readHeaderMetadata(image);
    ChannelMapping mapping;
    if (!inputErrorsAllowed([&] { mapping = mapChannels(image, MappingOptions{}); })) return;
    GBuffer gbuffer;
    if (!inputErrorsAllowed([&] { gbuffer = extractGBuffer(image, mapping); })) return;
    writeBack(image, mapping, gbuffer);
}

}  // namespace decalcomp::fuzz
