// Silhouette and crease pixels under a pixel filter, split between their two surfaces: the scalar
// twin of kernels/pixel_filter.h dc_split_silhouette and dc_split_crease, in double precision,
// noting every decision that float rounding could take the other way.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/tap_plane.hpp"

namespace decalcomp::reference {

namespace {

constexpr double kDepthJump = 0.02;     // DC_MIXED_DEPTH_JUMP
constexpr double kCleanStep = 0.015;    // DC_CLEAN_DEPTH_STEP
constexpr double kShareContrast = 0.01;  // DC_SHARE_CONTRAST
constexpr int kWindow = 3;              // DC_SPLIT_WINDOW
constexpr int kSteps = 16;              // DC_SPLIT_STEPS
constexpr double kRounding = 1e-5;      // relative band in which float and double may disagree
constexpr double kMixedNormalLength = 0.995;  // DC_MIXED_NORMAL_LENGTH
constexpr double kCleanNormalLength = 0.999;  // DC_CLEAN_NORMAL_LENGTH
constexpr double kFaceCos = 0.98;             // DC_CREASE_FACE_COS
constexpr double kFlatCos = 0.999;            // DC_CREASE_FLAT_COS
constexpr double kNormalFit = 0.15;           // DC_CREASE_NORMAL_FIT
constexpr double kSplitNormalFit = 0.5;       // DC_SPLIT_NORMAL_FIT

// `value > limit`, with `ambiguous` set when the two lie within rounding of each other.
bool above(double value, double limit, double scale, bool& ambiguous) {
    if (std::abs(value - limit) <= kRounding * scale) ambiguous = true;
    return value > limit;
}

// `value < limit`, likewise.
bool below(double value, double limit, double scale, bool& ambiguous) {
    if (std::abs(value - limit) <= kRounding * scale) ambiguous = true;
    return value < limit;
}

// The view depth of pixel (x, y) from the frame's map; nullopt off the frame or without a point.
std::optional<double> viewDepth(const GBuffer& f, const std::vector<double>& depths, int x, int y) {
    if (x < 0 || y < 0 || x >= f.width || y >= f.height) return std::nullopt;
    const double z = depths[std::size_t(y) * f.width + x];
    if (std::isnan(z)) return std::nullopt;
    return z;
}

// Every 4-neighbour a surface within kCleanStep of view depth z.
bool cleanPixel(const GBuffer& f, const std::vector<double>& depths, int x, int y, double z, bool& ambiguous) {
    for (int k = 0; k < 4; ++k) {
        const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
        if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height) continue;
        const auto zn = viewDepth(f, depths, nx, ny);
        if (!zn || above(std::abs(*zn - z), kCleanStep * z, z, ambiguous)) return false;
    }
    return true;
}

// The nearer surface's share of the pixel (kernels: dc_mixed_share): from the albedo where the two
// surfaces' albedos differ enough, else from the normal; nullopt where neither tells them apart.
std::optional<double> mixedShare(const GBuffer& f, const Camera& camera, std::size_t i, std::size_t in,
                                 std::size_t jf, bool& ambiguous) {
    const glm::dvec3 a = surfaceAt(f.planes, i).albedo, an = surfaceAt(f.planes, in).albedo,
                     af = surfaceAt(f.planes, jf).albedo;
    const glm::dvec3 da = an - af;
    auto clamped = [](double w) {
        return std::isfinite(w) ? std::optional<double>(std::clamp(w, 0.0, 1.0)) : std::nullopt;
    };
    if (above(glm::dot(da, da), kShareContrast, kShareContrast * 100.0, ambiguous))
        return clamped(glm::dot(a - af, da) / glm::dot(da, da));
    if (!f.has(Attribute::Normal)) return std::nullopt;
    const glm::dvec3 n = worldNormalAsStored(f, camera, i), nn = worldNormalAsStored(f, camera, in),
                     nf = worldNormalAsStored(f, camera, jf);
    const glm::dvec3 dn = nn - nf;
    if (!above(glm::dot(dn, dn), kShareContrast, kShareContrast * 100.0, ambiguous)) return std::nullopt;
    return clamped(glm::dot(n - nf, dn) / glm::dot(dn, dn));
}

// Surface k of the split: the plane through P with world normal n, placed on pixel (x, y)'s ray
// with its taps' footprint; false where the ray misses it or the footprint is not integrated.
bool placeSurface(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, int x, int y,
                  const glm::dvec3& P, const glm::dvec3& n, int k, SurfaceSplit& split) {
    const auto on_ray = rayOnPlane(f, camera, inverse_projection, x, y, P, n);
    if (!on_ray) return false;
    split.point[k] = *on_ray;
    split.normal[k] = n;
    split.plane[k] = tapPlane(f, camera, inverse_projection, x, y, *on_ray, n);
    if (split.plane[k].ambiguous) split.ambiguous = true;
    return split.plane[k].valid;
}

// The filter's weight on the nearer side of the line at c.
double nearWeight(const SurfaceSplit& s, const FilterQuadrature& q, double c) {
    SurfaceSplit at = s;
    at.c = c;
    double sum = 0.0;
    for (std::size_t j = 0; j < q.offsets.size(); ++j)
        for (std::size_t i = 0; i < q.offsets.size(); ++i)
            sum += q.weights[i] * q.weights[j] * at.nearShare(q.offsets[i], q.offsets[j]);
    return sum;
}

}  // namespace

