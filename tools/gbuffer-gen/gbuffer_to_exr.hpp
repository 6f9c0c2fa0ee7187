#pragma once
// Lays a synthetic G-buffer out as an OpenEXR image in one of the channel conventions decalcomp
// reads (Blender multilayer names or short generic names), single- or multi-part.
#include <OpenEXR/ImfCompression.h>

#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::gen {

// Channel naming conventions, one per renderer profile (docs/profiles.md lists the names).
enum class Naming { Blender, Generic, Arnold, Karma, RenderMan, Unreal };
const char* namingName(Naming naming);  // "blender", "generic", "arnold", "karma", "renderman", "unreal"
std::optional<Naming> namingFromName(const std::string& name);

struct ExrLayoutOptions {
    Naming naming = Naming::Blender;
    std::string layer = "ViewLayer";  // Blender view-layer name (Blender naming only)
    bool half = false;                // albedo, normal, beauty, roughness, metallic as HALF
    Imf::Compression compression = Imf::ZIP_COMPRESSION;
    bool multipart = false;           // one part per pass, part name = pass name (blender, generic)
    std::optional<Camera> header_camera;  // also written as worldToCamera/worldToNDC
    Camera camera;                        // for camera-space passes (RenderMan's Nn)
    bool light_passes = false;            // the diffuse light passes (synth_light.hpp): Blender's DiffDir/DiffInd
                                          // (divided), Arnold's and RenderMan's (multiplied); beauty = their sum
};

// A plain lit shade of the albedo (fixed sun + ambient, no shadows) as RGBA, 4 floats a pixel;
// background pixels (zero normal) are transparent black.
std::vector<float> beautyShade(const GBuffer& gbuffer);

// Builds the EXR image; its data window is the G-buffer's (origin and size) inside its display
// window. Depth and position are always FLOAT; the object id is FLOAT under Blender, Karma,
// RenderMan and Unreal naming and UINT under generic and Arnold naming. Depth and position are left
// out when the G-buffer has no such plane. Throws Error(Output) when a required plane is missing.
ExrImage gbufferToExr(const GBuffer& gbuffer, const ExrLayoutOptions& options);

// One file per pass, keyed "beauty" (R,G,B,A), "depth" (Z), "albedo" (R,G,B), "normal" (X,Y,Z),
// "position" (X,Y,Z), "id" (id, UINT), "roughness" (Y), "metallic" (Y): bare component names, as
// renderers write separate AOV files. Types, windows and compression as gbufferToExr.
std::vector<std::pair<std::string, ExrImage>> gbufferToPassFiles(const GBuffer& gbuffer, const ExrLayoutOptions& options);

}  // namespace decalcomp::gen
