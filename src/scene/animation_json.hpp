#pragma once
// Decal animation keys in scene files (docs/scene-format.md "Animation"): lifetime, fades and
// keyframed placement. Called by the scene parser for each decal.
#include <functional>

#include "decalcomp/decal.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

// The scene parser's own placement reader (matrix, translate/rotate/scale or look-at keys of an
// object), so a keyframe accepts exactly what a static decal accepts, with the same messages.
using PlacementParser = std::function<glm::dmat4(const JsonField& object)>;

// Reads "frames", "fade_in", "fade_out", "keyframes" and "keyframe_interpolation" of the decal
// object `j` into `decal`. Returns true when keyframes give the placement (world_matrix is then
// the first key's), false when the caller reads the static one. Throws Error(Input) "file: path: what".
bool parseDecalAnimation(const JsonField& j, const PlacementParser& placement, Decal& decal);

}  // namespace decalcomp::scene_detail
