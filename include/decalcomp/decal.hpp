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

struct Decal {
    std::string name;
    DecalKind kind = DecalKind::Box;
    glm::dmat4 world_matrix{1.0};  // decal local space -> world; local = inverse(M) * P
    int albedo_texture = -1;       // index into DecalScene::textures, -1 = none
    float opacity = 1.0f;          // in [0,1]
    TextureFilter filter = TextureFilter::Linear;
};

struct DecalScene {
    std::vector<Texture2D> textures;
    std::vector<Decal> decals;  // in blend order
};

// True when M is invertible with a usable condition (not degenerate to float precision).
bool isInvertibleDecalMatrix(const glm::dmat4& m);

}  // namespace decalcomp
