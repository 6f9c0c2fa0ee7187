#pragma once
// Scene-file fields of the decal kinds (box, volume, frustum, cube) and their fades.
#include <optional>
#include <string>

#include "decalcomp/decal.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

// How a texture file is arranged: a plain image, a vertical strip of volume slices, a horizontal
// strip of six cube faces, or six face files.
enum class TextureLayout { Image, VolumeStrip, CubeStrip, CubeFaces };

std::optional<DecalKind> kindFromName(const std::string& name);

// A frustum placed by origin/target/up without a size is a rigid projector at `origin`.
bool isProjectorLookAt(const JsonField& decal, DecalKind kind);
glm::dmat4 projectorLookAt(const JsonField& decal);

// fov_y_deg/aspect/near/far (frustum only), "fade": {angle_deg, axis, distance} and
// "occlusion" (frustum and cube).
void parseKindFields(const JsonField& decal, Decal& out);

// The layout a kind reads its texture in (a plain image means the kind's strip), or an error.
TextureLayout layoutForKind(DecalKind kind, TextureLayout given, const std::string& path, const std::string& file);

Texture2D arrangeTexture(Texture2D image, TextureLayout layout);

}  // namespace decalcomp::scene_detail
