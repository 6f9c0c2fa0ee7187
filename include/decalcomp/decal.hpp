#pragma once
// Decals and their textures as the compositor consumes them (already validated and decoded).
#include <glm/glm.hpp>
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/rest_mesh.hpp"

namespace decalcomp {

enum class DecalKind { Box, Volume, Frustum, Cube };
// The material attributes a decal can change, in kernel order (DC_TARGET_* in kernels/shared_types.h).
enum class DecalTarget { Albedo, Normal, Roughness, Metallic, AmbientOcclusion, Emission };
constexpr int kDecalTargets = 6;
// How a target's decal value v meets the surface value a, with f = clamp(g, 0, 1) and
// g = coverage * fades * opacity * mask * factor (docs/scene-format.md "Materials").
enum class BlendOp {
    Over,      // a (1 - f) + v f
    Multiply,  // a (1 - f) + a v f
    Add,       // a + v g
    Replace,   // v wherever g > 0
};
// How a normal map combines with the surface's normal (docs/conventions.md "Normal maps").
enum class NormalBlend { Reoriented, Udn, Whiteout, Replace };
enum class TextureFilter { Nearest, Linear, Mip };

const char* decalKindName(DecalKind k);
const char* decalTargetName(DecalTarget t);  // "albedo", "normal", "roughness", "metallic", "ao", "emission"
const char* blendOpName(BlendOp op);          // "over", "multiply", "add", "replace"
const char* normalBlendName(NormalBlend b);   // "rnm", "udn", "whiteout", "replace"
const char* textureFilterName(TextureFilter f);

// What the slices of a texture are: one 2D image (or independent layers), the slices of one
// volume, or the six faces of a cube. Mip chains and filtering follow the shape.
enum class TextureShape { Flat, Volume, Cube };

// RGBA texels in scene-linear colour with premultiplied alpha, row 0 = the image's top row.
// `depth` > 1 holds that many width x height slices back to back: the slices of a volume
// (slice k covers r in [k/depth, (k+1)/depth]) or the six faces of a cube (+X,-X,+Y,-Y,+Z,-Z).
struct Texture2D {
    std::string source;  // file it came from, for messages
    int width = 0, height = 0, depth = 1;
    TextureShape shape = TextureShape::Flat;  // set by volumeFromStrip, cubeFromStrip, cubeFromFaces
    std::vector<glm::vec4> texels;
};

// A vertical strip of square slices (width W, height D*W) viewed as a W x W x D volume.
Texture2D volumeFromStrip(Texture2D strip);
// A horizontal strip of six square faces (+X,-X,+Y,-Y,+Z,-Z; width 6N, height N) as a cube.
Texture2D cubeFromStrip(const Texture2D& strip);
// Six face images in +X,-X,+Y,-Y,+Z,-Z order, all N x N, as a cube.
Texture2D cubeFromFaces(const std::vector<Texture2D>& faces);
// The mip chain of a texture, level 0 first. Each level has floor(n / 2) texels (at least 1) along
// every axis that shrinks, each the exact box average of the region of the level above it covers:
// 2x2 (2x2x2) texels for even sizes; on an odd axis the boundary texel is shared by overlap
// (n = 5: weights 1, 1, 1/2 and 1/2, 1, 1 over 2.5 texels), so no texel is dropped and the mean is
// kept. Volumes shrink in width, height and depth down to 1x1x1; flat and cube textures shrink
// within each slice down to 1x1 and keep their slices (cube faces never mix).
std::vector<Texture2D> mipChain(const Texture2D& texture);

// Which surfaces a decal may touch. Evaluated per frame into a weight plane (1 = full effect),
// so antialiased Cryptomatte coverage gives antialiased decal edges.
struct DecalMask {
    std::vector<int> include_ids;  // object-id pass values the decal affects (empty = all)
    std::vector<int> exclude_ids;  // object-id pass values it never affects
    std::string cryptomatte_layer;               // e.g. "CryptoObject"; empty = no Cryptomatte
    std::vector<std::string> cryptomatte_names;  // names or wildcards ("Wall*")
    bool operator==(const DecalMask&) const = default;
};

// A placement at one frame of a decal's animation (scene key "keyframes").
struct DecalKeyframe {
    double frame = 0.0;
    glm::dmat4 world_matrix{1.0};
};
enum class KeyframeInterpolation { Linear, Step };

// What a decal does to one target. factor 0 leaves the target alone. `value` is a constant that
// replaces the texture's value for the target (albedo/emission: RGB; others: .r); the textures
// still shape the coverage.
struct TargetEffect {
    float factor = 1.0f;
    BlendOp op = BlendOp::Over;
    std::optional<glm::vec3> value;
    bool operator==(const TargetEffect&) const = default;
};
// Default ops: over, except multiply for ambient occlusion and add for emission.
std::array<TargetEffect, kDecalTargets> defaultTargetEffects();
// Blast occlusion (frustum and cube decals; docs/conventions.md "Blast occlusion"): a depth map
// from the decal's origin built from the G-buffer's own points; the decal reaches only the
// surfaces nearest the origin. Off unless the scene asks for it.
struct DecalOcclusion {
    bool enabled = false;
    int resolution = 256;  // texels along the longer map side (frustum) or a cube face's side
    double bias = 2.0;     // slope-scaled bias in map texels at the point's distance
    bool operator==(const DecalOcclusion&) const = default;
};

// Where a decal is placed (docs/texture-space.md): in the world, or on an object's rest-pose
// mesh, reached per pixel through the frame's UV pass so the decal sticks to the deforming surface.
enum class DecalSpace { World, ObjectRest };
// How a texture-space decal reaches a pixel: through its rest point (exact), or through a UV-space
// bake of the decal read at the pixel's UV (bake, seed 003; docs/texture-space.md "Bake mode").
enum class RestMode { Exact, Bake };

struct Decal {
    std::string name;
    DecalKind kind = DecalKind::Box;
    // decal local space -> world (ObjectRest: -> the rest mesh's object space); local = inverse(M) * P
    glm::dmat4 world_matrix{1.0};
    DecalSpace space = DecalSpace::World;
    int rest_mesh = -1;  // ObjectRest: index into DecalScene::meshes; `mask` selects the object's pixels
    RestMode rest_mode = RestMode::Exact;  // ObjectRest only
    int bake_resolution = 2048;  // Bake: the layer's texels per side
    int bake_dilation = 8;       // Bake: texels beyond island borders that get values (0: none)
    // Bake: names the decal's bake across sceneAtFrame/setDecals (the scene loader numbers bake
    // decals; -1: its index in the scene's decal list). `baked`: the textures already are the bake
    // (bakedDecal(), or a reused "baked" file), looked up at the pixel's UV.
    int bake_slot = -1;
    bool baked = false;
    int albedo_texture = -1;       // index into DecalScene::textures, -1 = none
    // The rest of the texture set (seed 002), same shape as the albedo (2D, volume or cube):
    // a tangent-space normal map (OpenGL, +Y up; data, not colour), occlusion/roughness/metallic
    // in R/G/B, and an emission colour. -1 = none: the surface keeps that attribute.
    int normal_texture = -1, orm_texture = -1, emission_texture = -1;
    std::array<TargetEffect, kDecalTargets> effects = defaultTargetEffects();  // by DecalTarget
    NormalBlend normal_blend = NormalBlend::Reoriented;
    float normal_strength = 1.0f;  // scales the normal map's tilt; 0 = flat
    TargetEffect& effect(DecalTarget t) { return effects[std::size_t(t)]; }
    const TargetEffect& effect(DecalTarget t) const { return effects[std::size_t(t)]; }
    float opacity = 1.0f;          // in [0,1]
    TextureFilter filter = TextureFilter::Linear;
    int mask = -1;  // index into DecalScene::masks, -1 = no mask

