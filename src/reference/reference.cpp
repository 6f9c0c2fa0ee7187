#include "decalcomp/reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/decal_hit.hpp"
#include "reference/filter_integral.hpp"
#include "reference/tap_plane.hpp"
#include "reference/occlusion.hpp"
#include "reference/rest_pose.hpp"

namespace decalcomp::reference {

namespace {

constexpr double kBackgroundDepth = 1e10;
constexpr double kMinViewDepth = 1e-6;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Pixel centre in NDC, over the display window.
glm::dvec2 pixelNdc(const GBuffer& f, int x, int y) {
    return {2.0 * (x + f.origin_x + 0.5) / f.display_width - 1.0, 1.0 - 2.0 * (y + f.origin_y + 0.5) / f.display_height};
}

// Camera-space point on the pixel's ray at NDC depth z.
glm::dvec3 unproject(const glm::dmat4& inverse_projection, glm::dvec2 ndc, double z) {
    const glm::dvec4 c = inverse_projection * glm::dvec4(ndc, z, 1.0);
    return glm::dvec3(c) / c.w;
}

}  // namespace

std::optional<glm::dvec3> pixelCameraPoint(const GBuffer& f, const Camera& camera, int x, int y) {
    const std::size_t i = std::size_t(y) * f.width + x;
    const bool perspective = !camera.isOrthographic();
    const glm::dmat4 inverse_projection = glm::inverse(camera.projection);
    const glm::dvec2 ndc = pixelNdc(f, x, y);
    const bool has_depth = f.has(Attribute::Depth);
    const double d = has_depth ? f.planes.at(Attribute::Depth).at(i, 0) : 1.0;
    const bool depth_background = !(d > 0.0) || std::isinf(d) || d >= kBackgroundDepth;
    glm::dvec3 p;
    switch (f.depth_convention) {
        case DepthConvention::Position: {
            if (has_depth && depth_background) return std::nullopt;
            const Plane& pos = f.planes.at(Attribute::Position);
            const glm::dvec3 w(pos.at(i, 0), pos.at(i, 1), pos.at(i, 2));
            if (!finite3(w)) return std::nullopt;
            p = glm::dvec3(camera.world_to_camera * glm::dvec4(w, 1.0));
            break;
        }
        case DepthConvention::Ndc: {
            if (std::isnan(d) || d < 0.0 || d > 1.0 || (f.reversed_z ? d <= 0.0 : d >= 1.0)) return std::nullopt;
            p = unproject(inverse_projection, ndc, f.reversed_z ? 1.0 - 2.0 * d : 2.0 * d - 1.0);
            break;
        }
        case DepthConvention::Planar:
        case DepthConvention::Radial: {
            if (depth_background) return std::nullopt;
            const glm::dvec3 near_point = unproject(inverse_projection, ndc, -1.0);
            const glm::dvec3 far_point = unproject(inverse_projection, ndc, 0.0);  // finite if far = inf
            const glm::dvec3 dir = far_point - near_point;
            if (perspective && f.depth_convention == DepthConvention::Radial) {
                p = glm::normalize(dir) * d;  // the ray leaves the camera origin
            } else {
                // intersect the ray with the plane z = -d
                p = near_point + dir * ((-d - near_point.z) / dir.z);
            }
            break;
        }
    }
    if (perspective && !(-p.z >= kMinViewDepth)) return std::nullopt;
    const double far = camera.farPlane();
    if (std::isfinite(far) && far > 0.0 && -p.z > double(float(far))) return std::nullopt;
    if (!finite3(p)) return std::nullopt;
    return p;
}

// Normal from neighbouring points (camera space), per axis from the neighbour nearer in depth;
// `tie` is set when both neighbours are about as near, so float rounding may pick either.
glm::dvec3 normalFromDepth(const GBuffer& f, const Camera& camera, int x, int y, const glm::dvec3& p, bool& tie) {
    glm::dvec3 axis[2];
    int found = 0;
    for (int a = 0; a < 2; ++a) {
        double gaps[2] = {-1.0, -1.0};
        glm::dvec3 diffs[2];
        for (int side = 0; side < 2; ++side) {
            const int step = side == 0 ? -1 : 1;
            const int nx = a == 0 ? x + step : x, ny = a == 0 ? y : y + step;
            if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height) continue;
            const auto q = pixelCameraPoint(f, camera, nx, ny);
            if (!q) continue;
            gaps[side] = std::abs(q->z - p.z);
            diffs[side] = (*q - p) * double(step);
        }
        if (gaps[0] < 0 && gaps[1] < 0) continue;
        int pick = gaps[0] < 0 ? 1 : gaps[1] < 0 ? 0 : (gaps[1] < gaps[0] ? 1 : 0);
        // a near tie matters only where the two sides disagree (curved surfaces; planes agree)
        if (gaps[0] >= 0 && gaps[1] >= 0 && std::abs(gaps[0] - gaps[1]) <= 1e-4 * (gaps[0] + gaps[1]) + 1e-7 &&
            glm::length(glm::cross(glm::normalize(diffs[0]), glm::normalize(diffs[1]))) > 1e-5)
            tie = true;
        axis[a] = diffs[pick];
        ++found;
    }
    const glm::dvec3 towards_camera = -glm::normalize(p);
    if (found < 2) return towards_camera;
    glm::dvec3 n = glm::cross(axis[0], axis[1]);
    if (!(glm::length(n) > 0.0)) return towards_camera;
    n = glm::normalize(n);
    return glm::dot(n, towards_camera) < 0.0 ? -n : n;
}

std::optional<glm::dvec3> pixelWorldPoint(const GBuffer& frame, const Camera& camera, int x, int y) {
    auto p = pixelCameraPoint(frame, camera, x, y);
    if (!p) return std::nullopt;
    return glm::dvec3(glm::inverse(camera.world_to_camera) * glm::dvec4(*p, 1.0));
}

std::vector<DepthRange> tileDepthRanges(const GBuffer& frame, const Camera& camera, int tile_size) {
    const int tiles_x = (frame.width + tile_size - 1) / tile_size;
    const int tiles_y = (frame.height + tile_size - 1) / tile_size;
    std::vector<DepthRange> ranges(std::size_t(tiles_x) * tiles_y);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = pixelCameraPoint(frame, camera, x, y);
            if (!p) continue;
            DepthRange& r = ranges[std::size_t(y / tile_size) * tiles_x + x / tile_size];
            const double depth = -p->z;
            r.min = r.empty ? depth : std::min(r.min, depth);
            r.max = r.empty ? depth : std::max(r.max, depth);
            r.empty = false;
        }
    return ranges;
}

