#pragma once
// One frame end to end: EXR in, decals composited on an OpenCL device, EXR (and preview) out.
// The CLI's `composite` and `info` commands are thin wrappers over these functions.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/camera_solve.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/depth_check.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/normal_check.hpp"

namespace decalcomp {

struct CompositeRequest {
    std::string input;                     // G-buffer EXR (the first positional input)
    std::vector<std::string> extra_inputs; // further positional EXRs, pooled with `input` for the profile
    std::map<Attribute, std::string> pass_files;  // --pass ATTR=FILE: the attribute comes from FILE
    std::string scene;        // decal scene JSON
    std::string camera_json;  // optional sidecar; wins over the EXR header
    std::string output;       // EXR to write, or a folder (docs/cli.md: which files are written)
    std::string preview;      // optional PNG: albedo (and lit normals) before | after
    std::string device;       // selector, see selectDevice()
    MappingOptions mapping;
    bool overwrite_input = false;
    bool binned = true;
};

struct CompositeReport {
    std::string device;
    std::string camera_source;
    std::optional<CameraSolveReport> camera_solve;  // when the camera was solved
    DepthCheck depth_check;                         // planar/radial verdict against the position pass
    NormalCheck normal_check;                       // normal space/encoding against the depth pass
    ChannelMapping mapping;
    CompositeStats stats;
    std::size_t background_pixels = 0;
    std::vector<std::string> outputs;  // the EXR files written
    std::vector<std::string> warnings;  // e.g. a mask name that matches nothing; the CLI prints them
};

// Throws Error; on any error no output (EXR or preview) is created or replaced.
CompositeReport compositeFile(const CompositeRequest& request);

// A frame's input files as read: the positional inputs first (roles.positional of them), then the
// --pass files that are not also positional (one read per file, however often it is named).
struct FrameFiles {
    std::vector<ExrImage> files;
    FileRoles roles;
};
FrameFiles readFrameFiles(const std::string& input, const std::vector<std::string>& extra_inputs,
                          const std::map<Attribute, std::string>& pass_files);

// The camera for a frame: the sidecar when given, else the first EXR header with
// worldToCamera/worldToNDC, else solved from the position pass (`solve` receives the report);
// Error(Input) when none works, with the reason (solve residual, missing passes).
Camera resolveCamera(const std::vector<ExrImage>& files, const GBuffer& gbuffer, const std::string& camera_json,
                     CameraSolveReport* solve = nullptr);
// The sidecar or the header only (no G-buffer to solve from).
Camera resolveCamera(const ExrImage& image, const std::string& camera_json);

// Checks planar vs radial depth against the position pass and, unless --depth was given, adopts
// the verdict in both the G-buffer and the mapping (with a note).
DepthCheck settleDepthConvention(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera);

// Checks the normal pass's space and encoding against the geometry and, unless --normals was
// given, adopts a clear verdict in both the G-buffer and the mapping (with a note).
NormalCheck settleNormalEncoding(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera);

// Where compositing writes `attributes` (compositedAttributes(scene)) back: one output per input
// file that holds their channels. `output` names the file when there is one such file, else a folder
// (an existing one, or a path ending in '/'), where each keeps its input's file name. Throws
// Error(Usage) when several files change and `output` is not a folder, or names collide.
std::map<int, std::string> outputPaths(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                                       const std::vector<Attribute>& attributes,
                                       const std::string& output);

// One warning per attribute the decals change that the input has no channels for (it is left
// out: compositing adds no channels).
std::vector<std::string> missingAttributeWarnings(const std::vector<Attribute>& attributes, const ChannelMapping& mapping,
                                                  const std::string& input);

// Refuses (Error(Usage)) to write over the input unless allowed.
void checkNotOverwritingInput(const std::string& input, const std::string& output, bool allowed);

// sRGB PNG preview: before | after albedo and, when the frames have a normal plane, a second row
// before | after lit (albedo * Lambert, fixed camera-space light from the upper left; background
// black), so normal-map decals are visible. `camera` takes world-space normals to camera space.
void writePreview(const GBuffer& before, const GBuffer& after, const Camera& camera, const std::string& path);

}  // namespace decalcomp
