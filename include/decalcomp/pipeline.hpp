#pragma once
// The building blocks of a frame's steps (decalcomp/frame.hpp): reading its files, its camera,
// where its outputs go, and writing them all or none.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/camera_solve.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"

namespace decalcomp {

// A frame's input files as read: the positional inputs first (roles.positional of them), then the
// --pass files that are not also positional (one read per file, however often it is named).
struct FrameFiles {
    std::vector<ExrImage> files;
    FileRoles roles;
};
// `region` limits decoding to the chunks it covers, in every file (ExrReadRegion).
FrameFiles readFrameFiles(const std::string& input, const std::vector<std::string>& extra_inputs,
                          const std::map<Attribute, std::string>& pass_files, const ExrReadRegion& region = {});

// The camera for a frame: the sidecar when given, else the first EXR header with
// worldToCamera/worldToNDC, else solved from the position pass (`solve` receives the report);
// Error(Input) when none works, with the reason (solve residual, missing passes).
Camera resolveCamera(const std::vector<ExrImage>& files, const GBuffer& gbuffer, const std::string& camera_json,
                     CameraSolveReport* solve = nullptr);
// The sidecar or the header only (no G-buffer to solve from).
Camera resolveCamera(const ExrImage& image, const std::string& camera_json);

// Where compositing writes `attributes` (compositedAttributes(scene)) back: one output per input
// file that holds their channels. `output` names the file when there is one such file, else a folder
// (an existing one, or a path ending in '/'), where each keeps its input's file name. Throws
// Error(Usage) when several files change and `output` is not a folder, or names collide.
std::map<int, std::string> outputPaths(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                                       const std::vector<Attribute>& attributes,
                                       const std::string& output);
// Whether `path` names a folder: an existing one, or a path ending in '/'.
bool isOutputFolder(const std::string& path);

// One warning per attribute the decals change that the input has no channels for (it is left
// out: compositing adds no channels).
std::vector<std::string> missingAttributeWarnings(const std::vector<Attribute>& attributes, const ChannelMapping& mapping,
                                                  const std::string& input);

// Warnings about the depth pass: every pixel background (nothing can be decaled), NaN or
// negative depths. `depth_channel` names the channel in the messages ("" when none).
std::vector<std::string> depthWarnings(const GBuffer& gbuffer, const Camera& camera, const std::string& depth_channel,
                                       const std::string& label);

// Whether two paths name one file: by inode when both exist (symlinks and hard links count),
// else by their absolute, normalised paths.
bool sameFile(const std::string& a, const std::string& b);
// Whether `path` ends in `extension` (".exr"), letter case aside.
bool hasExtension(const std::string& path, const std::string& extension);

// What one run writes and reads, checked before any work: no output may be a file the run reads
// or another output. EXR inputs may be replaced only with `overwrite_inputs` (--overwrite-input);
// the other files read (scene, camera, profiles, textures) never. EXR outputs need an .exr name.
// Throws Error(Usage) naming both files.
struct RunFiles {
    std::vector<std::string> exr_outputs;
    std::string preview;                   // "" when none
    std::vector<std::string> exr_inputs;   // positional and --pass files
    std::vector<std::string> other_reads;  // scene, camera sidecar, profiles, textures
};
void checkRunFiles(const RunFiles& files, bool overwrite_inputs);

// Writes every image to a temporary beside its path, and the preview
// through `write_preview` when `preview` is given, then renames them all into place; on any failure
// every temporary is removed and nothing is replaced. Missing folders on the way to an output are
// created (as a batch does), and removed again when the write fails.
struct PendingOutput {
    const ExrImage* image;
    std::string path;
};
// Outputs written to their temporaries and not yet renamed into place (stageOutputsTogether):
// commit() renames them all; an object destroyed uncommitted removes them, and the folders their
// write created. A batch encodes frames on several threads this way and commits them in frame
// order, so a stopped batch still leaves no frame after the one that failed.
class StagedOutputs {
public:
    StagedOutputs() = default;
    StagedOutputs(StagedOutputs&& other) noexcept;
    StagedOutputs& operator=(StagedOutputs&& other) noexcept;
    StagedOutputs(const StagedOutputs&) = delete;
    StagedOutputs& operator=(const StagedOutputs&) = delete;
    ~StagedOutputs() { discard(); }

    void commit();                                           // renames every temporary into place (the preview last)
    void discard() noexcept;                                 // removes them; nothing once committed
    const ChunkWriteStats& stats() const { return stats_; }  // what the EXR writes did with their chunks

private:
    friend StagedOutputs stageOutputsTogether(const std::vector<PendingOutput>&, const std::string*,
                                              const std::function<void(const std::string&)>&);
    std::vector<std::pair<std::string, std::string>> temporaries_;  // temporary, final; in commit order
    std::vector<std::filesystem::path> created_folders_;            // outermost first
    ChunkWriteStats stats_;
};

// The first half of writeOutputsTogether: every temporary written, none renamed.
StagedOutputs stageOutputsTogether(const std::vector<PendingOutput>& outputs, const std::string* preview,
                                   const std::function<void(const std::string&)>& write_preview);

// Returns what the EXR writes did with their chunks, summed over the outputs.
ChunkWriteStats writeOutputsTogether(const std::vector<PendingOutput>& outputs, const std::string* preview,
                                     const std::function<void(const std::string&)>& write_preview);

// sRGB PNG preview: before | after albedo and, when the frames have a normal plane, a second row
// before | after lit (albedo * Lambert, fixed camera-space light from the upper left; background
// black), so normal-map decals are visible. `camera` takes world-space normals to camera space.
// With beauty planes (RGB), a last row shows the beauty before | after, tone-mapped (Reinhard).
void writePreview(const GBuffer& before, const GBuffer& after, const Camera& camera, const std::string& path,
                  const Plane* beauty_before = nullptr, const Plane* beauty_after = nullptr);

}  // namespace decalcomp
