#include "decalcomp/normal_codec.hpp"

namespace decalcomp {

NormalCodec::NormalCodec(const NormalEncoding& encoding, const Camera& camera)
    : encoding_(encoding),
      to_world_(glm::transpose(glm::dmat3(camera.world_to_camera))),
      to_camera_(glm::inverse(to_world_)) {}

glm::vec3 NormalCodec::toWorld(const glm::vec3& stored) const {
    glm::dvec3 n(stored);
    if (encoding_.packed) n = n * 2.0 - 1.0;
    if (encoding_.space == NormalSpace::Camera) n = to_world_ * n;
    return glm::vec3(n);
}

glm::vec3 NormalCodec::toStored(const glm::vec3& world) const {
    glm::dvec3 n(world);
    if (encoding_.space == NormalSpace::Camera) n = glm::normalize(to_camera_ * n);
    if (encoding_.packed) n = n * 0.5 + 0.5;
    return glm::vec3(n);
}

glm::vec3 NormalCodec::worldToCamera(const glm::vec3& world) const { return glm::vec3(to_camera_ * glm::dvec3(world)); }

}  // namespace decalcomp
