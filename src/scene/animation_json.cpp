// Decal animation keys of scene files: "frames", "fade_in", "fade_out", "keyframes",
// "keyframe_interpolation" (docs/scene-format.md "Animation").
#include "scene/animation_json.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {

namespace {

using json = nlohmann::json;

// Every key that places a decal; a keyframe holds one placement and its "frame".
const std::vector<std::string> kPlacementKeys = {"matrix",          "world_matrix", "translate", "rotate_deg",
                                                 "quaternion_wxyz", "scale",        "origin",    "target",
                                                 "up",              "size"};

class AnimationParser {
public:
    AnimationParser(const std::string& path, const std::string& file) : path_(path), file_(file) {}

    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw inputError(fmt::format("{}: {}: {}", file_, at, what));
    }

    double number(const json& v, const std::string& at) const {
        if (!v.is_number()) fail(at, "expected a number");
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(at, "expected a finite number");
        return d;
    }

    void lifetime(const json& j, Decal& decal) const {
        if (!j.contains("frames")) return;
        const std::string at = path_ + ".frames";
        const json& v = j.at("frames");
        if (!v.is_array() || v.size() != 2)
            fail(at, "expected [first, last] (frame numbers, inclusive; null for an open end)");
        if (!v[0].is_null()) decal.first_frame = number(v[0], at + "[0]");
        if (!v[1].is_null()) decal.last_frame = number(v[1], at + "[1]");
        if (decal.first_frame && decal.last_frame && *decal.first_frame > *decal.last_frame)
            fail(at, fmt::format("first frame {} is after last frame {}", *decal.first_frame, *decal.last_frame));
    }

    double fade(const json& j, const char* key, bool anchored, const char* anchor) const {
        if (!j.contains(key)) return 0.0;
        const std::string at = path_ + "." + key;
        const double n = number(j.at(key), at);
        if (n < 0.0) fail(at, "expected a number of frames >= 0");
        if (!anchored) fail(at, fmt::format("needs the {} frame of 'frames' to fade from", anchor));
        return n;
    }

    void keyframes(const json& j, const PlacementParser& placement, Decal& decal) const {
        const std::string at = path_ + ".keyframes";
        for (const std::string& k : kPlacementKeys)
            if (j.contains(k))
                fail(path_, fmt::format("give either a placement ('{}') or 'keyframes', not both", k));
        const json& keys = j.at("keyframes");
        if (!keys.is_array() || keys.empty())
            fail(at, "expected a non-empty array of {\"frame\": N, <placement>} objects");
        for (std::size_t i = 0; i < keys.size(); ++i) {
            const std::string kat = fmt::format("{}[{}]", at, i);
            const json& key = keys[i];
            if (!key.is_object()) fail(kat, "expected an object {\"frame\": N, <placement>}");
            for (const auto& [name, value] : key.items())
                if (name != "frame" && (name.empty() || name[0] != '_') &&
                    std::find(kPlacementKeys.begin(), kPlacementKeys.end(), name) == kPlacementKeys.end())
                    fail(kat + "." + name, "unknown key (a keyframe has 'frame' and one placement)");
            if (!key.contains("frame")) fail(kat, "missing 'frame'");
            DecalKeyframe k;
            k.frame = number(key.at("frame"), kat + ".frame");
            if (!decal.keyframes.empty() && !(k.frame > decal.keyframes.back().frame))
                fail(kat + ".frame", fmt::format("{} is not after the previous keyframe's {} (frames must increase)",
                                                 k.frame, decal.keyframes.back().frame));
            k.world_matrix = placement(key, kat);
            decal.keyframes.push_back(k);
        }
        if (j.contains("keyframe_interpolation")) {
            const std::string iat = path_ + ".keyframe_interpolation";
            const json& v = j.at("keyframe_interpolation");
            const std::string name = v.is_string() ? v.get<std::string>() : std::string();
            if (name == "linear") decal.keyframe_interpolation = KeyframeInterpolation::Linear;
            else if (name == "step") decal.keyframe_interpolation = KeyframeInterpolation::Step;
            else fail(iat, "expected \"linear\" or \"step\"");
        }
        // A linear blend between a mirrored and an unmirrored placement passes through a flat box.
        if (decal.keyframe_interpolation == KeyframeInterpolation::Linear)
            for (std::size_t i = 1; i < decal.keyframes.size(); ++i) {
                const bool a = glm::determinant(glm::dmat3(decal.keyframes[i - 1].world_matrix)) < 0.0;
                const bool b = glm::determinant(glm::dmat3(decal.keyframes[i].world_matrix)) < 0.0;
                if (a != b)
                    fail(fmt::format("{}[{}]", at, i),
                         "mirrored where the previous keyframe is not (or the reverse): linear interpolation "
                         "would flatten the decal; mirror both or use \"keyframe_interpolation\": \"step\"");
            }
        decal.world_matrix = decal.keyframes.front().world_matrix;
    }

private:
    const std::string& path_;
    const std::string& file_;
};

}  // namespace

bool parseDecalAnimation(const json& j, const std::string& path, const std::string& file,
                         const PlacementParser& placement, Decal& decal) {
    const AnimationParser parser(path, file);
    parser.lifetime(j, decal);
    decal.fade_in_frames = parser.fade(j, "fade_in", decal.first_frame.has_value(), "first");
    decal.fade_out_frames = parser.fade(j, "fade_out", decal.last_frame.has_value(), "last");
    if (!j.contains("keyframes")) {
        if (j.contains("keyframe_interpolation"))
            parser.fail(path + ".keyframe_interpolation", "no 'keyframes' to interpolate");
        return false;
    }
    parser.keyframes(j, placement, decal);
    return true;
}

}  // namespace decalcomp::scene_detail