glm::dvec3 worldNormalAsStored(const GBuffer& f, const Camera& camera, std::size_t i) {
    const Plane& plane = f.planes.at(Attribute::Normal);
    glm::dvec3 n(plane.at(i, 0), plane.at(i, 1), plane.at(i, 2));
    if (f.normal_encoding.packed) n = 2.0 * n - 1.0;
    if (f.normal_encoding.space == NormalSpace::Camera) n = glm::transpose(glm::dmat3(camera.world_to_camera)) * n;
    return n;
}

double SurfaceSplit::nearShare(double u, double v) const {
    return std::clamp((c - (dir.x * u + dir.y * v)) / width + 0.5, 0.0, 1.0);
}

std::vector<double> viewDepths(const GBuffer& f, const Camera& camera) {
    std::vector<double> depths(f.pixelCount(), std::nan(""));
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x)
            if (const auto p = pixelCameraPoint(f, camera, x, y)) depths[std::size_t(y) * f.width + x] = -p->z;
    return depths;
}

SurfaceSplit splitSilhouette(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                                const FilterQuadrature& quadrature, const std::vector<double>& depths, int x,
                                int y) {
    SurfaceSplit split;
    const auto own = viewDepth(f, depths, x, y);
    if (!own) return split;
    const double z = *own;
    bool jump = false;
    for (int k = 0; k < 4; ++k) {
        const auto zn = viewDepth(f, depths, x + (k == 0) - (k == 1), y + (k == 2) - (k == 3));
        if (zn && above(std::abs(*zn - z), kDepthJump * z, z, split.ambiguous)) jump = true;
    }
    if (!jump) return split;
    // the window's clean pixels: their depth range, then the nearer and the farther half
    const double radius = double(float(f.pixel_filter.radius()));
    const int window = std::clamp(int(std::ceil(radius + 0.5)) + 1, 2, kWindow);
    double z_min = std::numeric_limits<double>::max(), z_max = 0.0;
    struct Side {
        int x = 0, y = 0, d2 = 1 << 20;
        glm::dvec2 sum{0.0};
        double count = 0.0;
    } side[2];
    for (int pass = 0; pass < 2; ++pass) {
        const double z_mid = 0.5 * (z_min + z_max);
        for (int dy = -window; dy <= window; ++dy)
            for (int dx = -window; dx <= window; ++dx) {
                if (dx == 0 && dy == 0) continue;
                const auto zq = viewDepth(f, depths, x + dx, y + dy);
                if (!zq || !cleanPixel(f, depths, x + dx, y + dy, *zq, split.ambiguous)) continue;
                if (pass == 0) {
                    z_min = std::min(z_min, *zq);
                    z_max = std::max(z_max, *zq);
                    continue;
                }
                Side& s = side[above(*zq, z_mid, z, split.ambiguous) || *zq == z_mid ? 1 : 0];
                s.sum += glm::dvec2(dx, dy);
                s.count += 1.0;
                if (dx * dx + dy * dy < s.d2) {
                    s.d2 = dx * dx + dy * dy;
                    s.x = x + dx;
                    s.y = y + dy;
                }
            }
        if (!above(z_max - z_min, kDepthJump * z, z, split.ambiguous)) return split;
    }
    glm::dvec2 dir = side[1].sum / side[1].count - side[0].sum / side[0].count;
    if (!(glm::length(dir) > 0.25)) return split;
    dir = glm::normalize(dir);
    const std::size_t i = std::size_t(y) * f.width + x;
    const std::size_t at[2] = {std::size_t(side[0].y) * f.width + side[0].x, std::size_t(side[1].y) * f.width + side[1].x};
    const auto share = mixedShare(f, camera, i, at[0], at[1], split.ambiguous);
    if (!share) return split;
    // the surfaces' normals mixed by the share explain the pixel's (not a third surface between them)
    if (f.has(Attribute::Normal)) {
        const glm::dvec3 mix = *share * glm::normalize(worldNormalAsStored(f, camera, at[0])) +
                               (1.0 - *share) * glm::normalize(worldNormalAsStored(f, camera, at[1]));
        if (above(glm::length(mix - worldNormalAsStored(f, camera, i)), kSplitNormalFit, 1.0, split.ambiguous))
            return split;
    }
    for (int k = 0; k < 2; ++k) {
        const glm::dvec3 P = *pixelWorldPoint(f, camera, side[k].x, side[k].y);
        glm::dvec3 n;
        if (f.has(Attribute::Normal)) {
            n = glm::normalize(worldNormalAsStored(f, camera, at[k]));
        } else {
            bool tie = false;
            const glm::dvec3 q = *pixelCameraPoint(f, camera, side[k].x, side[k].y);
            const glm::dvec3 n_camera = normalFromDepth(f, camera, side[k].x, side[k].y, q, tie);
            n = glm::normalize(glm::dvec3(glm::inverse(camera.world_to_camera) * glm::dvec4(n_camera, 0.0)));
            if (tie) split.ambiguous = true;
        }
        if (!placeSurface(f, camera, inverse_projection, x, y, P, n, k, split)) return split;
        split.material[k] = surfaceAt(f.planes, at[k]);
        split.material[k].normal = n;
    }
    // the line where the filter's weight on the nearer side is the nearer surface's share, placed
    // by the kernel's bisection
    split.dir = dir;
    split.width = quadrature.step * (std::abs(dir.x) + std::abs(dir.y));
    const double reach = radius + split.width;
    const double total = nearWeight(split, quadrature, reach);
    double lo = -reach, hi = reach;
    for (int step = 0; step < kSteps; ++step) {
        const double c = 0.5 * (lo + hi);
        (nearWeight(split, quadrature, c) < *share * total ? lo : hi) = c;
    }
    split.c = 0.5 * (lo + hi);
    split.valid = true;
    return split;
}

