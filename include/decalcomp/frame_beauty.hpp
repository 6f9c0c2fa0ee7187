#pragma once
// A frame's beauty step (docs/cli.md "Beauty"): which light passes the file has (as its profile
// declares them, decalcomp/beauty.hpp), whether this frame rebuilds its beauty, the planes the
// shading kernel updates, and storing them back into their channels.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/beauty.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"

namespace decalcomp {

// One RGB pass found in the frame's files.
struct FoundPass {
    std::string role;   // "beauty", "direct", "indirect", "total", "colour", or an added pass's name
    std::string lobe;   // "diffuse", ... ("" for the beauty and added passes)
    std::string name;   // the channels as found: "ViewLayer.DiffDir.{R,G,B}"
    std::vector<ChannelRef> refs;
};

// The profile's beauty model against the frame's channels.
struct BeautyPasses {
    std::string profile;        // the mapping's profile
    BeautyModel model;          // as the profile declares it (empty: it declares none)
    std::optional<FoundPass> beauty;
    std::vector<FoundPass> light;     // the albedo lobe's terms: direct, indirect, then totals
    std::vector<FoundPass> others;    // the other lobes' and the added passes found (for `info`)
    std::vector<std::string> missing; // the albedo lobe's passes not found, as "DiffDir (ViewLayer.DiffDir.{R,G,B})"
    bool complete() const { return beauty && !light.empty() && missing.empty(); }
    // "blender: ViewLayer.Combined.{R,G,B} = ... (light divided by colour)", one line per fact.
    std::vector<std::string> describe() const;
};
// Throws Error(Input) for an unreadable --profile-file (as the mapping did before).
BeautyPasses findBeautyPasses(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                              const MappingOptions& options);

// What the beauty step did, for the CLI.
struct BeautyReport {
    BeautyMode mode = BeautyMode::Auto;
    bool rebuilt = false;          // the beauty was rebuilt on this frame
    std::string summary;           // "rebuilt ViewLayer.Combined from ... (blender, divided light)"
    std::size_t changed_samples = 0;  // beauty and light samples rewritten
    std::optional<LightFit> fit;   // --relight: the fitted direct light
};

class FrameBeauty {
public:
    // Decides whether the frame rebuilds its beauty: warns (auto) or throws Error(Input) (on) when
    // passes are missing; `outputs` are the files the run writes (the beauty must be in one).
    void prepare(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const MappingOptions& mapping_options,
                 const BeautyOptions& options, const std::vector<Attribute>& attributes,
                 const std::map<int, std::string>& outputs, const std::string& label,
                 std::vector<std::string>& warnings);
    // Reads the planes over the G-buffer's window (and fits the light for --relight).
    void read(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const GBuffer& gbuffer,
              const Camera& camera, bool keep_before);
    // The planes for Compositor::composite; nullptr when the frame does not rebuild.
    BeautyPlanes* planes() { return planes_ ? &*planes_ : nullptr; }
    // Writes the updated planes into their channels; returns the samples changed.
    std::size_t store(std::vector<ExrImage>& files, const ChannelMapping& mapping);
    const Plane* before() const { return before_ ? &*before_ : nullptr; }
    const Plane* after() const { return planes_ ? &planes_->beauty : nullptr; }
    const BeautyReport& report() const { return report_; }
    const BeautyPasses& passes() const { return passes_; }

private:
    BeautyPasses passes_;
    std::optional<BeautyPlanes> planes_;
    std::optional<Plane> before_;  // for the preview
    bool rebuild_ = false, relight_ = false, emission_ = false;
    BeautyReport report_;
};

}  // namespace decalcomp
