// Per-frame cameras for batches: sidecar patterns, one sidecar for all frames, or one file with a
// camera per frame.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "decalcomp/frame_cameras.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

using json = nlohmann::json;

class PerFrameParser {
public:
    explicit PerFrameParser(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw inputError(at.empty() ? fmt::format("{}: {}", file_, what) : fmt::format("{}: {}: {}", file_, at, what));
    }

    glm::dmat4 matrix(const json& v, const std::string& at) const {
        const char* shape = "expected 4 rows of 4 numbers (row-major)";
        if (!v.is_array() || v.size() != 4) fail(at, shape);
        double rows[4][4];
        for (std::size_t r = 0; r < 4; ++r) {
            if (!v[r].is_array() || v[r].size() != 4) fail(at, shape);
            for (std::size_t c = 0; c < 4; ++c) {
                if (!v[r][c].is_number() || !std::isfinite(v[r][c].get<double>()))
                    fail(fmt::format("{}[{}][{}]", at, r, c), "expected a finite number");
                rows[r][c] = v[r][c].get<double>();
            }
        }
        const glm::dmat4 m = matrixFromRows(rows);
        const double det = glm::determinant(m);
        if (!std::isfinite(det) || std::abs(det) < 1e-12) fail(at, "matrix is not invertible");
        return m;
    }

    Camera camera(const json& entry, const std::string& at, const std::optional<glm::dmat4>& default_projection,
                  int frame) const {
        if (!entry.is_object()) fail(at, "expected an object with world_to_camera (and projection)");
        Camera c;
        if (!entry.contains("world_to_camera")) fail(at, "missing 'world_to_camera'");
        c.world_to_camera = matrix(entry.at("world_to_camera"), at + ".world_to_camera");
        if (entry.contains("projection")) c.projection = matrix(entry.at("projection"), at + ".projection");
        else if (default_projection) c.projection = *default_projection;
        else fail(at, "missing 'projection' (and no top-level 'projection' for every frame)");
        c.source = fmt::format("{} (frame {})", file_, frame);
        return c;
    }

    int frameNumber(const json& v, const std::string& at) const {
        if (v.is_number_integer()) return v.get<int>();
        if (v.is_string()) {
            const std::string s = v.get<std::string>();
            std::size_t used = 0;
            try {
                const int f = std::stoi(s, &used);
                if (used == s.size()) return f;
            } catch (const std::exception&) {
            }
        }
        fail(at, "expected a whole frame number");
    }

    std::map<int, Camera> load() const {
        std::ifstream in(file_, std::ios::binary);
        if (!in) fail("", "cannot open the cameras file");
        std::stringstream text;
        text << in.rdbuf();
        json doc;
        try {
            doc = json::parse(text.str(), nullptr, true, /*ignore_comments=*/true);
        } catch (const json::exception& e) {
            fail("", fmt::format("not valid JSON ({})", e.what()));
        }
        if (!doc.is_object() || !doc.contains("frames"))
            fail("", "expected an object with \"frames\" (a camera per frame)");
        std::optional<glm::dmat4> projection;
        if (doc.contains("projection")) projection = matrix(doc.at("projection"), "projection");
        std::map<int, Camera> cameras;
        const json& frames = doc.at("frames");
        auto add = [&](int frame, const json& entry, const std::string& at) {
            if (!cameras.emplace(frame, camera(entry, at, projection, frame)).second)
                fail(at, fmt::format("frame {} is given twice", frame));
        };
        if (frames.is_object()) {
            for (const auto& [key, entry] : frames.items()) {
                const std::string at = fmt::format("frames[{}]", json(key).dump());
                add(frameNumber(json(key), at), entry, at);
            }
        } else if (frames.is_array()) {
            for (std::size_t i = 0; i < frames.size(); ++i) {
                const std::string at = fmt::format("frames[{}]", i);
                if (!frames[i].is_object() || !frames[i].contains("frame")) fail(at, "missing 'frame'");
                add(frameNumber(frames[i].at("frame"), at + ".frame"), frames[i], at);
            }
        } else {
            fail("frames", "expected an object {\"1\": camera, ...} or an array of cameras with \"frame\"");
        }
        return cameras;
    }

private:
    std::string file_;
};

}  // namespace

std::map<int, Camera> loadPerFrameCameras(const std::string& path) { return PerFrameParser(path).load(); }

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

std::string FrameCameras::describe() const {
    if (fixed_) return fixed_->source + " (every frame)";
    if (pattern_) return "sidecars " + pattern_->text();
    if (!per_frame_file_.empty()) return fmt::format("{} ({} frames)", per_frame_file_, per_frame_.size());
    return "each frame's header (else solved from its position pass)";
}

}  // namespace decalcomp
