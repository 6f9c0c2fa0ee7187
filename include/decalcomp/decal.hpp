#pragma once
// Decals and their textures as the compositor consumes them (already validated and decoded).
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace decalcomp {

enum class DecalKind { Box };
enum class TextureFilter { Nearest, Linear };

const char* decalKindName(DecalKind k);
const char* textureFilterName(TextureFilter f);

// RGBA texels in scene-linear colour with premultiplied alpha, row 0 = the image's top row.
struct Texture2D {
    std::string source;  // file it came from, for messages
    int width = 0, height = 0;
    std::vector<glm::vec4> texels;
};

// Which surfaces a decal may touch. Evaluated per frame into a weight plane (1 = full effect),
// so antialiased Cryptomatte coverage gives antialiased decal edges.
struct DecalMask {
    std::vector<int> include_ids;  // object-id pass values the decal affects (empty = all)
    std::vector<int> exclude_ids;  // object-id pass values it never affects
    std::string cryptomatte_layer;               // e.g. "CryptoObject"; empty = no Cryptomatte
    std::vector<std::string> cryptomatte_names;  // names or wildcards ("Wall*")
    bool operator==(const DecalMask&) const = default;
};

struct Decal {
    std::string name;
    DecalKind kind = DecalKind::Box;
    glm::dmat4 world_matrix{1.0};  // decal local space -> world; local = inverse(M) * P
    int albedo_texture = -1;       // index into DecalScene::textures, -1 = none
    float opacity = 1.0f;          // in [0,1]
    TextureFilter filter = TextureFilter::Linear;
    int mask = -1;  // index into DecalScene::masks, -1 = no mask
};

struct DecalScene {
    std::vector<Texture2D> textures;
    std::vector<Decal> decals;  // in blend order
    std::vector<DecalMask> masks;  // distinct masks the decals refer to
};

// True when M is invertible with a usable condition (not degenerate to float precision).
bool isInvertibleDecalMatrix(const glm::dmat4& m);

}  // namespace decalcomp