// Whether local point l lies in the decal's volume (docs/conventions.md "Decals").
bool insideDecal(const Decal& decal, const glm::dvec3& l) {
    switch (decal.kind) {
        case DecalKind::Box:
        case DecalKind::Volume: return std::abs(l.x) <= 0.5 && std::abs(l.y) <= 0.5 && std::abs(l.z) <= 0.5;
        case DecalKind::Cube: return glm::length(l) <= 0.5;
        case DecalKind::Frustum: {
            const double dist = -l.z, half_h = dist * std::tan(glm::radians(decal.fov_y_deg) / 2.0);
            return dist >= decal.near && dist <= decal.far && std::abs(l.x) <= half_h * decal.aspect &&
                   std::abs(l.y) <= half_h;
        }
    }
    return false;
}

std::vector<std::vector<int>> exactBins(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                                        int tile_size) {
    const int tiles_x = (frame.width + tile_size - 1) / tile_size;
    const int tiles_y = (frame.height + tile_size - 1) / tile_size;
    std::vector<std::vector<char>> hit(std::size_t(tiles_x) * tiles_y, std::vector<char>(scene.decals.size(), 0));
    std::vector<glm::dmat4> world_to_local;
    for (const Decal& d : scene.decals) world_to_local.push_back(glm::inverse(d.world_matrix));
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = pixelWorldPoint(frame, camera, x, y);
            if (!p) continue;
            auto& tile = hit[std::size_t(y / tile_size) * tiles_x + x / tile_size];
            for (std::size_t k = 0; k < scene.decals.size(); ++k) {
                if (insideDecal(scene.decals[k], glm::dvec3(world_to_local[k] * glm::dvec4(*p, 1.0)))) tile[k] = 1;
            }
        }
    std::vector<std::vector<int>> bins(hit.size());
    for (std::size_t t = 0; t < hit.size(); ++t)
        for (std::size_t k = 0; k < scene.decals.size(); ++k)
            if (hit[t][k]) bins[t].push_back(int(k));
    return bins;
}

glm::dvec4 texelAt(const Texture2D& texture, long i, long j, long slice) {
    i = std::clamp<long>(i, 0, texture.width - 1);
    j = std::clamp<long>(j, 0, texture.height - 1);
    slice = std::clamp<long>(slice, 0, texture.depth - 1);
    return glm::dvec4(
        texture.texels[(std::size_t(slice) * texture.height + std::size_t(j)) * texture.width + std::size_t(i)]);
}

namespace {

// Bilinear between the four texel centres ((i + 0.5) / width) around texel-space point (x, y);
// `texel(i, j)` fetches a tap, which may lie one texel outside the image.
template <class Texel>
glm::dvec4 bilinear(double x, double y, Texel texel) {
    const double fx = x - 0.5, fy = y - 0.5;
    const long i = long(std::floor(fx)), j = long(std::floor(fy));
    const double ax = fx - i, ay = fy - j;
    return (texel(i, j) * (1 - ax) + texel(i + 1, j) * ax) * (1 - ay) +
           (texel(i, j + 1) * (1 - ax) + texel(i + 1, j + 1) * ax) * ay;
}

glm::dvec4 sampleSlice(const Texture2D& texture, double s, double t, long slice, TextureFilter filter) {
    const double x = std::clamp(s * texture.width, -1.0, double(texture.width) + 1.0);
    const double y = std::clamp(t * texture.height, -1.0, double(texture.height) + 1.0);
    if (filter == TextureFilter::Nearest) return texelAt(texture, long(std::floor(x)), long(std::floor(y)), slice);
    return bilinear(x, y, [&](long i, long j) { return texelAt(texture, i, j, slice); });
}

// Nearest texels integrated exactly over a box `rho` texels wide per axis centred on (s, t).
glm::dvec4 boxIntegratedNearest(const Texture2D& texture, double s, double t, glm::dvec2 rho) {
    const glm::dvec2 c(std::clamp(s * texture.width, -1.0, double(texture.width) + 1.0),
                       std::clamp(t * texture.height, -1.0, double(texture.height) + 1.0));
    const glm::dvec2 r = glm::max(rho, glm::dvec2(1e-6));
    const glm::dvec2 lo = c - 0.5 * r, hi = c + 0.5 * r;
    glm::dvec4 sum(0.0);
    for (long j = long(std::floor(lo.y)); double(j) < hi.y; ++j)
        for (long i = long(std::floor(lo.x)); double(i) < hi.x; ++i) {
            const double wx = std::max(0.0, std::min(hi.x, i + 1.0) - std::max(lo.x, double(i))) / r.x;
            const double wy = std::max(0.0, std::min(hi.y, j + 1.0) - std::max(lo.y, double(j))) / r.y;
            sum += texelAt(texture, i, j, 0) * (wx * wy);
        }
    return sum;
}

// Each cube face as the direction of its centre and the directions in which s and t grow
// (the OpenGL cube-map rule: +X s = -z t = -y; -X s = z t = -y; +Y s = x t = z; -Y s = x t = -z;
// +Z s = x t = -y; -Z s = -x t = -y).
struct FaceFrame {
    glm::dvec3 centre, s_axis, t_axis;
};
const FaceFrame kCubeFaces[6] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}}, {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
};

// Texel (i, j) of a cube face where i or j may lie one texel outside it: a tap past one edge is
// the nearest texel of the face that the direction of its centre on the extended face plane picks;
// a tap past two edges (a cube corner) is the mean of the three texels that meet at that corner.
glm::dvec4 cubeTexel(const Texture2D& texture, int face, long i, long j) {
    const bool inside_i = i >= 0 && i < texture.width, inside_j = j >= 0 && j < texture.height;
    if (inside_i && inside_j) return texelAt(texture, i, j, face);
    auto across = [&](long a, long b) {
        const FaceFrame& f = kCubeFaces[face];
        const double u = (a + 0.5) / texture.width * 2.0 - 1.0, v = (b + 0.5) / texture.height * 2.0 - 1.0;
        const CubeLookup c = cubeLookup(f.centre + u * f.s_axis + v * f.t_axis);
        return texelAt(texture, long(std::floor(c.s * texture.width)), long(std::floor(c.t * texture.height)), c.face);
    };
    if (inside_i || inside_j) return across(i, j);
    const long ci = std::clamp<long>(i, 0, texture.width - 1), cj = std::clamp<long>(j, 0, texture.height - 1);
    return (texelAt(texture, ci, cj, face) + across(i, cj) + across(ci, j)) / 3.0;
}

// A lookup at (s, t) on one cube face: nearest within the face, bilinear across its edges.
glm::dvec4 sampleCubeFace(const Texture2D& texture, int face, double s, double t, TextureFilter filter) {
    if (filter == TextureFilter::Nearest) return sampleSlice(texture, s, t, face, filter);
    return bilinear(s * texture.width, t * texture.height,
                    [&](long i, long j) { return cubeTexel(texture, face, i, j); });
}

}  // namespace

glm::dvec4 sampleTexture(const Texture2D& texture, double s, double t, TextureFilter filter) {
    return sampleSlice(texture, s, t, 0, filter);
}

