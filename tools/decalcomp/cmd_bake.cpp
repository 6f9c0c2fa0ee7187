// decalcomp bake: the UV-space layers of a scene's bake-mode texture-space decals, as EXR and PNG
// files an artist can paint over or reuse ("baked"; docs/texture-space.md "Bake mode").
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <set>

#include "commands.hpp"
#include "decalcomp/bake.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::cli {

namespace {

struct BakeFlags {
    std::string scene, output, device, decal;
    SceneOptions scene_options;
    bool no_png = false, quiet = false;
};

// A decal name as a file name: anything but letters, digits, '.', '-' and '_' becomes '_'.
std::string fileStem(const std::string& name) {
    std::string out;
    for (char c : name) out += std::isalnum((unsigned char)c) || c == '.' || c == '-' || c == '_' ? c : '_';
    return out.empty() || out[0] == '.' ? "_" + out : out;
}

// Every file the scene read: an output may be none of them.
std::vector<std::string> sceneInputs(const BakeFlags& flags, const DecalScene& scene) {
    std::vector<std::string> read = {flags.scene};
    for (const RestMesh& mesh : scene.meshes) read.push_back(mesh.source);
    for (const Texture2D& texture : scene.textures) read.push_back(texture.source);
    return read;
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
    auto flags = std::make_shared<BakeFlags>();
    CLI::App* cmd = app.add_subcommand(
        "bake", "Bake the scene's bake-mode texture-space decals into UV-space layers (EXR, and PNG for the albedo)");
    cmd->add_option("--decals", flags->scene, "Decal scene JSON (docs/scene-format.md)")->required();
    cmd->add_option("-o,--output", flags->output,
                    "Folder for DECAL.exr (float RGBA albedo, orm.*, emission.*) and DECAL.png (8-bit albedo)")
        ->required();
    cmd->add_option("--decal", flags->decal, "Bake only the decal of this name");
    cmd->add_flag("--no-png", flags->no_png, "Write only the EXR files");
    cmd->add_option("--device", flags->device, "OpenCL device: index, gpu, cpu or part of its name (default: GPU, else CPU)");
    cmd->add_flag("-q,--quiet", flags->quiet, "Print nothing on success");
    addOcioOption(*cmd, flags->scene_options.ocio_config);
    return [flags] {
        const DecalScene scene = loadScene(flags->scene, flags->scene_options);
        std::vector<const Decal*> decals;
        for (const Decal& d : scene.decals) {
            if (d.space != DecalSpace::ObjectRest || d.rest_mode != RestMode::Bake) continue;
            if (!flags->decal.empty() && d.name != flags->decal) continue;
            if (d.baked) {
                std::cerr << fmt::format("decalcomp: warning: {}: decal '{}' reads its \"baked\" file; not baked again\n",
                                         flags->scene, d.name);
                continue;
            }
            decals.push_back(&d);
        }
        if (decals.empty())
            throw inputError(fmt::format("{}: no decal to bake{}: give texture-space decals \"mode\": \"bake\"",
                                         flags->scene, flags->decal.empty() ? "" : " named '" + flags->decal + "'"));
        std::error_code ec;
        if (std::filesystem::exists(flags->output, ec) && !std::filesystem::is_directory(flags->output, ec))
            throw Error(ErrorKind::Usage, fmt::format("{}: --output: not a folder (bake writes one EXR and PNG per decal)",
                                                      flags->output));
        // Outputs are checked before any work: distinct, and never a file the scene reads.
        const std::vector<std::string> read = sceneInputs(*flags, scene);
        std::set<std::string> stems;
        for (const Decal* d : decals) {
            const std::string stem = fileStem(d->name);
            if (!stems.insert(stem).second)
                throw Error(ErrorKind::Usage, fmt::format("{}: two bake decals write {}.exr; give them distinct names",
                                                          flags->scene, stem));
            for (const char* ext : {".exr", ".png"}) {
                const std::string path = (std::filesystem::path(flags->output) / (stem + ext)).string();
                for (const std::string& input : read)
                    if (!input.empty() && sameFile(path, input))
                        throw Error(ErrorKind::Usage,
                                    fmt::format("{}: --output: would overwrite {}, which the scene reads", path, input));
            }
        }
        std::filesystem::create_directories(flags->output, ec);
        if (ec) throw outputError(fmt::format("{}: cannot create the output folder: {}", flags->output, ec.message()));
        ComputeDevice device(flags->device);
        for (const Decal* d : decals) {
            const BakedLayers layers = bakeDecal(device, scene, *d);
            const std::filesystem::path stem = std::filesystem::path(flags->output) / fileStem(d->name);
            const std::string exr = stem.string() + ".exr", png = flags->no_png ? "" : stem.string() + ".png";
            writeBakedLayers(layers, scene.meshes.at(std::size_t(d->rest_mesh)), d->name, exr, png);
            if (!flags->quiet)
                std::cout << fmt::format("{}{}{}: decal '{}', {}x{} texels, dilation {}, on {}\n", exr,
                                         png.empty() ? "" : ", ", png, d->name, layers.width, layers.height,
                                         d->bake_dilation, device.info().name);
        }
    };
}

}  // namespace decalcomp::cli
