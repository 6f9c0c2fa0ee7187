#pragma once
// Loads a decal scene JSON file (docs/scene-format.md). Texture paths are relative to the file.
#include <string>

#include "decalcomp/decal.hpp"

namespace decalcomp {

// Throws Error(Input) naming the file and JSON path ("scene.json: decals[3].opacity: ...").
DecalScene loadScene(const std::string& path);

}  // namespace decalcomp
