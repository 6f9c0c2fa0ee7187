// decalcomp-gbuffer-gen: ray-casts an analytic scene into an OpenEXR G-buffer plus a camera JSON
// sidecar. Thin: parse, render with decalcomp::synth, lay out (gbuffer_to_exr), write.
// Exit codes as decalcomp's: 0 ok, 2 usage, 3 input, 5 output (decalcomp::ErrorKind), 1 internal.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>

#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_io.hpp"
#include "decalcomp/synth.hpp"
#include "gbuffer_to_exr.hpp"

namespace {

using namespace decalcomp;

struct Options {
    std::string scene = "demo";
    std::uint32_t seed = 1;
    int width = 320, height = 240;
    std::string naming = "blender";
    std::string layer = "ViewLayer";
    std::string depth = "planar";
    bool reversed_z = false;
    bool half = false;
    bool no_position = false;
    std::string compression = "zip";
    bool multipart = false;
    bool header_camera = false;
    std::string output;
    std::string camera_json;
};

Error usageError(const std::string& message) { return Error(ErrorKind::Usage, message); }

// A camera outside the random scene's extent (about 10 units around the origin), looking at it.
Camera randomSceneCamera(int width, int height) {
    Camera c;
    c.world_to_camera = lookAt({16.0, -20.0, 12.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
    c.projection = perspectiveProjection(0.87, double(width) / height, 0.1, 200.0);
    c.source = "synthetic random-scene camera";
    return c;
}

// "out.exr" -> "out.camera.json" beside it.
std::string defaultCameraPath(const std::string& exr) {
    std::filesystem::path p(exr);
    return (p.parent_path() / (p.stem().string() + ".camera.json")).string();
}

int run(const Options& o, bool seed_given, bool layer_given) {
    if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
        throw usageError(fmt::format("--width/--height: {}x{} is outside 1..16384", o.width, o.height));
    if (seed_given && o.scene != "random") throw usageError("--seed applies only to --scene random");
    if (o.reversed_z && o.depth != "ndc") throw usageError("--reversed-z applies only to --depth ndc");
    if (layer_given && o.naming != "blender") throw usageError("--layer applies only to --naming blender");
    if (o.no_position && o.depth == "position")
        throw usageError("--no-position cannot be combined with --depth position");
    if (o.layer.empty()) throw usageError("--layer: empty view-layer name");

    const DepthConvention depth = *depthConventionFromName(o.depth);  // CLI11 checked the set
    const synth::Scene scene = o.scene == "demo" ? synth::demoScene() : synth::randomScene(o.seed);
    const Camera camera = o.scene == "demo" ? synth::demoCamera(o.width, o.height)
                                            : randomSceneCamera(o.width, o.height);
    synth::RenderOptions render;
    render.width = o.width;
    render.height = o.height;
    render.depth = depth;
    render.reversed_z = o.reversed_z;
    // A position-convention file carries no depth pass, so readers take depth from the position.
    render.with_depth = depth != DepthConvention::Position;
    GBuffer gbuffer = synth::render(scene, camera, render);
    if (o.no_position) gbuffer.planes.erase(Attribute::Position);

    static const std::map<std::string, Imf::Compression> compressions = {
        {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION}, {"none", Imf::NO_COMPRESSION}};
    gen::ExrLayoutOptions layout;
    layout.naming = o.naming == "blender" ? gen::Naming::Blender : gen::Naming::Generic;
    layout.layer = o.layer;
    layout.half = o.half;
    layout.compression = compressions.at(o.compression);
    layout.multipart = o.multipart;
    if (o.header_camera) layout.header_camera = camera;

    writeExrAtomic(gen::gbufferToExr(gbuffer, layout), o.output);
    saveCameraJson(camera, o.width, o.height, o.camera_json.empty() ? defaultCameraPath(o.output) : o.camera_json);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Ray-casts an analytic scene into an OpenEXR G-buffer and a camera JSON sidecar.",
                 "decalcomp-gbuffer-gen"};
    Options o;
    app.add_option("--scene", o.scene, "Scene: demo (floor, wall, sphere, box) or random")
        ->check(CLI::IsMember({"demo", "random"}))
        ->capture_default_str();
    auto* seed = app.add_option("--seed", o.seed, "Seed for --scene random")->capture_default_str();
    app.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels")->capture_default_str();
    app.add_option("--naming", o.naming,
                   "Channel names: blender (<layer>.Depth.Z, .DiffCol.RGB, .Normal.XYZ, .Position.XYZ, "
                   ".IndexOB.X, .Combined.RGBA) or generic (Z, albedo.RGB, N.XYZ, P.XYZ, id, roughness, "
                   "metallic, RGBA)")
        ->check(CLI::IsMember({"blender", "generic"}))
        ->capture_default_str();
    auto* layer = app.add_option("--layer", o.layer, "Blender view-layer name")->capture_default_str();
    app.add_option("--depth", o.depth,
                   "Depth pass convention: planar, radial, ndc, or position (no depth pass; the position "
                   "pass carries the geometry, NaN on background)")
        ->check(CLI::IsMember({"planar", "radial", "ndc", "position"}))
        ->capture_default_str();
    app.add_flag("--reversed-z", o.reversed_z, "With --depth ndc: near = 1, far = 0");
    app.add_flag("--half", o.half, "Store albedo, normal, beauty, roughness and metallic as HALF (depth and "
                                   "position stay FLOAT)");
    app.add_flag("--no-position", o.no_position,
                 "Leave out the position pass (it is most of a file's size: float noise compresses poorly)");
    app.add_option("--compression", o.compression, "EXR compression")
        ->check(CLI::IsMember({"zip", "piz", "none"}))
        ->capture_default_str();
    app.add_flag("--multipart", o.multipart,
                 "One part per pass (part name = pass name, channel names without the prefix)");
    app.add_flag("--header-camera", o.header_camera,
                 "Also write the camera as worldToCamera/worldToNDC/clipNear/clipFar header attributes");
    app.add_option("-o,--output", o.output, "Output EXR file")->required();
    app.add_option("--camera", o.camera_json, "Camera JSON file (default: beside the EXR, <stem>.camera.json)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);  // prints the message and usage hint
        return int(ErrorKind::Usage);
    }

    try {
        return run(o, seed->count() > 0, layer->count() > 0);
    } catch (const Error& e) {
        std::cerr << "decalcomp-gbuffer-gen: " << e.what() << "\n";
        return int(e.kind());
    } catch (const std::exception& e) {
        std::cerr << "decalcomp-gbuffer-gen: internal error: " << e.what() << "\n";
        return 1;
    }
}
