// Camera JSON: the input as a camera sidecar and as a per-frame cameras file (--cameras), then the
// near and far planes the compositor derives from a camera that loaded.
#include "decalcomp/camera.hpp"
#include "decalcomp/frame_cameras.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace {

void usePlanes(const Camera& camera) {
    volatile double sink = camera.nearPlane() + camera.farPlane() + (camera.isOrthographic() ? 1.0 : 0.0);
    (void)sink;
}

}  // namespace

void fuzzCamera(const std::uint8_t* data, std::size_t size) {
    const std::string path = writeScratchFile("camera.json", asText(data, size));
    inputErrorsAllowed([&] { usePlanes(loadCameraJson(path)); });
    inputErrorsAllowed([&] {
        for (const auto& [frame, camera] : loadPerFrameCameras(path)) usePlanes(camera);
    });
}

}  // namespace decalcomp::fuzz