glm::dvec4 sampleVolume(const Texture2D& texture, double s, double t, double r, TextureFilter filter) {
    const double z = std::clamp(r * texture.depth, -1.0, double(texture.depth) + 1.0);
    if (filter == TextureFilter::Nearest) return sampleSlice(texture, s, t, long(std::floor(z)), filter);
    const double fz = z - 0.5;
    const long k = long(std::floor(fz));
    const double a = fz - k;
    return sampleSlice(texture, s, t, k, filter) * (1 - a) + sampleSlice(texture, s, t, k + 1, filter) * a;
}

CubeLookup cubeLookup(const glm::dvec3& d) {
    const glm::dvec3 a = glm::abs(d);
    CubeLookup c;
    double sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {  // ties: x before y before z
        c.face = d.x >= 0 ? 0 : 1;
        ma = a.x;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        c.face = d.y >= 0 ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        c.face = d.z >= 0 ? 4 : 5;
        ma = a.z;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    c.s = 0.5 * (sc / ma + 1.0);
    c.t = 0.5 * (tc / ma + 1.0);
    return c;
}

glm::dvec4 sampleCube(const Texture2D& texture, const glm::dvec3& direction, TextureFilter filter) {
    const CubeLookup c = cubeLookup(direction);
    return sampleCubeFace(texture, c.face, c.s, c.t, filter);
}

// 1 up to `full`, 0 from `none`, linear between.
double rampDown(double x, double full, double none) { return std::clamp((none - x) / (none - full), 0.0, 1.0); }

namespace {

// Mip lookup: the levels around lod, each filtered by `level_lookup(level)`, blended.
template <class LevelLookup>
glm::dvec4 sampleMip(const std::vector<Texture2D>& chain, double lod, LevelLookup level_lookup) {
    lod = std::clamp(lod, 0.0, double(chain.size() - 1));
    const std::size_t l0 = std::size_t(std::floor(lod)), l1 = std::min(l0 + 1, chain.size() - 1);
    const double f = lod - double(l0);
    const glm::dvec4 a = level_lookup(chain[l0]);
    return f > 0.0 ? a * (1.0 - f) + level_lookup(chain[l1]) * f : a;
}

// log2 of the longer footprint axis in level-0 texels (0 when magnified).
double levelOfDetail(glm::dvec2 st, glm::dvec2 st_dx, glm::dvec2 st_dy, const Texture2D& t) {
    const glm::dvec2 size(t.width, t.height);
    const double rho = std::max(glm::length((st_dx - st) * size), glm::length((st_dy - st) * size));
    return rho > 1.0 ? std::log2(rho) : 0.0;
}

// How much of a stratum spanning `extent` lies where `inside` >= 0 (a straight edge across a box).
// A ramp much steeper than rounding (`slack` in the same measure) can flip like a step: then
// `ambiguous` is set near the edge.
double stratumCoverage(double inside, double extent, double slack, bool& ambiguous) {
    if (std::abs(inside) <= 0.5 * extent + slack && slack > 0.05 * extent) ambiguous = true;
    if (!(extent > 1e-12)) return inside >= 0.0 ? 1.0 : 0.0;
    return std::clamp(inside / extent + 0.5, 0.0, 1.0);
}

}  // namespace

// A cube decal's facing, face and face axes at local point l (0 < |l| <= 0.5) of world point P.
void cubeFaceAt(const Decal& decal, const glm::dvec3& l, const glm::dvec3& P, double slack, DecalHit& out) {
    const double r = glm::length(l);
    const glm::dmat3 axes(decal.world_matrix);
    out.facing = glm::normalize(glm::dvec3(decal.world_matrix[3]) - P);
    // the direction's rounding error grows as the point nears the centre
    out.direction_slack = slack / r;
    const glm::dvec3 a = glm::abs(l / r);
    const double hi = std::max({a.x, a.y, a.z});
    const double mid = a.x + a.y + a.z - hi - std::min({a.x, a.y, a.z});
    out.ambiguous |= hi - mid <= out.direction_slack;  // face choice
    out.cube = cubeLookup(l / r);
    // the face image's right and up in local space (faces are seen from inside: mirrored)
    const glm::dvec3 face_right[6] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {-1, 0, 0}};
    const glm::dvec3 face_up[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
    out.right = axes * face_right[out.cube.face];
    out.up = axes * face_up[out.cube.face];
}

DecalHit hitDecal(const Decal& decal, const glm::dmat4& world_to_local, const glm::dvec3& P,
                  const std::optional<glm::dvec3>& normal, const Footprint& footprint, double slack,
                  const Stratum* stratum) {
    DecalHit out;
    const glm::dvec3 l(world_to_local * glm::dvec4(P, 1.0));
    out.local = l;
    out.footprint = footprint.valid;
    out.local_dx = glm::dvec3(world_to_local * glm::dvec4(footprint.dx, 1.0));
    out.local_dy = glm::dvec3(world_to_local * glm::dvec4(footprint.dy, 1.0));
    if (stratum) {
        out.filtered = out.footprint = true;
        out.local_dx = l + stratum->su;
        out.local_dy = l + stratum->sv;
    }
    const glm::dvec3 extent = stratum ? glm::abs(stratum->su) + glm::abs(stratum->sv) : glm::dvec3(0.0);
    const glm::dmat3 axes(decal.world_matrix);
    out.right = axes[0];
    out.up = axes[1];
    double fade = 1.0;
    switch (decal.kind) {
        case DecalKind::Box:
        case DecalKind::Volume: {
            if (stratum) {
                bool& a = out.ambiguous;
                fade = stratumCoverage(0.5 - std::abs(l.x), extent.x, slack, a) *
                       stratumCoverage(0.5 - std::abs(l.y), extent.y, slack, a) *
                       stratumCoverage(0.5 - std::abs(l.z), extent.z, slack, a);
                if (!(fade > 0.0)) return out;
            } else {
                const double reach = std::max({std::abs(l.x), std::abs(l.y), std::abs(l.z)});
                out.ambiguous = std::abs(reach - 0.5) <= slack;
                if (reach > 0.5) return out;
            }
            if (decal.axis_fade > 0.0) fade *= std::clamp((0.5 - std::abs(l.z)) / (0.5 * decal.axis_fade), 0.0, 1.0);
            out.facing = glm::normalize(glm::dvec3(decal.world_matrix[2]));
            break;
        }
        case DecalKind::Frustum: {
            const double dist = -l.z;
            const double half_h = dist * std::tan(glm::radians(decal.fov_y_deg) / 2.0), half_w = half_h * decal.aspect;
            if (stratum) {
                bool& a = out.ambiguous;
                const double edge_slack = 2.0 * slack;  // both sides of each comparison carry rounding
                fade = stratumCoverage(dist - decal.near, extent.z, edge_slack, a) *
                       stratumCoverage(decal.far - dist, extent.z, edge_slack, a) *
                       stratumCoverage(half_w - std::abs(l.x), extent.x, edge_slack, a) *
                       stratumCoverage(half_h - std::abs(l.y), extent.y, edge_slack, a);
                if (!(fade > 0.0 && dist > 0.0)) return out;
            } else {
                const double edge_slack = 2.0 * slack;  // both sides of each comparison carry rounding
                out.ambiguous = std::abs(dist - decal.near) <= edge_slack || std::abs(dist - decal.far) <= edge_slack ||
                                std::abs(std::abs(l.x) - half_w) <= edge_slack ||
                                std::abs(std::abs(l.y) - half_h) <= edge_slack;
                if (!(dist >= decal.near && dist <= decal.far && std::abs(l.x) <= half_w && std::abs(l.y) <= half_h))
                    return out;
            }
            if (decal.distance_fade[1] > 0.0) fade *= rampDown(dist, decal.distance_fade[0], decal.distance_fade[1]);
            out.facing = glm::normalize(glm::dvec3(decal.world_matrix[3]) - P);
            break;
        }
        case DecalKind::Cube: {
            const double r = glm::length(l);
            out.ambiguous = std::abs(r - 0.5) <= slack;
            if (r > 0.5 || r == 0.0) return out;
            fade *= std::clamp(1.0 - r / 0.5, 0.0, 1.0);
            cubeFaceAt(decal, l, P, slack, out);
            break;
        }
    }
    if (normal && decal.angle_fade_deg[1] > 0.0) {
        const double cosine = glm::dot(*normal, out.facing);
        if (std::abs(cosine) <= 1e-4) out.ambiguous = true;  // the back-face cut is a step
        fade *= cosine <= 0.0 ? 0.0
                              : rampDown(std::acos(std::min(cosine, 1.0)), glm::radians(decal.angle_fade_deg[0]),
                                         glm::radians(decal.angle_fade_deg[1]));
    }
    out.fade = fade;
    return out;
}

// A texture of the decal's set at the hit, with the decal's filter (premultiplied RGBA); sets
// `ambiguous` when a nearest lookup lies within rounding of a texel edge.
glm::dvec4 hitTexel(const DecalHit& hit, const Decal& decal, const Texture2D& t, const std::vector<Texture2D>& chain,
                    double slack, bool& ambiguous) {
    return hitTexelScaled(hit, decal, t, chain, slack, ambiguous, 1.0);
}

// hitTexel, the footprint's texture coordinates scaled by `scale` around the hit's (the closed
// form's read over the filter's equivalent box, dc_integrated_texel: local_dx/dy one pixel away).
glm::dvec4 hitTexelScaled(const DecalHit& hit, const Decal& decal, const Texture2D& t,
                          const std::vector<Texture2D>& chain, double slack, bool& ambiguous, double scale) {
    auto nearEdge = [&](double coord, int size, double within) {
        const double x = coord * size;
        return decal.filter == TextureFilter::Nearest && std::abs(x - std::round(x)) <= within * size;
    };
    const glm::dvec3& l = hit.local;
    // A filter tap integrates its stratum: nearest texels box-integrated over strata up to two
    // texels wide, the mip chain at the stratum's size otherwise.
    const TextureFilter filter = hit.filtered ? TextureFilter::Mip : decal.filter;
    // A 2D lookup through `st_of` (local point -> s, t); mip level from the footprint's mapping.
    auto lookup2d = [&](auto st_of) {
        const glm::dvec2 st = st_of(l);
        auto footprint_st = [&](const glm::dvec3& v) { return st + (st_of(v) - st) * scale; };
        if (hit.filtered && decal.filter == TextureFilter::Nearest) {
            const glm::dvec2 size(t.width, t.height);
            const glm::dvec2 rho =
                (glm::abs(footprint_st(hit.local_dx) - st) + glm::abs(footprint_st(hit.local_dy) - st)) * size;
            // the switch to the mip chain is a step: within rounding of it, either side is right
            if (std::abs(std::max(rho.x, rho.y) - 2.0) <= 1e-4) ambiguous = true;
            if (rho.x <= 2.0 && rho.y <= 2.0) return boxIntegratedNearest(t, st.x, st.y, rho);
        }
        if (!hit.filtered) ambiguous |= nearEdge(st.x, t.width, slack) || nearEdge(st.y, t.height, slack);
        if (filter != TextureFilter::Mip) return sampleTexture(t, st.x, st.y, filter);
        const double lod =
            hit.footprint ? levelOfDetail(st, footprint_st(hit.local_dx), footprint_st(hit.local_dy), t) : 1e9;
        return sampleMip(chain, lod, [&](const Texture2D& level) {
            return sampleTexture(level, st.x, st.y, TextureFilter::Linear);
        });
    };
    switch (decal.kind) {
        case DecalKind::Box: return lookup2d([](const glm::dvec3& v) { return glm::dvec2(v.x + 0.5, 0.5 - v.y); });
        case DecalKind::Volume: {
            auto str = [](const glm::dvec3& v) { return glm::dvec3(v.x + 0.5, 0.5 - v.y, v.z + 0.5); };
            const glm::dvec3 c = str(l);
            if (!hit.filtered)
                ambiguous |= nearEdge(c.x, t.width, slack) || nearEdge(c.y, t.height, slack) || nearEdge(c.z, t.depth, slack);
            if (filter != TextureFilter::Mip) return sampleVolume(t, c.x, c.y, c.z, filter);
            // level from the footprint in level-0 voxels; trilinear in the two levels around it
            const glm::dvec3 size(t.width, t.height, t.depth);
            const double rho = std::max(glm::length((str(hit.local_dx) - c) * scale * size),
                                        glm::length((str(hit.local_dy) - c) * scale * size));
            const double lod = !hit.footprint ? 1e9 : rho > 1.0 ? std::log2(rho) : 0.0;
            return sampleMip(chain, lod, [&](const Texture2D& level) {
                return sampleVolume(level, c.x, c.y, c.z, TextureFilter::Linear);
            });
        }
        case DecalKind::Frustum: {
            const double tan_half = std::tan(glm::radians(decal.fov_y_deg) / 2.0), aspect = decal.aspect;
            return lookup2d([&](const glm::dvec3& v) {
                const double hh = -v.z * tan_half;
                return glm::dvec2(0.5 + v.x / (2.0 * hh * aspect), 0.5 - v.y / (2.0 * hh));
            });
        }
        case DecalKind::Cube: {
            const CubeLookup& c = hit.cube;
            if (!hit.filtered)
                ambiguous |= nearEdge(c.s, t.width, hit.direction_slack) || nearEdge(c.t, t.height, hit.direction_slack);
            if (filter != TextureFilter::Mip) return sampleCube(t, l / glm::length(l), filter);
            // the footprint's directions measured on this pixel's face, even past its edge
            auto on_face = [&](const glm::dvec3& v) {
                const double ma[6] = {v.x, -v.x, v.y, -v.y, v.z, -v.z};
                const double sc[6] = {-v.z, v.z, v.x, v.x, v.x, -v.x};
                const double tc[6] = {-v.y, -v.y, v.z, -v.z, -v.y, -v.y};
                const glm::dvec2 st(0.5 * (sc[c.face] / ma[c.face] + 1.0), 0.5 * (tc[c.face] / ma[c.face] + 1.0));
                return glm::dvec2(c.s, c.t) + (st - glm::dvec2(c.s, c.t)) * scale;
            };
            const double lod =
                hit.footprint ? levelOfDetail(glm::dvec2(c.s, c.t), on_face(hit.local_dx), on_face(hit.local_dy), t) : 1e9;
            return sampleMip(chain, lod, [&](const Texture2D& level) {
                return sampleCubeFace(level, c.face, c.s, c.t, TextureFilter::Linear);
            });
        }
    }
    return glm::dvec4(0.0);
}

// Where the ray through fractional pixel position (px, py) meets the plane through P with normal
// n (world space); nullopt when it runs parallel or meets it behind the camera.
PixelRay pixelRay(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, double px, double py) {
    const glm::dvec2 ndc(2.0 * (px + f.origin_x + 0.5) / f.display_width - 1.0,
                         1.0 - 2.0 * (py + f.origin_y + 0.5) / f.display_height);
    const glm::dmat4 camera_to_world = glm::inverse(camera.world_to_camera);
    const glm::dvec3 far_cam = unproject(inverse_projection, ndc, 0.0);
    const glm::dvec3 origin_cam = camera.isOrthographic() ? unproject(inverse_projection, ndc, -1.0) : glm::dvec3(0.0);
    return {glm::dvec3(camera_to_world * glm::dvec4(origin_cam, 1.0)),
            glm::dvec3(camera_to_world * glm::dvec4(far_cam - origin_cam, 0.0))};
}

std::optional<glm::dvec3> rayOnPlane(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection,
                                     double px, double py, const glm::dvec3& P, const glm::dvec3& n) {
    const auto [origin, dir] = pixelRay(f, camera, inverse_projection, px, py);
    const double denom = glm::dot(dir, n);
    if (!(std::abs(denom) > 1e-6 * glm::length(dir))) return std::nullopt;
    const double t = glm::dot(P - origin, n) / denom;
    if (!(t > 0.0)) return std::nullopt;
    return origin + dir * t;
}

namespace {

// The neighbours' rays (x+1, y) and (x, y+1) against the plane through P with normal n, in world space.
Footprint pixelFootprint(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, int x, int y,
                         const glm::dvec3& P, const glm::dvec3& n) {
    Footprint fp;
    const auto dx = rayOnPlane(f, camera, inverse_projection, x + 1.0, y, P, n);
    const auto dy = rayOnPlane(f, camera, inverse_projection, x, y + 1.0, P, n);
    if (!dx || !dy) return fp;
    fp = {true, *dx, *dy};
    return fp;
}

}  // namespace

TapPlane tapPlane(const GBuffer& f, const Camera& camera, const glm::dmat4& inverse_projection, int x, int y,
                  const glm::dvec3& P, const glm::dvec3& n) {
    TapPlane tp;
    for (int k = 0; k < 4; ++k) {
        const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
        if (nx >= 0 && ny >= 0 && nx < f.width && ny < f.height && !pixelWorldPoint(f, camera, nx, ny)) {
            tp.beside_background = true;
            return tp;
        }
    }
    const auto a = rayOnPlane(f, camera, inverse_projection, x + 1.0, y, P, n);
    const auto b = rayOnPlane(f, camera, inverse_projection, x, y + 1.0, P, n);
    if (!a || !b) return tp;
    tp.du = *a - P;
    tp.dv = *b - P;
    auto viewDepth = [&](const glm::dvec3& w) { return -(camera.world_to_camera * glm::dvec4(w, 1.0)).z; };
    const double z = viewDepth(P), r = f.pixel_filter.radius();
    for (int k = 0; k < 4; ++k) {
        const auto c = rayOnPlane(f, camera, inverse_projection, x + ((k & 1) ? r : -r), y + ((k & 2) ? r : -r), P, n);
        if (!c) return tp;
        const double stray = std::abs(viewDepth(*c) - z), limit = 0.04 * z;
        if (std::abs(stray - limit) <= 1e-3 * limit) tp.ambiguous = true;
        if (stray > limit) return tp;
    }
    tp.valid = true;
    return tp;
}

namespace {

// The material planes a decal may change, as reference::shade works on them.
constexpr Attribute kTargetAttributes[kDecalTargets] = {Attribute::Albedo,   Attribute::Normal,
                                                        Attribute::Roughness, Attribute::Metallic,
                                                        Attribute::AmbientOcclusion, Attribute::Emission};

// The file's normal as a world-space unit vector (docs/conventions.md "Normals").
glm::dvec3 decodedNormal(const GBuffer& f, const Camera& camera, std::size_t i) {
    return glm::normalize(worldNormalAsStored(f, camera, i));
}

glm::dvec3 encodedNormal(const GBuffer& f, const Camera& camera, glm::dvec3 world) {
    if (f.normal_encoding.space == NormalSpace::Camera)
        world = glm::normalize(glm::inverse(glm::transpose(glm::dmat3(camera.world_to_camera))) * world);
    return f.normal_encoding.packed ? world * 0.5 + 0.5 : world;
}

}  // namespace

ShadeResult shade(const GBuffer& frame, const Camera& camera, const DecalScene& scene, double margin) {
    ShadeResult result;
    for (Attribute a : kTargetAttributes)
        if (frame.has(a)) result.planes[a] = frame.planes.at(a);
    result.ambiguous.assign(frame.pixelCount(), 0);
    std::vector<glm::dmat4> world_to_local;
    std::vector<double> scale;  // how far rounding can move a local coordinate, per unit of |P|
    for (const Decal& d : scene.decals) {
        world_to_local.push_back(glm::inverse(d.world_matrix));
        const glm::dmat4& w = world_to_local.back();
        double row_norm = 0;
        for (int r = 0; r < 3; ++r) row_norm = std::max(row_norm, std::abs(w[0][r]) + std::abs(w[1][r]) + std::abs(w[2][r]));
        scale.push_back(row_norm);
    }
    const bool has_normal = frame.has(Attribute::Normal);
    const bool angle_fades = std::any_of(scene.decals.begin(), scene.decals.end(), [](const Decal& d) {
        return d.angle_fade_deg[1] > 0.0 || d.filter == TextureFilter::Mip || d.occlusion.enabled;  // need normals
    }) || frame.pixel_filter.enabled();
    const FilterQuadrature quadrature = filterQuadrature(frame.pixel_filter);
    const FilterIntegral filter_integral = filterIntegral(frame.pixel_filter, quadrature);
    const std::vector<double> view_depths =
        frame.pixel_filter.enabled() ? viewDepths(frame, camera) : std::vector<double>{};
    std::vector<std::vector<Texture2D>> chains;
    for (const Texture2D& t : scene.textures) chains.push_back(mipChain(t));
    const glm::dmat4 inverse_projection = glm::inverse(camera.projection);
    const glm::dmat4 camera_to_world = glm::inverse(camera.world_to_camera);
    const glm::dvec3 camera_position(glm::inverse(camera.world_to_camera)[3]);
    // the kernels work in camera space: their error grows with the distance to the camera
    auto slackAt = [&](std::size_t k, const glm::dvec3& P) {
        return margin * scale[k] * (1.0 + glm::length(P - camera_position));
    };
    std::vector<std::optional<BlastMap>> blast_maps(scene.decals.size());
    for (std::size_t k = 0; k < scene.decals.size(); ++k)
        if (scene.decals[k].occlusion.enabled)
            blast_maps[k].emplace(scene.decals[k], frame, camera, [&, k](const glm::dvec3& P) { return slackAt(k, P); });
    // Texture-space decals: one rest pass per (mesh, object mask) pair.
    std::map<std::pair<int, int>, RestPixels> rest;
    const bool texture_space = hasTextureSpaceDecals(scene);
    if (texture_space) {
        std::vector<std::optional<glm::dvec3>> world_normals;
        if (has_normal)
            for (std::size_t i = 0; i < frame.pixelCount(); ++i) world_normals.push_back(decodedNormal(frame, camera, i));
        for (const Decal& d : scene.decals)
            if (d.space == DecalSpace::ObjectRest && !rest.count({d.rest_mesh, d.mask}))
                rest.emplace(std::make_pair(d.rest_mesh, d.mask),
                             restPixels(frame, camera, scene.meshes.at(std::size_t(d.rest_mesh)), d.mask, world_normals));
    }
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = pixelWorldPoint(frame, camera, x, y);
            if (!p) continue;
            const std::size_t i = std::size_t(y) * frame.width + x;
            std::optional<glm::dvec3> normal;
            bool normal_tie = false;
            if (has_normal) {
                normal = decodedNormal(frame, camera, i);
            } else if (angle_fades) {
                const glm::dvec3 n_cam = normalFromDepth(frame, camera, x, y, *pixelCameraPoint(frame, camera, x, y), normal_tie);
                normal = glm::normalize(glm::dvec3(camera_to_world * glm::dvec4(n_cam, 0.0)));
            }
            Footprint footprint;
            if (normal) footprint = pixelFootprint(frame, camera, inverse_projection, x, y, *p, *normal);
            Surface surface = surfaceAt(result.planes, i);
            if (normal) surface.normal = *normal;
            TapPlane taps;
            SurfaceSplit split;
            if (frame.pixel_filter.enabled() && normal) {
                taps = tapPlane(frame, camera, inverse_projection, x, y, *p, *normal);
                if (taps.ambiguous) result.ambiguous[i] = 1;
                if (!taps.beside_background) {
                    split = splitSilhouette(frame, camera, inverse_projection, quadrature, view_depths, x, y);
                    if (split.ambiguous) result.ambiguous[i] = 1;
                }
                if (taps.valid && !split.valid) {
                    split = splitCrease(frame, camera, inverse_projection, quadrature, view_depths, x, y, *p);
                    if (split.ambiguous) result.ambiguous[i] = 1;
                }
            }
            auto has = [&](DecalTarget t) { return frame.has(kTargetAttributes[int(t)]); };
            // Decal k's opacity times its mask's weight at the pixel.
            auto decalWeight = [&](std::size_t k) {
                const Decal& decal = scene.decals[k];
                return decal.mask >= 0 ? decal.opacity * frame.mask_weights[std::size_t(decal.mask)].at(i, 0)
                                       : decal.opacity;
            };
            // Decal k's textures at a hit (`ambiguous` notes nearest lookups at texel edges).
            auto decalValues = [&](std::size_t k, const DecalHit& hit, double slack, bool& ambiguous) {
                const Decal& decal = scene.decals[k];
                return valuesAtHit(decal, hit, [&](std::size_t texture) {
                    return hitTexel(hit, decal, scene.textures[texture], chains[texture], slack, ambiguous);
                });
            };
            // On one tangent plane every tap blends every decal in order into the pixel's material,
            // and the pixel takes the taps' mean under the filter's weights (kernels:
            // dc_filter_stacked). Frames with texture-space decals keep one filtered decal at a time.
            // With the fast filter, pixels on one plane take each decal once in closed form instead
            // (kernels: dc_integrated_decal).
            const bool integrated = frame.pixel_filter.fast && taps.valid && !split.valid && !texture_space;
            const bool stacked = (taps.valid || split.valid) && !texture_space && !integrated;
            // The decals that reach the tap at pixel offset (u, v) on the plane through `point` with
            // normal n, blended in order into `out`; whether any did.
            auto stackDecals = [&](double u, double v, const glm::dvec3& point, const glm::dvec3& n,
                                   const glm::dvec3& du, const glm::dvec3& dv, Surface& out) {
                const auto tap = rayOnPlane(frame, camera, inverse_projection, x + u, y + v, point, n);
                bool touched = false;
                for (std::size_t k = 0; tap && k < scene.decals.size(); ++k) {
                    const glm::dmat3 to_local(world_to_local[k]);
                    const Stratum stratum{to_local * (du * quadrature.step), to_local * (dv * quadrature.step)};
                    const double slack = slackAt(k, *p);
                    const DecalHit hit = hitDecal(scene.decals[k], world_to_local[k], *tap, n, {}, slack, &stratum);
                    if (hit.ambiguous && !(hit.fade > 0.0)) result.ambiguous[i] = 1;  // just outside
                    bool reaches = hit.fade > 0.0;
                    if (reaches && blast_maps[k]) {
                        const BlastVisibility vis = blast_maps[k]->test(*tap, n, slack);
                        if (vis.ambiguous) result.ambiguous[i] = 1;
                        reaches = vis.reaches;
                    }
                    if (!reaches) continue;
                    bool ambiguous = hit.ambiguous;
                    applyDecal(scene.decals[k], decalValues(k, hit, slack, ambiguous), hit.fade * decalWeight(k), n,
                               has, out);
                    if (ambiguous) result.ambiguous[i] = 1;
                    touched = true;
                }
                return touched;
            };
            if (stacked && split.valid) {
                // each tap's share on each surface starts from that surface's material; the pixel
                // keeps its mix and adds each share's change (kernels: dc_filter_stacked_split)
                Surface sum = surface;
                bool touched = false;
                for (int sd = 0; sd < 2; ++sd) {
                    Surface base = surface;
                    base.albedo = split.material[sd].albedo;
                    base.roughness = split.material[sd].roughness;
                    base.metallic = split.material[sd].metallic;
                    base.normal = split.material[sd].normal;
                    for (std::size_t j = 0; j < quadrature.offsets.size(); ++j)
                        for (std::size_t t = 0; t < quadrature.offsets.size(); ++t) {
                            const double u = quadrature.offsets[t], v = quadrature.offsets[j];
                            const double near_share = split.nearShare(u, v);
                            const double share = sd == 0 ? near_share : 1.0 - near_share;
                            if (!(share > 0.0)) continue;
                            Surface out = base;
                            touched |= stackDecals(u, v, split.point[sd], split.normal[sd], split.plane[sd].du,
                                                   split.plane[sd].dv, out);
                            const double w = quadrature.weights[t] * quadrature.weights[j] * share;
                            addWeighted(sum, out, w);
                            addWeighted(sum, base, -w);
                        }
                }
                if (touched) {
                    if (sum.normal_changed && glm::length(sum.normal) > 1e-6) sum.normal = glm::normalize(sum.normal);
                    surface = sum;
                }
            } else if (stacked) {
                Surface sum;
                sum.normal = glm::dvec3(0.0);
                sum.normal_changed = surface.normal_changed;
                bool touched = false;
                for (std::size_t j = 0; j < quadrature.offsets.size(); ++j)
                    for (std::size_t t = 0; t < quadrature.offsets.size(); ++t) {
                        Surface out = surface;
                        touched |= stackDecals(quadrature.offsets[t], quadrature.offsets[j], *p, *normal, taps.du,
                                               taps.dv, out);
                        addWeighted(sum, out, quadrature.weights[t] * quadrature.weights[j]);
                    }
                if (touched) {
                    if (sum.normal_changed && glm::length(sum.normal) > 1e-6) sum.normal = glm::normalize(sum.normal);
                    surface = sum;
                }
            }
            for (std::size_t k = 0; !stacked && k < scene.decals.size(); ++k) {
                const Decal& decal = scene.decals[k];
                const double slack = slackAt(k, *p);
                const double weight = decalWeight(k);
                auto valuesAt = [&](const DecalHit& hit, bool& ambiguous) { return decalValues(k, hit, slack, ambiguous); };
                if (decal.space == DecalSpace::ObjectRest) {
                    const RestPixels& r = rest.at({decal.rest_mesh, decal.mask});
                    if (r.ambiguous[i]) result.ambiguous[i] = 1;
                    if (!r.points[i]) continue;
                    const glm::dvec3 P = *r.points[i];
                    const glm::dmat3& to_world = r.rotation[i];
                    const glm::dmat3 to_rest = glm::transpose(to_world);
                    // mip footprint: the neighbours' rest points, one pixel right and down
                    Footprint rest_footprint;
                    const int xn = x + 1 < frame.width ? x + 1 : x - 1, yn = y + 1 < frame.height ? y + 1 : y - 1;
                    if (decal.filter == TextureFilter::Mip && xn >= 0 && yn >= 0) {
                        const auto& px = r.points[std::size_t(y) * frame.width + xn];
                        const auto& py = r.points[std::size_t(yn) * frame.width + x];
                        if (px && py)
                            rest_footprint = {true, xn > x ? *px : 2.0 * P - *px, yn > y ? *py : 2.0 * P - *py};
                    }
                    std::optional<glm::dvec3> rest_normal;
                    if (normal) rest_normal = to_rest * *normal;
                    const double rest_slack = margin * scale[k] * (1.0 + glm::length(P));
                    // Blends the decal, looked up in rest space, into `s`: normals there and back.
                    auto blendInRestSpace = [&](const DecalHit& hit, Surface s, bool& ambiguous) {
                        Surface in_rest = s;
                        in_rest.normal = to_rest * s.normal;
                        in_rest.normal_changed = false;
                        applyDecal(decal, valuesAt(hit, ambiguous), hit.fade * weight, rest_normal.value_or(glm::dvec3(0.0)),
                                   has, in_rest);
                        const bool turned = in_rest.normal_changed;
                        in_rest.normal = turned ? to_world * in_rest.normal : s.normal;
                        in_rest.normal_changed = turned || s.normal_changed;
                        return in_rest;
                    };
                    // Under a pixel filter the taps follow the surface in rest space: P + u dP/dx +
                    // v dP/dy, dP from the nearer neighbour on the mesh on each axis.
                    const auto step_x = restStep(r, frame.width, frame.height, x, y, 1, 0);
                    const auto step_y = restStep(r, frame.width, frame.height, x, y, 0, 1);
                    if ((taps.valid || split.valid) && step_x && step_y) {
                        const glm::dmat3 to_local(world_to_local[k]);
                        const double h = quadrature.step;
                        const Stratum stratum{to_local * (*step_x * h), to_local * (*step_y * h)};
                        Surface sum;
                        sum.normal = glm::dvec3(0.0);
                        sum.normal_changed = surface.normal_changed;
                        bool touched = false;
                        for (std::size_t j = 0; j < quadrature.offsets.size(); ++j)
                            for (std::size_t t = 0; t < quadrature.offsets.size(); ++t) {
                                const glm::dvec3 tap =
                                    P + *step_x * quadrature.offsets[t] + *step_y * quadrature.offsets[j];
                                const DecalHit hit = hitDecal(decal, world_to_local[k], tap, rest_normal, {}, rest_slack,
                                                              &stratum);
                                if (hit.ambiguous && !(hit.fade > 0.0)) result.ambiguous[i] = 1;  // just outside
                                Surface out = surface;
                                if (hit.fade > 0.0) {
                                    bool ambiguous = hit.ambiguous;
                                    out = blendInRestSpace(hit, surface, ambiguous);
                                    if (ambiguous) result.ambiguous[i] = 1;
                                    touched = true;
                                }
                                addWeighted(sum, out, quadrature.weights[t] * quadrature.weights[j]);
                            }
                        if (!touched) continue;
                        if (sum.normal_changed && glm::length(sum.normal) > 1e-6) sum.normal = glm::normalize(sum.normal);
                        surface = sum;
                        continue;
                    }
                    const DecalHit hit = hitDecal(decal, world_to_local[k], P, rest_normal, rest_footprint, rest_slack);
                    bool ambiguous = hit.ambiguous;
                    if (hit.fade > 0.0) surface = blendInRestSpace(hit, surface, ambiguous);
                    if (ambiguous) result.ambiguous[i] = 1;
                    continue;
                }
                if (integrated) {
                    const IntegratedDecalHit at = integratedDecalHit(filter_integral, decal, world_to_local[k],
                                                                     scale[k], *p, normal, taps.du, taps.dv, slack);
                    bool ambiguous = at.hit.ambiguous;
                    if (!(at.hit.fade > 0.0)) {
                        if (ambiguous) result.ambiguous[i] = 1;
                        continue;
                    }
                    if (blast_maps[k]) {
                        const BlastVisibility v = blast_maps[k]->test(*p, *normal, slack);
                        if (v.ambiguous) result.ambiguous[i] = 1;
                        if (!v.reaches) continue;
                    }
                    const DecalValues values =
                        integratedDecalValues(filter_integral, decal, at, slack, scene.textures, chains, ambiguous);
                    applyDecal(decal, values, at.hit.fade * weight, *normal, has, surface);
                    if (ambiguous) result.ambiguous[i] = 1;
                    continue;
                }
                if (split.valid) {
                    // each surface's taps blend the decal into that surface's material; the pixel's
                    // mix takes their changes (kernels: dc_filter_decal)
                    const glm::dmat3 to_local(world_to_local[k]);
                    const double h = quadrature.step;
                    Surface base[2], side_sum[2];
                    double side_weight[2] = {0.0, 0.0};
                    for (int sd = 0; sd < 2; ++sd) {
                        base[sd] = surface;
                        base[sd].albedo = split.material[sd].albedo;
                        base[sd].roughness = split.material[sd].roughness;
                        base[sd].metallic = split.material[sd].metallic;
                        base[sd].normal = split.material[sd].normal;
                        side_sum[sd].normal_changed = surface.normal_changed;
                    }
                    Surface sum = surface;
                    bool touched = false;
                    for (std::size_t j = 0; j < quadrature.offsets.size(); ++j)
                        for (std::size_t t = 0; t < quadrature.offsets.size(); ++t) {
                            const double u = quadrature.offsets[t], v = quadrature.offsets[j];
                            const double w = quadrature.weights[t] * quadrature.weights[j];
                            const double near_share = split.nearShare(u, v);
                            for (int sd = 0; sd < 2; ++sd) {
                                const double share = sd == 0 ? near_share : 1.0 - near_share;
                                if (!(share > 0.0)) continue;
                                Surface out = base[sd];
                                const glm::dvec3& n = split.normal[sd];
                                const auto tap =
                                    rayOnPlane(frame, camera, inverse_projection, x + u, y + v, split.point[sd], n);
                                if (tap) {
                                    const Stratum stratum{to_local * (split.plane[sd].du * h),
                                                          to_local * (split.plane[sd].dv * h)};
                                    const DecalHit hit = hitDecal(decal, world_to_local[k], *tap, n, {}, slack, &stratum);
                                    if (hit.ambiguous && !(hit.fade > 0.0)) result.ambiguous[i] = 1;
                                    bool reaches = hit.fade > 0.0;
                                    if (reaches && blast_maps[k]) {
                                        const BlastVisibility vis = blast_maps[k]->test(*tap, n, slack);
                                        if (vis.ambiguous) result.ambiguous[i] = 1;
                                        reaches = vis.reaches;
                                    }
                                    if (reaches) {
                                        bool ambiguous = hit.ambiguous;
                                        applyDecal(decal, valuesAt(hit, ambiguous), hit.fade * weight, n, has, out);
                                        if (ambiguous) result.ambiguous[i] = 1;
                                        touched = true;
                                    }
                                }
                                addWeighted(sum, out, w * share);
                                addWeighted(sum, base[sd], -w * share);
                                addWeighted(side_sum[sd], out, w * share);
                                side_weight[sd] += w * share;
                            }
                        }
                    if (!touched) continue;
                    if (sum.normal_changed && glm::length(sum.normal) > 1e-6) sum.normal = glm::normalize(sum.normal);
                    for (int sd = 0; sd < 2; ++sd) {
                        if (!(side_weight[sd] > 0.0)) continue;
                        Surface& m = split.material[sd];
                        const Surface& acc = side_sum[sd];
                        m.albedo = acc.albedo / side_weight[sd];
                        m.roughness = acc.roughness / side_weight[sd];
                        m.metallic = acc.metallic / side_weight[sd];
                        if (acc.normal_changed && glm::length(acc.normal) > 1e-6) m.normal = glm::normalize(acc.normal);
                    }
                    surface = sum;
                    continue;
                }
                if (taps.valid) {
                    // (texture-space frames) each tap blends the decal into the material as it
                    // stands before this decal; the pixel takes their mean under the filter's weights
                    const glm::dmat3 to_local(world_to_local[k]);
                    const std::vector<double>& offsets = quadrature.offsets;
                    const std::vector<double>& weights = quadrature.weights;
                    const double h = quadrature.step;
                    const Stratum stratum{to_local * (taps.du * h), to_local * (taps.dv * h)};
                    Surface sum;
                    sum.normal = glm::dvec3(0.0);
                    sum.normal_changed = surface.normal_changed;
                    bool touched = false;
                    for (std::size_t j = 0; j < offsets.size(); ++j)
                        for (std::size_t t = 0; t < offsets.size(); ++t) {
                            Surface out = surface;
                            const auto tap = rayOnPlane(frame, camera, inverse_projection, x + offsets[t],
                                                        y + offsets[j], *p, *normal);
                            if (tap) {
                                const DecalHit hit = hitDecal(decal, world_to_local[k], *tap, normal, {}, slack, &stratum);
                                if (hit.ambiguous && !(hit.fade > 0.0)) result.ambiguous[i] = 1;  // just outside
                                bool reaches = hit.fade > 0.0;
                                if (reaches && blast_maps[k]) {
                                    const BlastVisibility v = blast_maps[k]->test(*tap, *normal, slack);
                                    if (v.ambiguous) result.ambiguous[i] = 1;
                                    reaches = v.reaches;
                                }
                                if (reaches) {
                                    bool ambiguous = hit.ambiguous;
                                    applyDecal(decal, valuesAt(hit, ambiguous), hit.fade * weight, *normal, has, out);
                                    if (ambiguous) result.ambiguous[i] = 1;
                                    touched = true;
                                }
                            }
                            addWeighted(sum, out, weights[t] * weights[j]);
                        }
                    if (!touched) continue;
                    if (sum.normal_changed && glm::length(sum.normal) > 1e-6) sum.normal = glm::normalize(sum.normal);
                    surface = sum;
                    continue;
                }
                const DecalHit hit = hitDecal(decal, world_to_local[k], *p, normal, footprint, slack);
                bool ambiguous = hit.ambiguous;
                if (!(hit.fade > 0.0)) {
                    if (ambiguous) result.ambiguous[i] = 1;
                    continue;
                }
                if (blast_maps[k]) {  // blast occlusion: applied only where the blast reaches first
                    const BlastVisibility v = blast_maps[k]->test(*p, *normal, slack);
                    if (v.ambiguous) result.ambiguous[i] = 1;
                    if (!v.reaches) continue;
                }
                const DecalValues values = valuesAt(hit, ambiguous);
                const bool changed = applyDecal(decal, values, hit.fade * weight, normal.value_or(glm::dvec3(0.0)), has, surface);
                const bool uses_normal = decal.angle_fade_deg[1] > 0.0 || decal.occlusion.enabled;
                if (ambiguous || (normal_tie && uses_normal && changed)) result.ambiguous[i] = 1;
            }
            storeSurface(surface, i, result.planes);
            if (surface.normal_changed && has_normal) {
                const glm::dvec3 n = encodedNormal(frame, camera, surface.normal);
                for (int c = 0; c < 3; ++c) result.planes.at(Attribute::Normal).at(i, c) = float(n[c]);
            }
        }
    result.albedo = result.planes.at(Attribute::Albedo);
    return result;
}

}  // namespace decalcomp::reference
