// Decal animation keys of scene files: "frames", "fade_in", "fade_out", "keyframes",
// "keyframe_interpolation" (docs/scene-format.md "Animation").
#include "scene/animation_json.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {

namespace {

// Every key that places a decal; a keyframe holds one placement and its "frame".
const std::vector<std::string> kPlacementKeys = {"matrix",          "world_matrix", "translate", "rotate_deg",
                                                 "quaternion_wxyz", "scale",        "origin",    "target",
                                                 "up",              "size"};

// "frames": [first, last], either end null for open.
void lifetime(const JsonField& j, Decal& decal) {
    const auto frames = j.optional("frames");
    if (!frames) return;
    frames->requireArray("[first, last] (frame numbers, inclusive; null for an open end)", 2);
    if (!(*frames)[0].value().is_null()) decal.first_frame = (*frames)[0].number();
    if (!(*frames)[1].value().is_null()) decal.last_frame = (*frames)[1].number();
    if (decal.first_frame && decal.last_frame && *decal.first_frame > *decal.last_frame)
        frames->fail(fmt::format("first frame {} is after last frame {}", *decal.first_frame, *decal.last_frame));
}

double fade(const JsonField& j, const char* key, bool anchored, const char* anchor) {
    const auto field = j.optional(key);
    if (!field) return 0.0;
    const double n = field->number();
    if (n < 0.0) field->fail("expected a number of frames >= 0");
    if (!anchored) field->fail(fmt::format("needs the {} frame of 'frames' to fade from", anchor));
    return n;
}

void keyframes(const JsonField& j, const PlacementParser& placement, Decal& decal) {
    for (const std::string& k : kPlacementKeys)
        if (j.has(k)) j.fail(fmt::format("give either a placement ('{}') or 'keyframes', not both", k));
    const JsonField keys = j.required("keyframes");
    if (!keys.isArray() || keys.size() == 0)
        keys.fail("expected a non-empty array of {\"frame\": N, <placement>} objects");
    std::vector<std::string> keyframeKeys = kPlacementKeys;
    keyframeKeys.push_back("frame");
    for (const JsonField& key : keys.elements()) {
        key.requireObject("an object {\"frame\": N, <placement>}");
        key.checkKeys(keyframeKeys);
        DecalKeyframe k;
        const JsonField frame = key.required("frame");
        k.frame = frame.number();
        if (!decal.keyframes.empty() && !(k.frame > decal.keyframes.back().frame))
            frame.fail(fmt::format("{} is not after the previous keyframe's {} (frames must increase)", k.frame,
                                   decal.keyframes.back().frame));
        k.world_matrix = placement(key);
        decal.keyframes.push_back(k);
    }
    if (const auto interpolation = j.optional("keyframe_interpolation"))
        decal.keyframe_interpolation =
            interpolation->choice({"linear", "step"}) == 0 ? KeyframeInterpolation::Linear : KeyframeInterpolation::Step;
    // A linear blend between a mirrored and an unmirrored placement passes through a flat box.
    if (decal.keyframe_interpolation == KeyframeInterpolation::Linear)
        for (std::size_t i = 1; i < decal.keyframes.size(); ++i) {
            const bool a = glm::determinant(glm::dmat3(decal.keyframes[i - 1].world_matrix)) < 0.0;
            const bool b = glm::determinant(glm::dmat3(decal.keyframes[i].world_matrix)) < 0.0;
            if (a != b)
                keys[i].fail("mirrored where the previous keyframe is not (or the reverse): linear interpolation "
                             "would flatten the decal; mirror both or use \"keyframe_interpolation\": \"step\"");
        }
    decal.world_matrix = decal.keyframes.front().world_matrix;
}

}  // namespace

bool parseDecalAnimation(const JsonField& j, const PlacementParser& placement, Decal& decal) {
    lifetime(j, decal);
    decal.fade_in_frames = fade(j, "fade_in", decal.first_frame.has_value(), "first");
    decal.fade_out_frames = fade(j, "fade_out", decal.last_frame.has_value(), "last");
    if (!j.has("keyframes")) {
        if (const auto interpolation = j.optional("keyframe_interpolation"))
            interpolation->fail("no 'keyframes' to interpolate");
        return false;
    }
    keyframes(j, placement, decal);
    return true;
}

}  // namespace decalcomp::scene_detail