    // ---- kind parameters and fades (docs/conventions.md "Decals"); fades are off by default.
    double fov_y_deg = 60.0, aspect = 1.0, near = 0.1, far = 10.0;  // frustum
    // Angle fade: full effect while the surface normal is within angle_fade_deg[0] of the decal's
    // projection axis, none beyond angle_fade_deg[1]; back-facing surfaces never receive it.
    // Needs a normal pass. Off when angle_fade_deg[1] <= 0.
    glm::dvec2 angle_fade_deg{0.0, 0.0};
    double axis_fade = 0.0;  // box/volume: fraction of the half-depth faded at both ends of local Z
    glm::dvec2 distance_fade{0.0, 0.0};  // frustum: fade from distance [0] to [1]; off when [1] <= 0
    DecalOcclusion occlusion;            // frustum/cube only

    // ---- over time (batch sequences, docs/scene-format.md "Animation"); the defaults mean a
    // static decal alive on every frame. sceneAtFrame() evaluates these; the compositor ignores them.
    std::optional<double> first_frame, last_frame;  // lifetime, inclusive ("frames": [first, last])
    double fade_in_frames = 0.0, fade_out_frames = 0.0;  // linear opacity ramps inside the lifetime
    std::vector<DecalKeyframe> keyframes;  // increasing frames; when set, world_matrix = first key's
    KeyframeInterpolation keyframe_interpolation = KeyframeInterpolation::Linear;
    bool isAnimated() const { return first_frame || last_frame || !keyframes.empty(); }
};

struct DecalScene {
    std::string source;  // the scene file it was loaded from ("" when built in code)
    // The scene's identity in the outputs' provenance (provenance.hpp): a hash of its JSON,
    // whitespace and key order aside ("" when built in code).
    std::string fingerprint;
    std::vector<Texture2D> textures;
    std::vector<Decal> decals;  // in blend order
    std::vector<DecalMask> masks;  // distinct masks the decals refer to
    std::vector<RestMesh> meshes;  // rest-pose meshes of texture-space decals
    std::vector<std::string> warnings;  // found while loading (duplicate decal names); the CLI prints them
    // Colour management (docs/colour.md): the OpenColorIO space the colour textures were
    // converted to and the config read ("" for both: built-in sRGB / linear Rec.709 decode).
    std::string working_space, colour_config;
};

// The scene as it is at `frame`: decals outside their lifetime are left out, the others get their
// keyframed placement (translation and scale/shear linear, rotation along the shortest arc) and
// their opacity times the fade factor. Textures and masks are kept; order is kept.
DecalScene sceneAtFrame(const DecalScene& scene, double frame);
// The same for the decal list alone (no texture copy), and for one decal (nullopt = not alive).
std::vector<Decal> decalsAtFrame(const std::vector<Decal>& decals, double frame);
std::optional<Decal> decalAtFrame(const Decal& decal, double frame);
bool isAnimated(const DecalScene& scene);  // any decal with a lifetime or keyframes
bool hasTextureSpaceDecals(const DecalScene& scene);  // any decal placed on a rest mesh

// Whether a decal changes a target: a positive factor and something to take the value from (a
// texture of the set or a constant).
bool decalAffects(const Decal& decal, DecalTarget target);
// The targets any decal of the scene changes, by DecalTarget.
std::array<bool, kDecalTargets> sceneTargets(const DecalScene& scene);
// The texel grid of a decal's occlusion map: a frustum map has the frustum's aspect, its longer
// side `resolution` texels (at least 1 on the shorter); a cube map has six resolution^2 faces.
struct OcclusionMapSize {
    int width = 0, height = 0, faces = 0;
    std::size_t texels() const { return std::size_t(width) * std::size_t(height) * std::size_t(faces); }
};
OcclusionMapSize occlusionMapSize(const Decal& decal);

// True when M is invertible with a usable condition (not degenerate to float precision).
bool isInvertibleDecalMatrix(const glm::dmat4& m);

}  // namespace decalcomp
