#pragma once
// The "mask" field of a decal (docs/scene-format.md, "Masks"): JSON -> DecalMask (internal).
#include <string>
#include <vector>

#include "decalcomp/decal.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

// The Cryptomatte layer a mask uses when it does not name one.
inline constexpr const char* kDefaultCryptomatteLayer = "CryptoObject";

// Parses the mask field `value`. Throws Error(Input) "file: path...: what" (e.g.
// "scene.json: decals[2].mask.ids[1]: expected an integer").
// Id lists come back sorted without duplicates; Cryptomatte names keep their order (warnings
// name them by index).
DecalMask parseMaskJson(const JsonField& value);

// Parses the mask and returns its index in `masks`, appending it only when no identical mask is
// there yet, so decals with the same mask share one weight plane.
int parseAndInternMask(const JsonField& value, std::vector<DecalMask>& masks);
// The index of `mask` in `masks`, appended when no identical mask is there yet.
int internMask(DecalMask mask, std::vector<DecalMask>& masks);

}  // namespace decalcomp::scene_detail
