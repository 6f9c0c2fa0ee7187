// Per-frame cameras for batches: sidecar patterns, one sidecar for all frames, or one file with a
// camera per frame.
#include <fmt/format.h>

#include <cctype>

#include "decalcomp/camera_json.hpp"
#include "decalcomp/frame_cameras.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp {

namespace {

using json = nlohmann::json;

Camera frameCamera(const JsonField& entry, const std::optional<glm::dmat4>& default_projection, int frame) {
    entry.requireObject("an object with world_to_camera (and projection)");
    Camera c;
    c.world_to_camera = readWorldToCamera(entry.required("world_to_camera"));
    if (const auto projection = entry.optional("projection")) c.projection = readProjection(*projection);
    else if (default_projection) c.projection = *default_projection;
    else entry.fail("missing 'projection' (and no top-level 'projection' for every frame)");
    c.source = fmt::format("{} (frame {})", entry.file(), frame);
    return c;
}

// A frame number as a key of "frames" ("12") or as the value of "frame" (12).
int frameNumber(const JsonField& at, const std::string& key) {
    std::size_t used = 0;
    try {
        const int f = std::stoi(key, &used);
        if (used == key.size() && !key.empty() && !std::isspace(static_cast<unsigned char>(key[0]))) return f;
    } catch (const std::exception&) {
    }
    at.fail("expected a whole frame number");
}

}  // namespace

std::map<int, Camera> loadPerFrameCameras(const std::string& file) {
    const json doc = readJsonFile(file, "cameras file");
    const JsonField root(doc, file);
    if (!doc.is_object() || !doc.contains("frames")) root.fail("expected an object with \"frames\" (a camera per frame)");
    std::optional<glm::dmat4> projection;
    if (const auto p = root.optional("projection")) projection = readProjection(*p);
    std::map<int, Camera> cameras;
    const JsonField frames = root.required("frames");
    auto add = [&](int frame, const JsonField& entry) {
        if (!cameras.emplace(frame, frameCamera(entry, projection, frame)).second)
            entry.fail(fmt::format("frame {} is given twice", frame));
    };
    if (frames.isObject()) {
        for (const auto& [key, entry] : frames.members()) add(frameNumber(entry, key), entry);
    } else if (frames.isArray()) {
        for (const JsonField& entry : frames.elements()) {
            if (!entry.isObject()) entry.fail("expected an object with \"frame\" and world_to_camera");
            const JsonField frame = entry.required("frame");
            add(frame.value().is_string() ? frameNumber(frame, frame.string()) : frame.integer(), entry);
        }
    } else {
        frames.fail("expected an object {\"1\": camera, ...} or an array of cameras with \"frame\"");
    }
    return cameras;
}


FrameCameras::FrameCameras(const std::string& camera, const std::string& cameras) {
    if (!camera.empty() && !cameras.empty())
        throw Error(ErrorKind::Usage, "give either --camera (a sidecar or sidecar pattern) or --cameras, not both");
    if (!cameras.empty()) {
        per_frame_ = loadPerFrameCameras(cameras);
        per_frame_file_ = cameras;
    } else if (!camera.empty()) {
        if (FramePattern::hasToken(camera)) pattern_ = FramePattern(camera);
        else fixed_ = loadCameraJson(camera);
    }
}

std::optional<Camera> FrameCameras::explicitCamera(int frame) const {
    if (fixed_) return fixed_;
    if (pattern_) return loadCameraJson(pattern_->path(frame));
    if (!per_frame_file_.empty()) {
        auto it = per_frame_.find(frame);
        if (it == per_frame_.end()) throw inputError(fmt::format("{}: no camera for frame {}", per_frame_file_, frame));
        return it->second;
    }
    return std::nullopt;
}

std::string FrameCameras::cameraFile(int frame) const {
    if (fixed_) return fixed_->source;
    if (pattern_) return pattern_->path(frame);
    return per_frame_file_;
}

std::string FrameCameras::sidecarPath(int frame) const { return pattern_ ? pattern_->path(frame) : std::string(); }

bool FrameCameras::hasFrame(int frame) const { return per_frame_file_.empty() || per_frame_.count(frame) > 0; }

std::string FrameCameras::describe() const {
    if (fixed_) return fixed_->source + " (every frame)";
    if (pattern_) return "sidecars " + pattern_->text();
    if (!per_frame_file_.empty()) return fmt::format("{} ({} frames)", per_frame_file_, per_frame_.size());
    return "each frame's header (else solved from its position pass)";
}

}  // namespace decalcomp
