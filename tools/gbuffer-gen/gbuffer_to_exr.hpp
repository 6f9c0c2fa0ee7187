#pragma once
// Lays a synthetic G-buffer out as an OpenEXR image in one of the channel conventions decalcomp
// reads (Blender multilayer names or short generic names), single- or multi-part.
#include <OpenEXR/ImfCompression.h>

#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/exr_io.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::gen {

enum class Naming { Blender, Generic };

struct ExrLayoutOptions {
    Naming naming = Naming::Blender;
    std::string layer = "ViewLayer";  // Blender view-layer name (Blender naming only)
    bool half = false;                // albedo, normal, beauty, roughness, metallic as HALF
    Imf::Compression compression = Imf::ZIP_COMPRESSION;
    bool multipart = false;           // one part per pass, part name = pass name
    std::optional<Camera> header_camera;  // also written as worldToCamera/worldToNDC
};

// A plain lit shade of the albedo (fixed sun + ambient, no shadows) as RGBA, 4 floats a pixel;
// background pixels (zero normal) are transparent black.
std::vector<float> beautyShade(const GBuffer& gbuffer);

// Builds the EXR image. Depth and position are always FLOAT; the object id is FLOAT under
// Blender naming (as Cycles writes IndexOB) and UINT under generic naming. Depth and position are
// left out when the G-buffer has no such plane. Throws Error(Output) when a required plane is missing.
ExrImage gbufferToExr(const GBuffer& gbuffer, const ExrLayoutOptions& options);

}  // namespace decalcomp::gen
