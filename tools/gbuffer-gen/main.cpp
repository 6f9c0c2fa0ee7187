// decalcomp-gbuffer-gen: ray-casts an analytic scene into an OpenEXR G-buffer plus a camera JSON
// sidecar. Thin: parse, render with decalcomp::synth, lay out (gbuffer_to_exr), write.
// Exit codes as decalcomp's: 0 ok, 2 usage, 3 input, 5 output (decalcomp::ErrorKind), 1 internal.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>

#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
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
    bool per_pass = false;
    std::string data_window;  // "x0,y0,x1,y1", inclusive, display-window pixel coordinates
    std::string lens_shift;   // "sx,sy" in NDC half-units (Blender's shift x2)
    double ortho = 0.0;       // > 0: orthographic camera with this half height
    bool header_camera = false;
    bool light_passes = false;
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

// "x0,y0,x1,y1" -> box; the window may reach outside the display window (overscan) or lie inside it (crop).
Imath::Box2i parseWindow(const std::string& text) {
    int v[4];
    char tail = 0;
    if (std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &v[0], &v[1], &v[2], &v[3], &tail) != 4)
        throw usageError(fmt::format("--data-window {}: expected x0,y0,x1,y1", text));
    if (v[2] < v[0] || v[3] < v[1] || v[2] - v[0] >= 16384 || v[3] - v[1] >= 16384 || std::abs(v[0]) > 65536 ||
        std::abs(v[1]) > 65536)
        throw usageError(fmt::format("--data-window {}: empty, reversed or larger than 16384 pixels", text));
    return Imath::Box2i({v[0], v[1]}, {v[2], v[3]});
}

// "out.exr" + "depth" -> "out.depth.exr" beside it.
std::string passPath(const std::string& exr, const std::string& key) {
    std::filesystem::path p(exr);
    return (p.parent_path() / (p.stem().string() + "." + key + p.extension().string())).string();
}

