#pragma once
// Per-frame cameras of a sequence: a per-frame cameras file, a sidecar pattern or one sidecar.
#include <map>
#include <optional>
#include <string>

#include "decalcomp/camera.hpp"
#include "decalcomp/frame_pattern.hpp"

namespace decalcomp {

// Where each frame's camera comes from, in order: a per-frame cameras file (`cameras`), a sidecar
// pattern or one sidecar for every frame (`camera`), else nothing (the frame's header, then a
// camera solved from its position pass, as `composite`).
class FrameCameras {
public:
    FrameCameras() = default;
    // Loads a fixed sidecar or the per-frame file up front; Error(Input) naming file and field.
    FrameCameras(const std::string& camera, const std::string& cameras);
    // nullopt: no explicit camera, use the header / solve. Error(Input) when the frame has none in
    // the per-frame file or its sidecar cannot be read.
    std::optional<Camera> explicitCamera(int frame) const;
    std::string describe() const;
    // What a batch checks before it starts: the sidecar the pattern names for `frame` ("" without
    // a sidecar pattern), and whether a per-frame cameras file has the frame (true without one).
    std::string sidecarPath(int frame) const;
    bool hasFrame(int frame) const;
    const std::string& perFrameFile() const { return per_frame_file_; }
    // The file `frame`'s explicit camera is read from ("" without one), so no output may replace it.
    std::string cameraFile(int frame) const;

private:
    std::optional<Camera> fixed_;
    std::optional<FramePattern> pattern_;
    std::map<int, Camera> per_frame_;
    std::string per_frame_file_;
};

// One JSON file with a camera per frame (docs/cli.md): {"projection": [[...]] (optional default),
// "frames": {"1": {"world_to_camera": [[...]], "projection": [[...]]}, ...}} or "frames" as an
// array of objects with a "frame" number. Throws Error(Input) naming the file and JSON path.
std::map<int, Camera> loadPerFrameCameras(const std::string& path);

}  // namespace decalcomp
