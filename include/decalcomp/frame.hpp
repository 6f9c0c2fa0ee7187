#pragma once
// One frame end to end: its input files and their roles, the channel mapping, the G-buffer
// planes, the camera, the settled depth and normal conventions, the masks and the outputs, in
// three steps: prepare, composite, write back. `decalcomp composite`, `decalcomp batch` and
// programs that embed the library all drive this one type.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/camera_solve.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/depth_check.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/frame_beauty.hpp"
#include "decalcomp/normal_check.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/provenance.hpp"
#include "decalcomp/sequence_conventions.hpp"

namespace decalcomp {

// Where a frame's passes and camera come from.
struct FrameSources {
    std::vector<std::string> inputs;              // positional EXRs, pooled and mapped through the profile
    std::map<Attribute, std::string> pass_files;  // --pass ATTR=FILE: the attribute comes from FILE only
    std::optional<Camera> camera;                 // explicit camera; else camera_json
    std::string camera_json;                      // sidecar; else the first header's, else solved
    std::string camera_file;                      // the file `camera` was read from (outputs may not replace it)
};

// Where a frame's results go.
struct FrameTargets {
    std::string output;   // EXR to write, or a folder where each changed file keeps its name
    std::string preview;  // optional PNG: albedo (and lit normals) before | after
    bool overwrite_input = false;
    // The caller reads gbuffer() after composite() (a batch's contact sheet): every pixel is decoded
    // and the planes are extracted even on a frame where no decal is alive.
    bool every_pixel = false;
    // Composite a scene the inputs' headers say was already composited into them (provenance.hpp);
    // without it prepare() refuses, since every decal would be stacked twice.
    bool force = false;
};

struct FrameOptions {
    MappingOptions mapping;
    CompositeOptions compositing;
    BeautyOptions beauty;  // --beauty, --relight
    std::optional<PixelFilter> pixel_filter;  // --pixel-filter; nullopt: chosen per frame (frame_pixel_filter.hpp)
    bool pixel_filter_fast = false;  // --pixel-filter auto:fast: the filter chosen per frame, evaluated `:fast`
    std::optional<bool> uv_v_down;  // --uv-origin top (true) | bottom; nullopt: from the rest meshes (texture space)
    std::optional<double> frame_number;  // picks animated decals' state; nullopt: the scene as written
    std::string label;  // names the frame in warnings (a batch gives its pattern); default: the first input
};

// What one frame did, for the CLI and callers.
struct FrameReport {
    std::string camera_source;
    std::optional<CameraSolveReport> camera_solve;  // when the camera was solved
    DepthCheck depth_check;                         // planar/radial verdict against the position pass
    NormalCheck normal_check;                       // normal space/encoding against the depth pass
    ChannelMapping mapping;
    CompositeStats stats;
    BeautyReport beauty;  // whether the beauty was rebuilt, from which passes
    std::string pixel_filter;  // the filter decals were integrated over, and why: "blackman-harris:3 (profile blender)"
    std::size_t changed_samples = 0;    // channel samples the decals changed (0: a warning)
    // What writeBack() did with the outputs' chunks: copied compressed from the input, or
    // decoded, composited and encoded again (docs/cli.md, "Chunks").
    std::size_t chunks_copied = 0, chunks_reencoded = 0, pixels_reencoded = 0;
    std::vector<std::string> outputs;   // the EXR files written
    std::vector<std::string> warnings;  // e.g. a mask name that matches nothing; the CLI prints them
};

class Frame {
public:
    Frame(FrameSources sources, FrameTargets targets, FrameOptions options);

    // Reads the input files (each once, however often it is named). Idempotent; prepare() calls it.
    // A batch calls it on its reader thread so decoding overlaps the other frames' compositing.
    // With `scene`, decodes only the chunks this frame's decals can reach (frame_region.hpp) when
    // the camera is known before any pixel (explicit, sidecar or header) and neither a preview nor
    // --add-channels needs every pixel; the rest are copied from the input when written.
    void read(const DecalScene* scene = nullptr);

    // Reads every chunk and has writeBack() re-encode every chunk, as for a frame whose decals
    // change all of them, instead of copying the input: what batch --io-only measures.
    void readAsIfEverythingChanged();

    // Maps channels, adds requested channels, decides where each changed file goes (and refuses
    // to overwrite an input), extracts the planes, resolves the camera, settles the depth and normal
    // conventions and the pixel filter (once per sequence when `sequence` is given) and evaluates the
    // decal masks.
    // `scene` is the whole scene; animated decals are taken at FrameOptions::frame_number.
    // Throws Error naming the file and field; nothing is written.
    void prepare(const DecalScene& scene, SequenceConventions* sequence = nullptr);

    // Blends this frame's decals into its planes with `compositor` (which holds the scene's
    // textures: Compositor::setScene with the same scene), then stores the changed attributes into
    // the EXR channels they came from.
    void composite(Compositor& compositor);

    // Writes every output (and the preview) to a temporary beside it and renames them into place
    // only when all are complete, so a failure leaves none behind. Returns the EXRs written.
    // The same as stageOutputs() then commitOutputs().
    const std::vector<std::string>& writeBack();

    // writeBack() in two halves, so that frames can be encoded on several threads and still land in
    // order: stageOutputs() writes every temporary (the encoding: nearly all of a write's time),
    // commitOutputs() renames them into place. A frame destroyed before its commit removes them.
    void stageOutputs();
    const std::vector<std::string>& commitOutputs();

    // The outputs prepare() decided: input file index -> path.
    const std::map<int, std::string>& outputs() const { return outputs_; }
    const FrameReport& report() const { return report_; }
    const GBuffer& gbuffer() const { return gbuffer_; }
    const Camera& camera() const { return camera_; }
    const std::vector<ExrImage>& files() const { return files_; }
    // False when no decal is alive on this frame: composite() leaves the planes as they are.
    bool hasDecals() const { return !decals_.empty(); }

private:
    // This frame's decals: the scene's, at FrameOptions::frame_number when it animates.
    std::vector<Decal> frameDecals(const DecalScene& scene) const;
    // The chunks read(scene) decodes (everything when that cannot be known before the pixels).
    ExrReadRegion readRegion(const DecalScene& scene) const;
    // Refuses (Error(Usage)) a scene an output's input already holds unless FrameTargets::force;
    // keeps the record each output will carry (provenance.hpp).
    void recordProvenance(const DecalScene& scene);
    // How messages name this frame: FrameOptions::label, else the first input.
    const std::string& label() const { return options_.label.empty() ? sources_.inputs.front() : options_.label; }
    // A preview or the caller (FrameTargets::every_pixel) looks at every pixel of the planes.
    bool showsPixels() const { return !targets_.preview.empty() || targets_.every_pixel; }

    FrameSources sources_;
    FrameTargets targets_;
    FrameOptions options_;
    std::vector<ExrImage> files_;
    FileRoles roles_;
    bool read_ = false, prepared_ = false;
    std::vector<Decal> decals_;          // this frame's decals
    bool animated_ = false;              // decals_ differ from the scene's: the compositor gets them
    std::vector<Attribute> attributes_;  // what compositing may change
    std::map<int, std::string> outputs_;
    GBuffer gbuffer_;
    std::optional<GBuffer> before_;  // for the preview
    Camera camera_;
    FrameBeauty beauty_;
    std::map<int, ProvenanceRecord> provenance_;  // per output file: what writeBack() records in its header
    std::optional<StagedOutputs> staged_;         // between stageOutputs() and commitOutputs()
    FrameReport report_;
};

}  // namespace decalcomp
