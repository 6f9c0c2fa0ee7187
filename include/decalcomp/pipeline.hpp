#pragma once
// One frame end to end: EXR in, decals composited on an OpenCL device, EXR (and preview) out.
// The CLI's `composite` and `info` commands are thin wrappers over these functions.
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/exr_io.hpp"

namespace decalcomp {

struct CompositeRequest {
    std::string input;        // G-buffer EXR
    std::string scene;        // decal scene JSON
    std::string camera_json;  // optional sidecar; wins over the EXR header
    std::string output;       // EXR to write
    std::string preview;      // optional PNG: input albedo | output albedo
    std::string device;       // selector, see selectDevice()
    MappingOptions mapping;
    bool overwrite_input = false;
    bool binned = true;
};

struct CompositeReport {
    std::string device;
    std::string camera_source;
    ChannelMapping mapping;
    CompositeStats stats;
    std::size_t background_pixels = 0;
};

// Throws Error; on any error no output (EXR or preview) is created or replaced.
CompositeReport compositeFile(const CompositeRequest& request);

// The camera for a file: the sidecar when given, else the EXR header; Error(Input) when neither.
Camera resolveCamera(const ExrImage& image, const std::string& camera_json);

// Refuses (Error(Usage)) to write over the input unless allowed.
void checkNotOverwritingInput(const std::string& input, const std::string& output, bool allowed);

// Side-by-side sRGB PNG of the before and after albedo, written atomically.
void writeAlbedoPreview(const GBuffer& before, const GBuffer& after, const std::string& path);

}  // namespace decalcomp
