#pragma once
// Texture-space decals in scene files (docs/texture-space.md): "space": "object_rest" with the
// rest-pose "mesh" and the object the decal sticks to ("pass_index", "cryptomatte_object").
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "decalcomp/bake.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

// Keys this part of the format reads, and those it accepts as notes (the Blender export's).
extern const std::vector<std::string> kTextureSpaceKeys;
extern const std::vector<std::string> kTextureSpaceNotes;

// The rest meshes a scene loads, each file once.
struct MeshTable {
    std::filesystem::path dir;  // the scene file's folder: mesh paths are relative to it
    std::map<std::string, int> index;  // canonical path -> DecalScene::meshes entry
    std::vector<RestMesh> meshes;
    int bake_decals = 0;                   // bake-mode decals so far: the next one's bake_slot
    std::map<int, BakedLayers> baked_files;  // by bake_slot: layers read from a decal's "baked" file
};

// Reads the decal's space. For "object_rest": loads its mesh into `meshes`, and binds the decal to
// its object through a mask (interned in `masks`) unless the decal gives its own "mask". Fails
// "FILE: PATH: what" for a missing or broken mesh, a missing binding, blast occlusion, or mesh
// fields on a world decal. Bake mode (docs/texture-space.md "Bake mode"): numbers the decal's
// bake_slot and reads its "baked" file, if any, into `meshes.baked_files`.
void parseDecalSpace(const JsonField& j, Decal& decal, MeshTable& meshes, std::vector<DecalMask>& masks);

}  // namespace decalcomp::scene_detail
