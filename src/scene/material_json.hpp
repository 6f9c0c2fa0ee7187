#pragma once
// Scene-file "affects": which material attributes a decal changes, by how much and how.
#include "decalcomp/decal.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

// Parses `"affects": {"albedo": 1, "roughness": {"factor": 0.5, "op": "add", "value": 0.2},
// "normal": {"factor": 1, "mode": "udn", "strength": 2}}` into out.effects, normal_blend and
// normal_strength. Targets not listed get factor 0. Errors name the file and JSON path.
void parseAffects(const JsonField& affects, Decal& out);

}  // namespace decalcomp::scene_detail