namespace {

// A crease's two faces: their world normals and nearest clean pixels (kernels: dc_crease_faces).
struct CreaseFaces {
    glm::dvec3 normal[2];
    int x[2] = {0, 0}, y[2] = {0, 0};
};

std::optional<CreaseFaces> creaseFaces(const GBuffer& f, const Camera& camera, const std::vector<double>& depths,
                                       int x, int y, const glm::dvec3& mix, bool& ambiguous) {
    const int window = std::clamp(int(std::ceil(double(float(f.pixel_filter.radius())) + 0.5)) + 1, 2, kWindow);
    // a clean pixel's stored normal: unit length and continuous depth around it
    auto cleanNormal = [&](int nx, int ny) -> std::optional<glm::dvec3> {
        if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height) return std::nullopt;
        const glm::dvec3 n = worldNormalAsStored(f, camera, std::size_t(ny) * f.width + nx);
        if (above(std::abs(glm::length(n) - 1.0), 1.0 - kCleanNormalLength, 1.0, ambiguous)) return std::nullopt;
        const auto zq = viewDepth(f, depths, nx, ny);
        if (!zq || !cleanPixel(f, depths, nx, ny, *zq, ambiguous)) return std::nullopt;
        return n;
    };
    CreaseFaces faces;
    // passes 0 and 1: the clean normal turned furthest from the mix, then from that one
    for (int pass = 0; pass < 2; ++pass) {
        const glm::dvec3 from = pass == 0 ? glm::normalize(mix) : faces.normal[0];
        std::optional<glm::dvec3> pick;
        double least = 2.0;
        for (int dy = -window; dy <= window; ++dy)
            for (int dx = -window; dx <= window; ++dx) {
                if (dx == 0 && dy == 0) continue;
                const auto n = cleanNormal(x + dx, y + dy);
                if (!n) continue;
                const double c = glm::dot(*n, from);
                if (pick && std::abs(c - least) <= kRounding && glm::length(*n - *pick) > 1e-4) ambiguous = true;
                if (c < least) {
                    least = c;
                    pick = *n;
                }
            }
        if (!pick) return std::nullopt;
        faces.normal[pass] = glm::normalize(*pick);
    }
    // pass 2: every clean pixel on one of the two flat faces; each face's nearest
    int best_d2[2] = {1 << 20, 1 << 20};
    for (int dy = -window; dy <= window; ++dy)
        for (int dx = -window; dx <= window; ++dx) {
            if (dx == 0 && dy == 0) continue;
            const auto n = cleanNormal(x + dx, y + dy);
            if (!n) continue;
            const int side = above(glm::dot(*n, faces.normal[1]), glm::dot(*n, faces.normal[0]), 1.0, ambiguous) ? 1 : 0;
            if (below(glm::dot(*n, faces.normal[side]), kFlatCos * glm::length(*n), 1.0, ambiguous)) return std::nullopt;
            if (dx * dx + dy * dy < best_d2[side]) {
                best_d2[side] = dx * dx + dy * dy;
                faces.x[side] = x + dx;
                faces.y[side] = y + dy;
            }
        }
    if (!below(glm::dot(faces.normal[0], faces.normal[1]), kFaceCos, 1.0, ambiguous)) return std::nullopt;
    if (best_d2[0] == 1 << 20 || best_d2[1] == 1 << 20) return std::nullopt;
    return faces;
}

}  // namespace

