#pragma once
// Loads a decal scene JSON file (docs/scene-format.md). Texture paths are relative to the file.
#include <string>

#include "decalcomp/decal.hpp"

namespace decalcomp {

// What a scene is read with, besides its own file.
struct SceneOptions {
    // The OpenColorIO config its colour spaces are looked up in (--ocio); "" for the one $OCIO
    // names. Only read when the scene names a working space or a texture colour space.
    std::string ocio_config;
};

// Throws Error(Input) naming the file and JSON path ("scene.json: decals[3].opacity: ...").
DecalScene loadScene(const std::string& path, const SceneOptions& options = {});

// The same from JSON text (a program's or Python's scene): `label` names it in messages and
// DecalScene::source; relative texture and mesh paths resolve against `base_dir`.
DecalScene parseScene(const std::string& json_text, const std::string& label, const std::string& base_dir,
                      const SceneOptions& options = {});

}  // namespace decalcomp
