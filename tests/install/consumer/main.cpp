// Composites one frame through the installed library's frame pipeline and checks the result:
//   consumer IN.exr SCENE.json CAMERA.json OUT.exr
// Exits 0 only when the output exists and the decals changed some samples.
#include <cstdio>
#include <filesystem>
#include <decalcomp/compositor.hpp>
#include <decalcomp/device.hpp>
#include <decalcomp/error.hpp>
#include <decalcomp/frame.hpp>
#include <decalcomp/scene.hpp>
#include <decalcomp/version.hpp>

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: consumer IN.exr SCENE.json CAMERA.json OUT.exr\n");
        return 2;
    }
    try {
        const decalcomp::DecalScene scene = decalcomp::loadScene(argv[2]);
        decalcomp::ComputeDevice device("cpu");
        decalcomp::Compositor compositor(device);
        compositor.setScene(scene);

        decalcomp::FrameSources sources;
        sources.inputs = {argv[1]};
        sources.camera_json = argv[3];
        decalcomp::FrameTargets targets;
        targets.output = argv[4];
        decalcomp::Frame frame(sources, targets, {});
        frame.prepare(scene);
        frame.composite(compositor);
        frame.writeBack();

        const auto& report = frame.report();
        std::printf("decalcomp %s on %s: %zu samples changed, wrote %s\n", decalcomp::kVersion,
                    device.info().name.c_str(), report.changed_samples, argv[4]);
        return report.changed_samples > 0 && std::filesystem::exists(argv[4]) ? 0 : 1;
    } catch (const decalcomp::Error& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 1;
    }
}
