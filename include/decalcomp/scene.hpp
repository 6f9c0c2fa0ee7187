#pragma once
// Loads a decal scene JSON file (docs/scene-format.md). Texture paths are relative to the file.
#include <string>

#include "decalcomp/decal.hpp"

namespace decalcomp {

// Throws Error(Input) naming the file and JSON path ("scene.json: decals[3].opacity: ...").
DecalScene loadScene(const std::string& path);

// The same from JSON text (a program's or Python's scene): `label` names it in messages and
// DecalScene::source; relative texture and mesh paths resolve against `base_dir`.
DecalScene parseScene(const std::string& json_text, const std::string& label, const std::string& base_dir);

}  // namespace decalcomp
