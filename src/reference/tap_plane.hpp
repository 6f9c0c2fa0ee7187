#pragma once
// The pixel filter's geometry in the reference (reference.cpp, surface_split.cpp): the taps'
// planes and where pixel rays meet them, in world space, double precision.
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/gbuffer.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

// The ray through fractional pixel position (px, py) in world space: origin + t dir, dir reaching
// the NDC z = 0 plane at t = 1 (the kernels' dc_pixel_ray).
struct PixelRay {
    glm::dvec3 origin, dir;
};
PixelRay pixelRay(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, double px, double py);

// Where the ray through fractional pixel position (px, py) meets the plane through P with normal
// n (world space); nullopt when it runs parallel or meets it behind the camera.
std::optional<glm::dvec3> rayOnPlane(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                                     double px, double py, const glm::dvec3& P, const glm::dvec3& n);

// The file's normal at pixel i decoded to world space, not normalised (a filtered normal is shorter
// than 1).
glm::dvec3 worldNormalAsStored(const GBuffer& f, const Camera& camera, std::size_t i);

// Camera-space normal from neighbouring points, per axis from the neighbour nearer in depth; `tie`
// is set when both neighbours are about as near, so float rounding may pick either.
glm::dvec3 normalFromDepth(const GBuffer& f, const Camera& camera, int x, int y, const glm::dvec3& p, bool& tie);

// The pixel filter's footprint on pixel (x, y)'s tangent plane through P (on the pixel's ray) with
// normal n (docs/pixel-filter.md), or invalid where the filter is not integrated over it: beside
// background (a 4-neighbour without a point) and where a footprint corner strays more than 4 % in
// view depth (grazing).
struct TapPlane {
    bool valid = false;
    bool beside_background = false;
    bool ambiguous = false;       // the grazing test within rounding of its threshold
    glm::dvec3 du{0.0}, dv{0.0};  // world step per pixel offset at the centre
};
TapPlane tapPlane(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, int x, int y,
                  const glm::dvec3& P, const glm::dvec3& n);

// A silhouette's or a crease's taps split between its two surfaces (docs/pixel-filter.md
// "Silhouettes" and "Creases", kernels/pixel_filter.h dc_split_silhouette and dc_split_crease).
struct SurfaceSplit {
    bool valid = false;
    bool ambiguous = false;  // a decision within rounding of its threshold
    glm::dvec3 point[2];     // [0] the nearer surface (a crease's first face), [1] the farther: plane point on the pixel's ray
    glm::dvec3 normal[2];    // and the plane's world normal
    TapPlane plane[2];
    Surface material[2];     // each surface's material as the file holds it (its clean pixel's)
    glm::dvec2 dir{0.0};
    double c = 0.0, width = 1.0;
    // the share of the tap at pixel offset (u, v) on the nearer surface
    double nearShare(double u, double v) const;
};
// Every pixel's view depth (NaN where it has no point), which splitSilhouette reads many times.
std::vector<double> viewDepths(const GBuffer& f, const Camera& camera);
SurfaceSplit splitSilhouette(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                                const FilterQuadrature& quadrature, const std::vector<double>& view_depths, int x,
                                int y);
// A crease pixel (an averaged normal without a depth jump) split between its two flat faces along
// the image of their edge; `p` is the pixel's world point. Invalid elsewhere.
SurfaceSplit splitCrease(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                         const FilterQuadrature& quadrature, const std::vector<double>& view_depths, int x, int y,
                         const glm::dvec3& p);

}  // namespace decalcomp::reference