SurfaceSplit splitCrease(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                         const FilterQuadrature& quadrature, const std::vector<double>& depths, int x, int y,
                         const glm::dvec3& p) {
    SurfaceSplit split;
    if (!f.has(Attribute::Normal)) return split;
    const std::size_t i = std::size_t(y) * f.width + x;
    const glm::dvec3 mix = worldNormalAsStored(f, camera, i);
    if (!below(glm::length(mix), kMixedNormalLength, 1.0, split.ambiguous) || !(glm::length(mix) > 0.0)) return split;
    const auto faces = creaseFaces(f, camera, depths, x, y, mix, split.ambiguous);
    if (!faces) return split;
    auto viewDepthOf = [&](const glm::dvec3& w) { return -(camera.world_to_camera * glm::dvec4(w, 1.0)).z; };
    const double z = viewDepthOf(p);
    glm::dvec3 clean_point[2];
    std::size_t at[2];
    for (int k = 0; k < 2; ++k) {
        at[k] = std::size_t(faces->y[k]) * f.width + faces->x[k];
        clean_point[k] = *pixelWorldPoint(f, camera, faces->x[k], faces->y[k]);
        if (!placeSurface(f, camera, inverse_projection, x, y, clean_point[k], faces->normal[k], k, split))
            return split;
    }
    // both faces pass through the pixel's own point (no depth jump)
    for (int k = 0; k < 2; ++k)
        if (above(std::abs(viewDepthOf(split.point[k]) - z), kDepthJump * z, z, split.ambiguous)) return split;
    // the image of the faces' edge, linearised at the pixel centre
    auto sideOf = [&](double u, double v) {
        const PixelRay r = pixelRay(f, camera, inverse_projection, x + u, y + v);
        return glm::dot(r.origin - split.point[0], split.normal[0]) * glm::dot(r.dir, split.normal[1]) -
               glm::dot(r.origin - split.point[1], split.normal[1]) * glm::dot(r.dir, split.normal[0]);
    };
    const double f00 = sideOf(0.0, 0.0);
    const glm::dvec2 g(sideOf(1.0, 0.0) - f00, sideOf(0.0, 1.0) - f00);
    if (!(glm::length(g) > 0.0)) return split;
    double c = -f00 / glm::length(g);
    glm::dvec2 dir = g / glm::length(g);
    const double radius = double(float(f.pixel_filter.radius()));
    if (above(std::abs(c), radius, radius, split.ambiguous)) return split;
    // face 0 keeps the side where it is the plane a ray meets (kernels: dc_split_crease)
    const glm::dvec3 ray_dir = pixelRay(f, camera, inverse_projection, x, y).dir;
    const bool concave = above(glm::dot(clean_point[1] - clean_point[0], split.normal[0]), 0.0,
                               glm::length(clean_point[1] - clean_point[0]), split.ambiguous);
    const bool facing = above(glm::dot(ray_dir, split.normal[0]) * glm::dot(ray_dir, split.normal[1]), 0.0,
                              glm::dot(ray_dir, ray_dir), split.ambiguous);
    if (concave == facing) {
        dir = -dir;
        c = -c;
    }
    split.dir = dir;
    split.width = quadrature.step * (std::abs(dir.x) + std::abs(dir.y));
    // each face's clean material shifted by one offset, so that their mix is the pixel's own
    const double w = nearWeight(split, quadrature, c) / nearWeight(split, quadrature, std::numeric_limits<double>::infinity());
    // the faces' normals mixed by the split's weights give the pixel's (an occluding edge does not)
    if (above(glm::length(w * split.normal[0] + (1.0 - w) * split.normal[1] - mix), kNormalFit, 1.0, split.ambiguous))
        return split;
    split.c = c;
    const Surface mine = surfaceAt(f.planes, i), a = surfaceAt(f.planes, at[0]), b = surfaceAt(f.planes, at[1]);
    const glm::dvec3 albedo_shift = mine.albedo - (w * a.albedo + (1.0 - w) * b.albedo);
    const double roughness_shift = mine.roughness - (w * a.roughness + (1.0 - w) * b.roughness);
    const double metallic_shift = mine.metallic - (w * a.metallic + (1.0 - w) * b.metallic);
    for (int k = 0; k < 2; ++k) {
        Surface& m = split.material[k];
        m = k == 0 ? a : b;
        m.albedo += albedo_shift;
        m.roughness += roughness_shift;
        m.metallic += metallic_shift;
        m.normal = split.normal[k];
    }
    split.valid = true;
    return split;
}

}  // namespace decalcomp::reference
