// `decalcomp bake` as a library call (bake.hpp bakeFiles): which decals, where their files go, the
// checks before any work, then one bake and one EXR (and PNG) per decal.
#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <set>

#include "decalcomp/bake.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp {

namespace {

// A decal name as a file name: anything but letters, digits, '.', '-' and '_' becomes '_'.
std::string fileStem(const std::string& name) {
    std::string out;
    for (char c : name) out += std::isalnum((unsigned char)c) || c == '.' || c == '-' || c == '_' ? c : '_';
    return out.empty() || out[0] == '.' ? "_" + out : out;
}

// Every file the scene read: an output may be none of them.
std::vector<std::string> sceneInputs(const std::string& scene_file, const DecalScene& scene) {
    std::vector<std::string> read = {scene_file};
    for (const RestMesh& mesh : scene.meshes) read.push_back(mesh.source);
    for (const Texture2D& texture : scene.textures) read.push_back(texture.source);
    return read;
}

}  // namespace

BakeFilesResult bakeFiles(const DecalScene& scene, const BakeFilesRequest& request) {
    const std::string scene_file = request.scene_file.empty() ? scene.source : request.scene_file;
    const std::string label = scene_file.empty() ? "scene" : scene_file;
    BakeFilesResult result;
    std::vector<const Decal*> decals;
    for (const Decal& d : scene.decals) {
        if (d.space != DecalSpace::ObjectRest || d.rest_mode != RestMode::Bake) continue;
        if (!request.decal.empty() && d.name != request.decal) continue;
        if (d.baked) {
            result.warnings.push_back(
                fmt::format("{}: decal '{}' reads its \"baked\" file; not baked again", label, d.name));
            continue;
        }
        decals.push_back(&d);
    }
    if (decals.empty())
        throw inputError(fmt::format("{}: no decal to bake{}: give texture-space decals \"mode\": \"bake\"", label,
                                     request.decal.empty() ? "" : " named '" + request.decal + "'"));
    std::error_code ec;
    if (std::filesystem::exists(request.output, ec) && !std::filesystem::is_directory(request.output, ec))
        throw Error(ErrorKind::Usage, fmt::format("{}: --output: not a folder (bake writes one EXR and PNG per decal)",
                                                  request.output));
    // Outputs are checked before any work: distinct, and never a file the scene reads.
    const std::vector<std::string> read = sceneInputs(scene_file, scene);
    std::set<std::string> stems;
    for (const Decal* d : decals) {
        const std::string stem = fileStem(d->name);
        if (!stems.insert(stem).second)
            throw Error(ErrorKind::Usage,
                        fmt::format("{}: two bake decals write {}.exr; give them distinct names", label, stem));
        for (const char* ext : {".exr", ".png"}) {
            const std::string path = (std::filesystem::path(request.output) / (stem + ext)).string();
            for (const std::string& input : read)
                if (!input.empty() && sameFile(path, input))
                    throw Error(ErrorKind::Usage,
                                fmt::format("{}: --output: would overwrite {}, which the scene reads", path, input));
        }
    }
    std::filesystem::create_directories(request.output, ec);
    if (ec) throw outputError(fmt::format("{}: cannot create the output folder: {}", request.output, ec.message()));
    ComputeDevice device(request.device);
    for (const Decal* d : decals) {
        const BakedLayers layers = bakeDecal(device, scene, *d);
        const std::filesystem::path stem = std::filesystem::path(request.output) / fileStem(d->name);
        BakedFile file{d->name, stem.string() + ".exr", request.png ? stem.string() + ".png" : "",
                       layers.width, layers.height, d->bake_dilation, device.info().name};
        writeBakedLayers(layers, scene.meshes.at(std::size_t(d->rest_mesh)), d->name, file.exr, file.png);
        result.files.push_back(std::move(file));
    }
    return result;
}

}  // namespace decalcomp
