#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>
#include <optional>

#include "commands.hpp"
#include "decalcomp/provenance.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/frame_beauty.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/sequence_conventions.hpp"

namespace decalcomp::cli {

namespace {

struct InfoFlags {
    std::vector<std::string> inputs, passes;
    std::string camera;
    MappingOptions mapping;
    std::vector<std::string> channels;
    std::string depth;
};

const char* typeName(SampleType t) {
    switch (t) {
        case SampleType::Uint: return "uint";
        case SampleType::Half: return "half";
        case SampleType::Float: return "float";
    }
    return "?";
}

void printMatrix(const std::string& title, const glm::dmat4& m) {
    std::cout << "  " << title << ":\n";
    for (int r = 0; r < 4; ++r) std::cout << fmt::format("    [{:12.6f} {:12.6f} {:12.6f} {:12.6f}]\n", m[0][r], m[1][r], m[2][r], m[3][r]);
}

std::string windowText(const Imath::Box2i& w) {
    return fmt::format("({},{})-({},{})", w.min.x, w.min.y, w.max.x, w.max.y);
}

void printFile(const ExrImage& image) {
    std::cout << image.path << ": " << image.parts.size() << " part(s)\n";
    for (std::size_t p = 0; p < image.parts.size(); ++p) {
        const ExrPart& part = image.parts[p];
        const Imath::Box2i dw = part.header.dataWindow(), display = part.header.displayWindow();
        std::cout << fmt::format("part {} '{}': {}x{} data window {}{}, {} channels\n", p,
                                 part.header.hasName() ? part.header.name() : "", part.width, part.height,
                                 windowText(dw), dw == display ? "" : " (display window " + windowText(display) + ")",
                                 part.channels.size());
        for (const ExrChannel& c : part.channels) std::cout << fmt::format("  {} ({})\n", c.qualified, typeName(c.type));
    }
    if (const auto record = readProvenance(image.parts.front().header, image.path)) {
        std::cout << fmt::format("composited by decalcomp {} with {} ({}): {} decal(s){}{}\n", record->version,
                                 record->scene_file.empty() ? "a scene built in code" : record->scene_file, record->scene,
                                 record->decals.size(), record->decals.empty() ? "" : ": ",
                                 fmt::join(record->decals, ", "));
        if (record->scenes.size() > 1)
            std::cout << fmt::format("  scenes composited into it, oldest first: {}\n", fmt::join(record->scenes, ", "));
    }
}

void printInfo(const InfoFlags& f) {
    const FrameFiles frame = readFrameFiles(f.inputs.front(), {f.inputs.begin() + 1, f.inputs.end()},
                                            parsePassFlags(f.passes));
    const std::vector<ExrImage>& files = frame.files;
    for (const ExrImage& image : files) printFile(image);
    ChannelMapping mapping = mapChannels(files, f.mapping, frame.roles);
    std::cout << "profile: " << mapping.profile << "\n";
    std::cout << "profile scores:";
    for (const ProfileCandidate& c : mapping.candidates) std::cout << fmt::format(" {} {:g}", c.name, c.score);
    std::cout << "\n";
    for (const std::string& note : mapping.notes) std::cout << "  " << note << "\n";
    for (const auto& [attribute, refs] : mapping.attributes) {
        std::string names;
        for (const ChannelRef& ref : refs)
            names += (names.empty() ? "" : ", ") +
                     files[std::size_t(ref.file)].parts[std::size_t(ref.part)].channels[std::size_t(ref.channel)].qualified;
        const std::string where = files.size() > 1 ? " (" + files[std::size_t(refs.front().file)].path + ")" : "";
        std::cout << fmt::format("  {:<10} <- {}{}\n", attributeName(attribute), names, where);
    }

    std::optional<GBuffer> gbuffer;
    try {
        gbuffer = extractGBuffer(files, mapping);
        const FrameWindow window = frameWindow(files, mapping);
        std::cout << fmt::format("g-buffer window: {} of display window {} (from {})\n", windowText(window.data),
                                 windowText(window.display), window.owner);
    } catch (const Error& e) {
        std::cout << "g-buffer: cannot extract (" << e.what() << ")\n";
    }
    std::optional<Camera> camera;
    CameraSolveReport solve;
    try {
        camera = gbuffer ? resolveCamera(files, *gbuffer, f.camera, &solve) : resolveCamera(files.front(), f.camera);
        std::cout << "camera: " << camera->source << (camera->isOrthographic() ? " (orthographic)" : " (perspective)")
                  << fmt::format(", near {:.6g}, far {:.6g}\n", camera->nearPlane(), camera->farPlane());
        if (solve.points > 0) {
            std::cout << "camera solve: " << solve.summary() << "\n";
            std::cout << "  near/far: " << solve.near_far_rule << "\n";
            for (const std::string& note : solve.notes) std::cout << "  " << note << "\n";
        }
        printMatrix("world_to_camera", camera->world_to_camera);
        printMatrix("projection", camera->projection);
    } catch (const Error& e) {
        std::cout << "camera: none (" << e.what() << ")\n";
    }
    if (gbuffer && camera) {
        const DepthCheck check = settleDepthConvention(*gbuffer, mapping, *camera);
        std::cout << "depth check: " << check.summary() << "\n";
        if (gbuffer->has(Attribute::Normal))
            std::cout << "normal check: " << settleNormalEncoding(*gbuffer, mapping, *camera).summary() << "\n";
    }
    std::cout << "depth convention: " << depthConventionName(mapping.depth_convention)
              << (mapping.reversed_z ? " (reversed-z)" : "") << "\n";
    if (mapping.attributes.count(Attribute::Normal))
        std::cout << "normals: " << normalSpaceName(mapping.normals.space) << " space, "
                  << (mapping.normals.packed ? "packed" : "signed") << "\n";
    std::cout << "beauty:\n";
    for (const std::string& line : findBeautyPasses(files, mapping, f.mapping).describe()) std::cout << "  " << line << "\n";
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
    auto flags = std::make_shared<InfoFlags>();
    CLI::App* cmd = app.add_subcommand("info", "Show an EXR's channels, the matched profile, camera and depth convention");
    cmd->add_option("inputs", flags->inputs, "EXR file(s); several are pooled as in composite")->required();
    cmd->add_option("--camera", flags->camera, "Camera JSON sidecar");
    addMappingOptions(*cmd, flags->mapping, flags->channels, flags->depth);
    addPassOptions(*cmd, flags->passes);
    return [flags] {
        finishMappingOptions(flags->mapping, flags->channels, flags->depth);
        printInfo(*flags);
    };
}

}  // namespace decalcomp::cli
