#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp::cli {

namespace {

struct InfoFlags {
    std::string input, camera;
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

void printInfo(const InfoFlags& f) {
    const ExrImage image = readExr(f.input);
    std::cout << f.input << ": " << image.parts.size() << " part(s)\n";
    for (std::size_t p = 0; p < image.parts.size(); ++p) {
        const ExrPart& part = image.parts[p];
        std::cout << fmt::format("part {} '{}': {}x{} data window, {} channels\n", p,
                                 part.header.hasName() ? part.header.name() : "", part.width, part.height,
                                 part.channels.size());
        for (const ExrChannel& c : part.channels) std::cout << fmt::format("  {} ({})\n", c.qualified, typeName(c.type));
    }
    const ChannelMapping mapping = mapChannels(image, f.mapping);
    std::cout << "profile: " << mapping.profile << "\n";
    for (const std::string& note : mapping.notes) std::cout << "  " << note << "\n";
    for (const auto& [attribute, refs] : mapping.attributes) {
        std::string names;
        for (const ChannelRef& ref : refs)
            names += (names.empty() ? "" : ", ") + image.parts[std::size_t(ref.part)].channels[std::size_t(ref.channel)].qualified;
        std::cout << fmt::format("  {:<10} <- {}\n", attributeName(attribute), names);
    }
    std::cout << "depth convention: " << depthConventionName(mapping.depth_convention)
              << (mapping.reversed_z ? " (reversed-z)" : "") << "\n";
    try {
        const Camera camera = resolveCamera(image, f.camera);
        std::cout << "camera: " << camera.source << (camera.isOrthographic() ? " (orthographic)" : " (perspective)")
                  << fmt::format(", near {:.6g}, far {:.6g}\n", camera.nearPlane(), camera.farPlane());
        printMatrix("world_to_camera", camera.world_to_camera);
        printMatrix("projection", camera.projection);
    } catch (const Error& e) {
        std::cout << "camera: none (" << e.what() << ")\n";
    }
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
    auto flags = std::make_shared<InfoFlags>();
    CLI::App* cmd = app.add_subcommand("info", "Show an EXR's channels, the matched profile, camera and depth convention");
    cmd->add_option("input", flags->input, "EXR file")->required();
    cmd->add_option("--camera", flags->camera, "Camera JSON sidecar");
    addMappingOptions(*cmd, flags->mapping, flags->channels, flags->depth);
    return [flags] {
        finishMappingOptions(flags->mapping, flags->channels, flags->depth);
        printInfo(*flags);
    };
}

}  // namespace decalcomp::cli
