#pragma once
// Pixel geometry of a G-buffer (docs/conventions.md "Pixels", "Depth conventions"): the background
// rule, pixel centres in NDC and the camera/world point each pixel sees under its depth convention.
// The one host implementation; the kernels (kernels/reconstruct.h) and the scalar reference (the
// kernels' test oracle) keep their own.
#include <cstddef>
#include <optional>

#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// Planar and radial depths at or beyond this are background (Blender writes 1e10); the kernels'
// DC_BACKGROUND_DEPTH.
constexpr double kBackgroundDepth = 1e10;
// Perspective points nearer the camera than this (planar) are background.
constexpr double kMinViewDepth = 1e-6;

// The depth value's own part of the background rule: NaN and inf; for planar, radial (and the
// depth pass beside a position pass) <= 0 or >= kBackgroundDepth; for ndc outside [0, 1] or at
// the far end (1, or 0 with reversed-Z). "Beyond the far plane" needs the camera: pixelCameraPoint.
bool isBackgroundDepth(DepthConvention convention, bool reversed_z, double depth);

// True where the pixel is geometry by the depth value alone (isBackgroundDepth), or, without a
// depth pass, where its position is finite.
bool isGeometryPixel(const GBuffer& gbuffer, std::size_t pixel);

// NDC of a point given in display-window pixel coordinates (pixel (i, j)'s centre is (i+0.5, j+0.5)).
glm::dvec2 displayPixelToNdc(const GBuffer& gbuffer, const glm::dvec2& display_pixel);
// NDC of the centre of data-window pixel (x, y).
glm::dvec2 pixelNdc(const GBuffer& gbuffer, int x, int y);
// Camera-space point on the ray through `ndc` at NDC depth `ndc_z` (-1 near plane, +1 far plane).
glm::dvec3 unprojectNdc(const glm::dmat4& inverse_projection, const glm::dvec2& ndc, double ndc_z);

// Camera-space point seen by data-window pixel (x, y), or nullopt for background: the depth rule
// above, a non-finite position or point, a perspective point nearer than kMinViewDepth, or a
// planar depth beyond the camera's far plane.
std::optional<glm::dvec3> pixelCameraPoint(const GBuffer& gbuffer, const Camera& camera, int x, int y);
// The same point in world space.
std::optional<glm::dvec3> pixelWorldPoint(const GBuffer& gbuffer, const Camera& camera, int x, int y);

}  // namespace decalcomp
