#pragma once
// Between a normal plane's stored vectors (its space and encoding, GBuffer::normal_encoding) and
// world space: what compositing, the preview and write-back share.
#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

class NormalCodec {
public:
    NormalCodec(const NormalEncoding& encoding, const Camera& camera);
    // Stored -> world, not renormalised (an unchanged pixel must round-trip bit for bit).
    glm::vec3 toWorld(const glm::vec3& stored) const;
    // World (unit) -> stored, in the plane's space and encoding.
    glm::vec3 toStored(const glm::vec3& world) const;
    // World -> the camera's own axes (-Z forward, +Y up).
    glm::vec3 worldToCamera(const glm::vec3& world) const;

private:
    NormalEncoding encoding_;
    // Normals go from camera to world space by the transpose of the camera rotation (the inverse
    // transpose of camera -> world), and back by its inverse.
    glm::dmat3 to_world_, to_camera_;
};

}  // namespace decalcomp