int run(const Options& o, bool seed_given, bool layer_given, bool naming_given) {
    if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
        throw usageError(fmt::format("--width/--height: {}x{} is outside 1..16384", o.width, o.height));
    if (seed_given && o.scene != "random") throw usageError("--seed applies only to --scene random");
    if (o.reversed_z && o.depth != "ndc") throw usageError("--reversed-z applies only to --depth ndc");
    if (layer_given && o.naming != "blender") throw usageError("--layer applies only to --naming blender");
    if (o.no_position && o.depth == "position")
        throw usageError("--no-position cannot be combined with --depth position");
    if (o.layer.empty()) throw usageError("--layer: empty view-layer name");
    const gen::Naming naming = *gen::namingFromName(o.naming);  // CLI11 checked the set
    if (o.multipart && naming != gen::Naming::Blender && naming != gen::Naming::Generic)
        throw usageError("--multipart applies only to --naming blender and generic");
    if (o.per_pass && (o.multipart || naming_given || layer_given))
        throw usageError("--per-pass writes bare component names: it takes no --naming, --layer or --multipart");

    const DepthConvention depth = *depthConventionFromName(o.depth);  // CLI11 checked the set
    const synth::Scene scene = o.scene == "demo" ? synth::demoScene() : synth::randomScene(o.seed);
    Camera camera = o.scene == "demo" ? synth::demoCamera(o.width, o.height) : randomSceneCamera(o.width, o.height);
    if (o.ortho > 0.0) {
        if (!o.lens_shift.empty()) throw usageError("--lens-shift applies to perspective cameras, not --ortho");
        camera.projection = orthographicProjection(o.ortho, double(o.width) / o.height, camera.nearPlane(),
                                                   camera.farPlane());
    }
    if (!o.lens_shift.empty()) {
        double sx = 0.0, sy = 0.0;
        char tail = 0;
        if (std::sscanf(o.lens_shift.c_str(), "%lf,%lf%c", &sx, &sy, &tail) != 2 || !std::isfinite(sx) ||
            !std::isfinite(sy) || std::abs(sx) > 10.0 || std::abs(sy) > 10.0)
            throw usageError(fmt::format("--lens-shift {}: expected sx,sy (NDC half-units, |s| <= 10)", o.lens_shift));
        camera.projection[2][0] = 2.0 * sx;  // as perspectiveProjection's shift
        camera.projection[2][1] = 2.0 * sy;
    }
    synth::RenderOptions render;
    render.width = o.width;
    render.height = o.height;
    render.depth = depth;
    render.reversed_z = o.reversed_z;
    // A position-convention file carries no depth pass, so readers take depth from the position.
    render.with_depth = depth != DepthConvention::Position;
    if (!o.data_window.empty()) {
        const Imath::Box2i window = parseWindow(o.data_window);
        render.origin_x = window.min.x;
        render.origin_y = window.min.y;
        render.width = window.max.x - window.min.x + 1;
        render.height = window.max.y - window.min.y + 1;
        render.display_width = o.width;
        render.display_height = o.height;
    }
    GBuffer gbuffer = synth::render(scene, camera, render);
    if (o.no_position) gbuffer.planes.erase(Attribute::Position);

    static const std::map<std::string, Imf::Compression> compressions = {
        {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION}, {"none", Imf::NO_COMPRESSION}};
    gen::ExrLayoutOptions layout;
    layout.naming = naming;
    layout.camera = camera;
    layout.layer = o.layer;
    layout.half = o.half;
    layout.compression = compressions.at(o.compression);
    layout.multipart = o.multipart;
    layout.light_passes = o.light_passes;
    if (o.header_camera) layout.header_camera = camera;

    if (o.per_pass) {
        for (const auto& [key, image] : gen::gbufferToPassFiles(gbuffer, layout))
            writeExrAtomic(image, key == "beauty" ? o.output : passPath(o.output, key));
    } else {
        writeExrAtomic(gen::gbufferToExr(gbuffer, layout), o.output);
    }
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
    auto* naming = app.add_option("--naming", o.naming,
                   "Channel names, one per renderer profile (docs/profiles.md): blender (<layer>.Depth.Z, "
                   ".DiffCol.RGB, .Normal.XYZ, .Position.XYZ, .IndexOB.X, .Combined.RGBA), generic (Z, "
                   "albedo.RGB, N.XYZ, P.XYZ, id, roughness, metallic, RGBA), arnold (Z, diffuse_albedo.RGB, "
                   "N.XYZ, P.XYZ, ID), karma (Z, albedo.RGB, N.RGB, P.RGB, id), renderman (z, albedo.rgb, "
                   "camera-space Nn.xyz, __Pworld.xyz, id) or unreal (SceneDepthWorldUnits.RGB, BaseColor.RGB, "
                   "WorldNormal.RGB, WorldPosition.RGB, CustomStencil.RGB)")
        ->check(CLI::IsMember({"blender", "generic", "arnold", "karma", "renderman", "unreal"}))
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
    app.add_option("--lens-shift", o.lens_shift, "Shift the perspective camera's lens: sx,sy in NDC half-units");
    app.add_option("--ortho", o.ortho, "Orthographic camera with this half height (world units) instead")
        ->check(CLI::Range(1e-6, 1e6));
    app.add_flag("--per-pass", o.per_pass,
                 "One file per pass: -o gets the beauty (R,G,B,A), <stem>.depth.exr (Z), <stem>.albedo.exr (R,G,B), "
                 "<stem>.normal.exr, <stem>.position.exr (X,Y,Z), <stem>.id.exr (id), <stem>.roughness.exr, "
                 "<stem>.metallic.exr (Y)");
    app.add_option("--data-window", o.data_window,
                   "Render only this data window x0,y0,x1,y1 (inclusive) of the --width x --height display window; "
                   "it may reach outside it (overscan, negative origin) or lie inside it (crop)");
    app.add_flag("--header-camera", o.header_camera,
                 "Also write the camera as worldToCamera/worldToNDC/clipNear/clipFar header attributes");
    app.add_flag("--light-passes", o.light_passes,
                 "Also write the diffuse light passes: Blender's DiffDir/DiffInd (divided by DiffCol), Arnold's "
                 "diffuse_direct/indirect, RenderMan's directDiffuse/indirectDiffuse (multiplied by the albedo); "
                 "the beauty is exactly their shade");
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
        return run(o, seed->count() > 0, layer->count() > 0, naming->count() > 0);
    } catch (const Error& e) {
        std::cerr << "decalcomp-gbuffer-gen: " << e.what() << "\n";
        return int(e.kind());
    } catch (const std::exception& e) {
        std::cerr << "decalcomp-gbuffer-gen: internal error: " << e.what() << "\n";
        return 1;
    }
}
