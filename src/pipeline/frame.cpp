#include "decalcomp/frame.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "decalcomp/error.hpp"
#include "decalcomp/frame_region.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/pipeline.hpp"
#include "images/image_codecs.hpp"
#include "pipeline/frame_pixel_filter.hpp"
#include "pipeline/frame_texture_space.hpp"

namespace decalcomp {

namespace {

// The depth pass's channel as `info` shows it ("ViewLayer.Depth.Z"), "" without one.
std::string depthChannelName(const std::vector<ExrImage>& files, const ChannelMapping& mapping) {
    const auto found = mapping.attributes.find(Attribute::Depth);
    if (found == mapping.attributes.end() || found->second.empty()) return "";
    const ChannelRef& ref = found->second.front();
    return files.at(std::size_t(ref.file)).parts.at(std::size_t(ref.part)).channels.at(std::size_t(ref.channel)).qualified;
}

// False when read(scene) found every decal off screen and decoded nothing.
bool anyChunkDecoded(const std::vector<ExrImage>& files) {
    for (const ExrImage& image : files)
        for (const ExrPart& part : image.parts)
            for (int chunk = 0; chunk < part.chunks.count(); ++chunk)
                if (part.isDecoded(chunk)) return true;
    return false;
}

}  // namespace

Frame::Frame(FrameSources sources, FrameTargets targets, FrameOptions options)
    : sources_(std::move(sources)), targets_(std::move(targets)), options_(std::move(options)) {
    if (sources_.inputs.empty()) throw Error(ErrorKind::Usage, "a frame needs at least one input EXR");
}

std::vector<Decal> Frame::frameDecals(const DecalScene& scene) const {
    return options_.frame_number && isAnimated(scene) ? decalsAtFrame(scene.decals, *options_.frame_number)
                                                      : scene.decals;
}

ExrReadRegion Frame::readRegion(const DecalScene& scene) const {
    const ExrReadRegion everything;
    // A preview shows every pixel; a new channel is written into every chunk.
    if (showsPixels() || !options_.mapping.add_channels.empty()) return everything;
    if (hasTextureSpaceDecals(scene)) return everything;  // they go wherever their object is seen
    const std::vector<Decal> decals = frameDecals(scene);
    if (decals.empty()) return ExrReadRegion{false, {}};
    std::vector<std::string> paths = sources_.inputs;
    for (const auto& [attribute, path] : sources_.pass_files) paths.push_back(path);
    std::optional<Camera> camera = sources_.camera;
    if (!camera && !sources_.camera_json.empty()) camera = loadCameraJson(sources_.camera_json);
    const std::vector<Imf::Header> first = readExrHeaders(paths.front());
    for (std::size_t i = 0; !camera && i < paths.size(); ++i)
        for (const Imf::Header& header : i == 0 ? first : readExrHeaders(paths[i]))
            if (!camera) camera = cameraFromExrHeader(header, paths[i]);
    if (!camera) return everything;  // solved from the position pass: needs its pixels
    return decalReadRegion(decals, *camera, first.front().displayWindow());
}

void Frame::read(const DecalScene* scene) {
    if (read_) return;
    FrameFiles frame = readFrameFiles(sources_.inputs.front(), {sources_.inputs.begin() + 1, sources_.inputs.end()},
                                      sources_.pass_files, scene ? readRegion(*scene) : ExrReadRegion{});
    files_ = std::move(frame.files);
    roles_ = frame.roles;
    read_ = true;
}

void Frame::readAsIfEverythingChanged() {
    read();
    for (ExrImage& image : files_)
        for (ExrPart& part : image.parts) part.changed.assign(std::size_t(part.chunks.count()), 1);
}

void Frame::prepare(const DecalScene& scene, SequenceConventions* sequence) {
    read(&scene);
    const std::string& input = sources_.inputs.front();
    ChannelMapping& mapping = report_.mapping;
    mapping = mapChannels(files_, options_.mapping, roles_);
    if (!mapping.attributes.count(Attribute::Albedo))
        throw inputError(fmt::format("{}: no albedo channels found (profile {}); map them with --channel albedo=R,G,B",
                                     input, mapping.profile));
    addAttributeChannels(files_, mapping, options_.mapping);

    // What changes, and where each changed file goes, decided (and checked) before any work.
    animated_ = options_.frame_number && isAnimated(scene);
    decals_ = frameDecals(scene);
    attributes_ = compositedAttributes(scene);
    report_.warnings =
        missingAttributeWarnings(attributes_, mapping, label());
    report_.warnings.insert(report_.warnings.end(), mapping.warnings.begin(), mapping.warnings.end());
    report_.warnings.insert(report_.warnings.end(), scene.warnings.begin(), scene.warnings.end());
    outputs_ = outputPaths(files_, mapping, attributes_, targets_.output);
    recordProvenance(scene);
    RunFiles run;
    for (const auto& [file, path] : outputs_) run.exr_outputs.push_back(path);
    run.preview = targets_.preview;
    for (const ExrImage& image : files_) run.exr_inputs.push_back(image.path);
    run.other_reads = {scene.source, scene.colour_config, sources_.camera_json, sources_.camera_file};
    for (const std::string& profile : options_.mapping.profile_files) run.other_reads.push_back(profile);
    for (const Texture2D& texture : scene.textures) run.other_reads.push_back(texture.source);
    for (const CryptomatteLayer& layer : cryptomatteLayers(files_))  // sidecar manifests ("" for none)
        run.other_reads.push_back(cryptomatteSidecarPath(layer));
    checkRunFiles(run, targets_.overwrite_input);
    beauty_.prepare(files_, mapping, options_.mapping, options_.beauty, attributes_, outputs_, label(),
                    report_.warnings);
    report_.beauty = beauty_.report();

    // (A scene built in code with no decals, as batch --io-only passes, asked for nothing.)
    if (decals_.empty() && !(scene.decals.empty() && scene.source.empty()))
        report_.warnings.push_back(
            scene.decals.empty()
                ? fmt::format("{}: decals: the scene has no decals; the output is the input unchanged", scene.source)
                : fmt::format("{}: no decal is alive on this frame (their frames, fade_in, fade_out); the output is "
                              "the input unchanged",
                              label()));
    if (!decals_.empty() && !anyChunkDecoded(files_)) {
        report_.warnings.push_back(fmt::format(
            "{}: no decal changed any pixel: check the decals' positions and the camera: no decal is on screen (their "
            "volumes project outside the camera's view); the output is the input unchanged",
            label()));
        decals_.clear();
    }
    if (decals_.empty() && !showsPixels()) {  // nothing alive (or visible) on this frame: written as read
        prepared_ = true;
        return;
    }
    if (!mapping.attributes.count(Attribute::Depth) && !mapping.attributes.count(Attribute::Position))
        throw inputError(fmt::format("{}: no depth pass found (profile {}): name its channel with --channel "
                                     "depth=CHANNEL, or read it from its own file with --pass depth=FILE",
                                     input, mapping.profile));
    gbuffer_ = extractGBuffer(files_, mapping);
    CameraSolveReport solve;
    camera_ = sources_.camera ? *sources_.camera : resolveCamera(files_, gbuffer_, sources_.camera_json, &solve);
    if (solve.points > 0) report_.camera_solve = solve;
    report_.camera_source = camera_.source;
    if (sequence) {
        sequence->settle(gbuffer_, mapping, camera_, &report_.depth_check, &report_.normal_check);
    } else {
        report_.depth_check = settleDepthConvention(gbuffer_, mapping, camera_);
        report_.normal_check = settleNormalEncoding(gbuffer_, mapping, camera_);
    }
    const auto choose = [&] {
        PixelFilterChoice choice = choosePixelFilter(files_, mapping.profile, options_.mapping.profile_files, gbuffer_,
                                                     options_.pixel_filter);
        if (options_.pixel_filter_fast && choice.filter.enabled()) choice.filter.fast = true;
        return choice;
    };
    const PixelFilterChoice filter = sequence ? sequence->pixelFilter(choose) : choose();
    gbuffer_.pixel_filter = filter.filter;
    report_.pixel_filter = fmt::format("{} ({})", filter.filter.spelling(), filter.source);
    for (std::string& warning : depthWarnings(gbuffer_, camera_, depthChannelName(files_, mapping), label()))
        report_.warnings.push_back(std::move(warning));
    // Decal masks for this frame; their warnings name the first input by the label, as above.
    evaluateMasks(files_, mapping, scene, gbuffer_, &report_.warnings, {options_.label});
    settleTextureSpace(scene, decals_, mapping, options_.uv_v_down, label(), gbuffer_, report_.warnings);
    beauty_.read(files_, mapping, gbuffer_, camera_, !targets_.preview.empty());
    prepared_ = true;
}

void Frame::recordProvenance(const DecalScene& scene) {
    provenance_.clear();
    if (decals_.empty()) return;  // written as read
    for (const auto& [file, path] : outputs_) {
        const ExrImage& image = files_[std::size_t(file)];
        const auto previous = readProvenance(image.parts.front().header, image.path);
        const bool again = previous && !scene.fingerprint.empty() &&
                           std::find(previous->scenes.begin(), previous->scenes.end(), scene.fingerprint) !=
                               previous->scenes.end();
        if (again && !targets_.force)
            throw Error(ErrorKind::Usage,
                        fmt::format("{}: already composited with this scene ({} {}, decalcomp/scenes in its header); "
                                    "compositing it again stacks every decal twice: --force does it anyway",
                                    image.path, scene.source, scene.fingerprint));
        provenance_[file] = composeProvenance(scene, decals_, previous);
    }
}

void Frame::composite(Compositor& compositor) {
    if (!prepared_) throw Error(ErrorKind::Usage, "Frame::composite before Frame::prepare");
    if (decals_.empty()) return;  // nothing alive on this frame: the output is the input
    if (!targets_.preview.empty()) before_ = gbuffer_;
    if (animated_) compositor.setDecals(decals_);  // textures stay on the device
    report_.stats = compositor.composite(gbuffer_, camera_, options_.compositing, beauty_.planes());
    std::size_t changed = 0;
    for (Attribute attribute : attributes_)
        if (gbuffer_.has(attribute))
            changed += storeAttribute(files_, report_.mapping, attribute, gbuffer_.planes.at(attribute));
    report_.changed_samples = changed;
    beauty_.store(files_, report_.mapping);
    report_.beauty = beauty_.report();
    if (changed == 0)
        report_.warnings.push_back(fmt::format(
            "{}: no decal changed any pixel: check that the decals' boxes reach visible surfaces (position, size, "
            "projection axis), their masks, and the camera",
            label()));
}

const std::vector<std::string>& Frame::writeBack() {
    stageOutputs();
    return commitOutputs();
}

void Frame::stageOutputs() {
    if (!prepared_) throw Error(ErrorKind::Usage, "Frame::stageOutputs before Frame::prepare");
    if (staged_) throw Error(ErrorKind::Usage, "Frame::stageOutputs twice without Frame::commitOutputs");
    std::vector<PendingOutput> pending;
    for (const auto& [file, path] : outputs_) {
        const auto record = provenance_.find(file);
        if (record != provenance_.end()) files_[std::size_t(file)].added_attributes = provenanceAttributes(record->second);
        pending.push_back({&files_[std::size_t(file)], path});
    }
    const GBuffer& before = before_ ? *before_ : gbuffer_;
    // The preview is written to an unnamed temporary: an image module that cannot load is named
    // by the preview's own path, before anything is staged.
    if (!targets_.preview.empty()) images::imageCodecs(ErrorKind::Output, targets_.preview);
    staged_ = stageOutputsTogether(
        pending, targets_.preview.empty() ? nullptr : &targets_.preview, [&](const std::string& preview_path) {
            writePreview(before, gbuffer_, camera_, preview_path, beauty_.before(), beauty_.after());
        });
    report_.chunks_copied = staged_->stats().copied;
    report_.chunks_reencoded = staged_->stats().reencoded;
    report_.pixels_reencoded = staged_->stats().pixels_reencoded;
}

const std::vector<std::string>& Frame::commitOutputs() {
    if (!staged_) throw Error(ErrorKind::Usage, "Frame::commitOutputs before Frame::stageOutputs");
    StagedOutputs staged = std::move(*staged_);
    staged_.reset();
    staged.commit();
    report_.outputs.clear();
    for (const auto& [file, path] : outputs_) report_.outputs.push_back(path);
    return report_.outputs;
}

}  // namespace decalcomp
