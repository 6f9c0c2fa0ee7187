// decalcomp-bench-batch: writes the decal scene for the batch benchmark (tools/bench-batch/run.sh):
// N box decals scattered on the visible surfaces of the generator's demo frame (the same camera as
// `decalcomp-gbuffer-gen --scene demo` at that size), with procedural EXR textures. With --profile,
// times the host side of one frame step by step instead.
#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/json_fields.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/sequence_conventions.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/synth.hpp"

namespace {

using namespace decalcomp;
namespace fs = std::filesystem;

void writeTexture(const Texture2D& t, const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw outputError(path + ": cannot create");
    OIIO::ImageSpec spec(t.width, t.height, 4, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, t.texels.data()) || !out->close())
        throw outputError(path + ": " + out->geterror());
}

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Median of `repeat` timings of f(), milliseconds.
template <typename F>
double medianMs(int repeat, F&& f) {
    std::vector<double> v;
    for (int i = 0; i < repeat; ++i) {
        const auto t = std::chrono::steady_clock::now();
        f();
        v.push_back(msSince(t));
    }
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The host side of one frame, step by step: what the batch's compositing stage does, and the
// steps inside Compositor::composite() replayed (the same repacking into 1/4-channel images,
// image creation with CL_MEM_COPY_HOST_PTR, read-back of the float4 result and unpacking).
int profileHost(const std::string& frame_path, const std::string& scene_path, const std::string& device_name,
                int repeat) {
    auto line = [](const std::string& what, double ms) { std::cout << fmt::format("  {:<58} {:8.2f} ms\n", what, ms); };
    ExrImage image;
    line("readExr (OpenEXR pool of " + std::to_string(Imf::globalThreadCount()) + " threads)",
         medianMs(repeat, [&] { image = readExr(frame_path); }));
    std::vector<ExrImage> files{image};
    ChannelMapping mapping;
    line("mapChannels", medianMs(repeat, [&] { mapping = mapChannels(files, MappingOptions{}); }));
    GBuffer g;
    line("extractGBuffer, all mapped attributes", medianMs(repeat, [&] { g = extractGBuffer(files, mapping); }));
    for (const auto& [attribute, refs] : mapping.attributes) {
        ChannelMapping one = mapping;
        one.attributes = {{attribute, refs}};
        if (attribute != Attribute::Depth && mapping.attributes.count(Attribute::Depth))
            one.attributes[Attribute::Depth] = mapping.attributes.at(Attribute::Depth);  // same window
        const double with_depth = medianMs(repeat, [&] { (void)extractGBuffer(files, one); });
        line(fmt::format("  extract {} ({} channels{})", attributeName(attribute), refs.size(),
                         attribute == Attribute::Depth ? "" : ", with depth"),
             with_depth);
    }
    Camera camera;
    line("resolveCamera (header)", medianMs(repeat, [&] { camera = resolveCamera(files, g, ""); }));
    line("settleDepthConvention (first frame only in a batch)",
         medianMs(repeat, [&] { GBuffer copy = g; ChannelMapping m = mapping; settleDepthConvention(copy, m, camera); }));
    const DecalScene scene = loadScene(scene_path);
    ComputeDevice device(device_name);
    Compositor compositor(device);
    compositor.setScene(scene);
    line("evaluateMasks", medianMs(repeat, [&] { evaluateMasks(files, mapping, scene, g, nullptr); }));
    GBuffer work = g;
    compositor.composite(work, camera);  // warm-up
    double kernels = 0;
    line(fmt::format("Compositor::composite ({} decals, {})", scene.decals.size(), device.info().name),
         medianMs(repeat, [&] { work = g; kernels = compositor.composite(work, camera).totalKernelMs(); }));
    line("  of which device kernels (profiling events)", kernels);
    line("  (GBuffer copy, not part of composite)", medianMs(repeat, [&] { work = g; }));

    // composite()'s host steps, replayed.
    const std::size_t pixels = g.pixelCount();
    auto pack = [&](const Plane& plane, int channels) {
        std::vector<float> out(pixels * std::size_t(channels), 0.0f);
        const int copy = std::min(channels, plane.components);
        for (std::size_t i = 0; i < pixels; ++i)
            for (int c = 0; c < copy; ++c) out[i * std::size_t(channels) + std::size_t(c)] = plane.at(i, c);
        return out;
    };
    auto image2d = [&](int channels, const std::vector<float>& px) {
        const cl::ImageFormat format(channels == 1 ? CL_R : CL_RGBA, CL_FLOAT);
        return cl::Image2D(device.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, format, std::size_t(g.width),
                           std::size_t(g.height), 0, const_cast<float*>(px.data()));
    };
    std::vector<float> depth1, albedo4, normal4, position4;
    line("  replay: repack depth into a 1-channel image buffer",
         medianMs(repeat, [&] { depth1 = pack(g.planes.at(Attribute::Depth), 1); }));
    line("  replay: repack albedo into RGBA", medianMs(repeat, [&] { albedo4 = pack(g.planes.at(Attribute::Albedo), 4); }));
    if (g.has(Attribute::Normal))
        line("  replay: repack normal into RGBA (only when a decal needs normals)",
             medianMs(repeat, [&] { normal4 = pack(g.planes.at(Attribute::Normal), 4); }));
    if (g.has(Attribute::Position))
        line("  replay: repack position into RGBA (only for the position convention)",
             medianMs(repeat, [&] { position4 = pack(g.planes.at(Attribute::Position), 4); }));
    line("  replay: create 1-channel float image, COPY_HOST_PTR",
         medianMs(repeat, [&] { auto im = image2d(1, depth1); device.queue().finish(); }));
    line("  replay: create RGBA float image, COPY_HOST_PTR",
         medianMs(repeat, [&] { auto im = image2d(4, albedo4); device.queue().finish(); }));
    std::vector<float> result(pixels * 4);
    cl::Buffer out(device.context(), CL_MEM_WRITE_ONLY, result.size() * sizeof(float));
    line("  replay: allocate the float4 result vector", medianMs(repeat, [&] { std::vector<float> r(pixels * 4); result.swap(r); }));
    line("  replay: blocking read-back of the float4 result", medianMs(repeat, [&] {
             device.queue().enqueueReadBuffer(out, CL_TRUE, 0, result.size() * sizeof(float), result.data());
         }));
    Plane& albedo = work.planes.at(Attribute::Albedo);
    line("  replay: unpack RGBA into the albedo plane", medianMs(repeat, [&] {
             for (std::size_t i = 0; i < pixels; ++i)
                 for (int c = 0; c < albedo.components && c < 4; ++c) albedo.at(i, c) = result[i * 4 + std::size_t(c)];
         }));
    work = g;
    compositor.composite(work, camera);
    line("storeAttribute albedo (changed pixels re-encoded)", medianMs(repeat, [&] {
             std::vector<ExrImage> copy = files;
             storeAttribute(copy, mapping, Attribute::Albedo, work.planes.at(Attribute::Albedo));
         }));
    line("  (copy of the ExrImage, not part of store)", medianMs(repeat, [&] { std::vector<ExrImage> copy = files; }));
    storeAttribute(files, mapping, Attribute::Albedo, work.planes.at(Attribute::Albedo));
    const std::string out_path = frame_path + ".profile-out.exr";
    line("writeExrAtomic composited frame", medianMs(repeat, [&] { writeExrAtomic(files.front(), out_path); }));
    line("writeExrAtomic unmodified frame", medianMs(repeat, [&] { writeExrAtomic(image, out_path); }));
    std::filesystem::remove(out_path);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes the batch benchmark's decal scene (scene.json + textures) for the demo frame"};
    int width = 1920, height = 1080, count = 1000, animate_frames = 0;
    double min_size = 0.1, max_size = 0.4;
    std::uint32_t seed = 1;
    std::string out;
    app.add_option("--width", width)->capture_default_str();
    app.add_option("--height", height)->capture_default_str();
    app.add_option("--decals", count)->capture_default_str();
    app.add_option("--min-size", min_size)->capture_default_str();
    app.add_option("--max-size", max_size)->capture_default_str();
    app.add_option("--seed", seed)->capture_default_str();
    int first_row = 0, last_row = -1;
    app.add_option("--first-row", first_row, "Centre decals on pixels of rows from this one")->capture_default_str();
    app.add_option("--last-row", last_row, "... to this one (-1: the last row)")->capture_default_str();
    app.add_option("--animate", animate_frames,
                   "Keyframe every decal from frame 1 to this frame (drifting 0.2 units, turning 30 degrees), "
                   "so each frame has its own placements; 0 = static");
    app.add_option("-o,--output", out, "Output folder (scene mode)");
    std::string profile_frame, profile_scene, device = "gpu";
    int repeat = 5, threads = 0;
    app.add_option("--profile", profile_frame,
                   "Instead: time the host side of one frame (read, extract, composite and its steps, store, write)");
    app.add_option("--scene", profile_scene, "Scene for --profile");
    app.add_option("--device", device, "Device for --profile")->capture_default_str();
    app.add_option("--repeat", repeat, "Repetitions for --profile (median)")->capture_default_str();
    app.add_option("--threads", threads, "OpenEXR threads for --profile (0 = hardware)")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        if (!profile_frame.empty()) {
            Imf::setGlobalThreadCount(threads > 0 ? threads : int(std::thread::hardware_concurrency()));
            return profileHost(profile_frame, profile_scene, device, std::max(1, repeat));
        }
        if (out.empty()) throw Error(ErrorKind::Usage, "-o is required");
        fs::create_directories(fs::path(out) / "tex");
        const Camera camera = synth::demoCamera(width, height);
        synth::RenderOptions render;
        render.width = width;
        render.height = height;
        const GBuffer frame = synth::render(synth::demoScene(), camera, render);
        synth::ScatterOptions scatter;
        scatter.count = count;
        scatter.min_size = min_size;
        scatter.max_size = max_size;
        scatter.seed = seed;
        scatter.first_row = first_row;
        scatter.last_row = last_row;
        const DecalScene scene = synth::scatterDecals(frame, camera, scatter);
        nlohmann::json doc;
        doc["format"] = "decalcomp-scene/1";
        doc["description"] = fmt::format("decalcomp-bench-batch: {} decals on the {}x{} demo frame", count, width, height);
        for (std::size_t t = 0; t < scene.textures.size(); ++t) {
            const std::string name = fmt::format("tex/t{}.exr", t);
            writeTexture(scene.textures[t], (fs::path(out) / name).string());
            doc["textures"][fmt::format("t{}", t)] = name;
        }
        doc["decals"] = nlohmann::json::array();
        for (const Decal& d : scene.decals) {
            nlohmann::json j;
            j["name"] = d.name;
            j["texture"] = fmt::format("t{}", d.albedo_texture);
            j["opacity"] = d.opacity;
            j["filter"] = textureFilterName(d.filter);
            if (animate_frames > 1) {
                glm::dmat4 end = d.world_matrix;
                end[3] += glm::dvec4(0.2, 0.1, 0.0, 0.0);
                const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
                glm::dmat4 turn(1.0);
                turn[0][0] = c, turn[0][1] = s, turn[1][0] = -s, turn[1][1] = c;
                end = end * turn;
                j["keyframes"] = {{{"frame", 1}, {"matrix", matrixRowsJson(d.world_matrix)}},
                                  {{"frame", animate_frames}, {"matrix", matrixRowsJson(end)}}};
            } else {
                j["matrix"] = matrixRowsJson(d.world_matrix);
            }
            doc["decals"].push_back(j);
        }
        std::ofstream(fs::path(out) / "scene.json") << doc.dump(1) << "\n";
    } catch (const Error& e) {
        std::cerr << "decalcomp-bench-batch: " << e.what() << "\n";
        return int(e.kind());
    }
    return 0;
}
