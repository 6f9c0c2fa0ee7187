#include "scene/texture_space_json.hpp"

#include <fmt/format.h>

#include "decalcomp/error.hpp"
#include "decalcomp/mesh_file.hpp"
#include "scene/mask_json.hpp"

namespace decalcomp::scene_detail {

const std::vector<std::string> kTextureSpaceKeys = {"space",           "mesh",           "pass_index", "cryptomatte_object",
                                                    "mode",            "bake_resolution", "bake_dilation", "baked"};
const std::vector<std::string> kBakeKeys = {"bake_resolution", "bake_dilation", "baked"};
// Written by the Blender export beside a rest-pose decal; they restate the placement.
const std::vector<std::string> kTextureSpaceNotes = {"object",
                                                     "object_matrix",
                                                     "location_rest",
                                                     "rotation_quaternion_wxyz_rest",
                                                     "world_matrix_rest_pose",
                                                     "world_matrix_rest_pose_note"};

namespace {

int loadMesh(const JsonField& field, MeshTable& table) {
    std::filesystem::path file(field.nonEmptyString("mesh file (OBJ)"));
    if (file.is_relative()) file = table.dir / file;
    std::error_code ec;
    std::filesystem::path identity = std::filesystem::weakly_canonical(file, ec);
    if (ec) identity = file.lexically_normal();
    if (const auto it = table.index.find(identity.string()); it != table.index.end()) return it->second;
    try {
        table.meshes.push_back(loadRestMesh(file.string()));
    } catch (const Error& e) {
        field.fail(e.what());
    }
    const int index = int(table.meshes.size()) - 1;
    table.index.emplace(identity.string(), index);
    return index;
}

// "bake_resolution", "bake_dilation" and a reused "baked" file (which must fit the mesh).
void parseBakeFields(const JsonField& j, Decal& decal, MeshTable& meshes) {
    if (!decal.keyframes.empty())
        j.required("mode").fail("a baked decal cannot move (its keyframes would need a bake per frame); use "
                                "\"exact\" for keyframed texture-space decals");
    const auto resolution = j.optional("bake_resolution");
    if (resolution) decal.bake_resolution = int(resolution->integer(1, 16384));
    if (const auto dilation = j.optional("bake_dilation")) decal.bake_dilation = int(dilation->integer(0, 1024));
    decal.bake_slot = meshes.bake_decals++;
    const auto baked = j.optional("baked");
    if (!baked) return;
    std::filesystem::path file(baked->nonEmptyString("baked layer file (EXR)"));
    if (file.is_relative()) file = meshes.dir / file;
    BakedLayers layers;
    try {
        layers = readBakedLayers(file.string(), meshes.meshes.at(std::size_t(decal.rest_mesh)));
    } catch (const Error& e) {
        baked->fail(e.what());
    }
    if (resolution && layers.width != decal.bake_resolution)
        baked->fail(fmt::format("{}: the file is a {}x{} bake and bake_resolution is {}; re-run decalcomp bake or drop "
                                "bake_resolution",
                                file.string(), layers.width, layers.height, decal.bake_resolution));
    decal.bake_resolution = layers.width;
    meshes.baked_files.emplace(decal.bake_slot, std::move(layers));
}

}  // namespace

void parseDecalSpace(const JsonField& j, Decal& decal, MeshTable& meshes, std::vector<DecalMask>& masks) {
    const auto space = j.optional("space");
    decal.space = space && space->choice({"world", "object_rest"}) == 1 ? DecalSpace::ObjectRest : DecalSpace::World;
    if (decal.space == DecalSpace::World) {
        for (const char* key : {"mesh", "pass_index", "cryptomatte_object", "mode", "bake_resolution", "bake_dilation", "baked"})
            if (j.has(key))
                j.required(key).fail("belongs to texture-space decals: add \"space\": \"object_rest\" to place the "
                                     "decal on the object's rest-pose mesh");
        return;
    }
    const auto mode = j.optional("mode");
    decal.rest_mode = mode && mode->choice({"exact", "bake"}) == 1 ? RestMode::Bake : RestMode::Exact;
    decal.rest_mesh = loadMesh(j.required("mesh", "the object's rest-pose mesh with UVs, an OBJ file"), meshes);
    if (decal.rest_mode == RestMode::Exact) {
        for (const std::string& key : kBakeKeys)
            if (j.has(key)) j.required(key).fail("belongs to bake mode: add \"mode\": \"bake\"");
    } else {
        parseBakeFields(j, decal, meshes);
    }
    if (decal.occlusion.enabled)
        j.required("occlusion").fail("blast occlusion is not available for texture-space decals");
    const auto pass_index = j.optional("pass_index");
    const auto crypto = j.optional("cryptomatte_object");
    if (j.has("mask") && (pass_index || crypto))
        j.required("mask").fail("give the decal's object either by 'pass_index'/'cryptomatte_object' or by 'mask', "
                                "not both");
    if (j.has("mask")) return;  // the decal's own mask selects the object (parsed with the other fields)
    if (!pass_index && !crypto)
        j.fail("a texture-space decal needs the object it sticks to: 'pass_index' (the object-id pass value) or "
               "'cryptomatte_object' (its Cryptomatte name)");
    DecalMask mask;
    if (pass_index) mask.include_ids = {pass_index->integer()};
    if (crypto) {
        mask.cryptomatte_layer = kDefaultCryptomatteLayer;
        mask.cryptomatte_names = {crypto->nonEmptyString("Cryptomatte object name")};
    }
    decal.mask = internMask(std::move(mask), masks);
}

}  // namespace decalcomp::scene_detail
