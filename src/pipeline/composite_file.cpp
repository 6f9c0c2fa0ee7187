#include <fmt/format.h>

#include <filesystem>

#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

Camera resolveCamera(const ExrImage& image, const std::string& camera_json) {
    if (!camera_json.empty()) return loadCameraJson(camera_json);
    for (const ExrPart& part : image.parts)
        if (auto camera = cameraFromExrHeader(part.header, image.path)) return *camera;
    throw inputError(fmt::format("{}: no camera: the header has no worldToCamera/worldToNDC; pass --camera camera.json",
                                 image.path));
}

void checkNotOverwritingInput(const std::string& input, const std::string& output, bool allowed) {
    std::error_code ec;
    const bool same = fs::exists(output, ec) && fs::equivalent(input, output, ec);
    if (same && !allowed)
        throw Error(ErrorKind::Usage, fmt::format("{}: output is the input file; pass --overwrite-input to replace it", output));
}

CompositeReport compositeFile(const CompositeRequest& request) {
    checkNotOverwritingInput(request.input, request.output, request.overwrite_input);
    CompositeReport report;
    ExrImage image = readExr(request.input);
    report.mapping = mapChannels(image, request.mapping);
    if (!report.mapping.attributes.count(Attribute::Albedo))
        throw inputError(fmt::format("{}: no albedo channels found (profile {}); map them with --channel albedo=R,G,B",
                                     request.input, report.mapping.profile));
    const GBuffer before = extractGBuffer(image, report.mapping);
    const Camera camera = resolveCamera(image, request.camera_json);
    report.camera_source = camera.source;
    const DecalScene scene = loadScene(request.scene);

    ComputeDevice device(request.device);
    report.device = device.info().name;
    Compositor compositor(device);
    compositor.setScene(scene);
    GBuffer after = before;
    report.stats = compositor.composite(after, camera, CompositeOptions{request.binned});
    storeAttribute(image, report.mapping, Attribute::Albedo, after.planes.at(Attribute::Albedo));

    // Preview to a temporary name first, so a failed EXR write leaves neither file behind.
    std::string preview_tmp;
    if (!request.preview.empty()) {
        preview_tmp = request.preview + ".partial.png";
        writeAlbedoPreview(before, after, preview_tmp);
    }
    try {
        writeExrAtomic(image, request.output);
    } catch (...) {
        if (!preview_tmp.empty()) fs::remove(preview_tmp);
        throw;
    }
    if (!preview_tmp.empty()) {
        std::error_code ec;
        fs::rename(preview_tmp, request.preview, ec);
        if (ec) {
            fs::remove(preview_tmp);
            throw outputError(fmt::format("{}: cannot write preview: {}", request.preview, ec.message()));
        }
    }
    return report;
}

}  // namespace decalcomp
