// decalcomp bake: the UV-space layers of a scene's bake-mode texture-space decals, as EXR and PNG
// files an artist can paint over or reuse ("baked"; docs/texture-space.md "Bake mode"). The work is
// the library's bakeFiles (bake.hpp), which the Python module's bake() runs too.
#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/bake.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::cli {

namespace {

struct BakeFlags {
    std::string scene;
    BakeFilesRequest request;
    SceneOptions scene_options;
    bool no_png = false, quiet = false;
};

}  // namespace

Command addBakeCommand(CLI::App& app) {
    auto flags = std::make_shared<BakeFlags>();
    CLI::App* cmd = app.add_subcommand(
        "bake", "Bake the scene's bake-mode texture-space decals into UV-space layers (EXR, and PNG for the albedo)");
    cmd->add_option("--decals", flags->scene, "Decal scene JSON (docs/scene-format.md)")->required();
    cmd->add_option("-o,--output", flags->request.output,
                    "Folder for DECAL.exr (float RGBA albedo, orm.*, emission.*) and DECAL.png (8-bit albedo)")
        ->required();
    cmd->add_option("--decal", flags->request.decal, "Bake only the decal of this name");
    cmd->add_flag("--no-png", flags->no_png, "Write only the EXR files");
    cmd->add_option("--device", flags->request.device,
                    "OpenCL device: index, gpu, cpu or part of its name (default: GPU, else CPU)");
    cmd->add_flag("-q,--quiet", flags->quiet, "Print nothing on success");
    addOcioOption(*cmd, flags->scene_options.ocio_config);
    return [flags] {
        const DecalScene scene = loadScene(flags->scene, flags->scene_options);
        BakeFilesRequest request = flags->request;
        request.png = !flags->no_png;
        request.scene_file = flags->scene;
        const BakeFilesResult result = bakeFiles(scene, request);
        for (const std::string& w : result.warnings) std::cerr << "decalcomp: warning: " << w << "\n";
        if (flags->quiet) return;
        for (const BakedFile& f : result.files)
            std::cout << fmt::format("{}{}{}: decal '{}', {}x{} texels, dilation {}, on {}\n", f.exr,
                                     f.png.empty() ? "" : ", ", f.png, f.decal, f.width, f.height, f.dilation, f.device);
    };
}

}  // namespace decalcomp::cli
