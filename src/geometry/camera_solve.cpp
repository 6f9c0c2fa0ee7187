// solveCamera: a camera from the position pass by least squares (normalised DLT, reweighted to the
// geometric error, affine fit for orthographic cameras), decomposed into decalcomp's conventions.
#include "decalcomp/camera_solve.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "decalcomp/error.hpp"
#include "decalcomp/geometry.hpp"
#include "geometry/median.hpp"

namespace decalcomp {

namespace {

// ---- small dense linear algebra ----

template <int N>
using Mat = std::array<std::array<double, N>, N>;

template <int N>
struct Eigen {
    std::array<double, N> values;
    Mat<N> vectors;  // column k is the eigenvector of values[k]
};

// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations.
template <int N>
Eigen<N> symmetricEigen(Mat<N> a) {
    Mat<N> v{};
    for (int i = 0; i < N; ++i) v[i][i] = 1.0;
    for (int sweep = 0; sweep < 100; ++sweep) {
        double off = 0.0, total = 0.0;
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j) (i == j ? total : off) += a[i][j] * a[i][j];
        if (off <= 1e-30 * (total + off)) break;
        for (int p = 0; p < N - 1; ++p)
            for (int q = p + 1; q < N; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < N; ++k) {  // columns p, q
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < N; ++k) {  // rows p, q
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < N; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    Eigen<N> out;
    for (int i = 0; i < N; ++i) out.values[i] = a[i][i];
    out.vectors = v;
    return out;
}

// The eigenvector of the smallest eigenvalue.
template <int N>
std::array<double, N> smallestEigenvector(const Mat<N>& a) {
    const Eigen<N> e = symmetricEigen<N>(a);
    int best = 0;
    for (int i = 1; i < N; ++i)
        if (e.values[i] < e.values[best]) best = i;
    std::array<double, N> out;
    for (int k = 0; k < N; ++k) out[k] = e.vectors[k][best];
    return out;
}

// Solves A x = b by Gaussian elimination with partial pivoting; nullopt when singular.
template <int N>
std::optional<std::array<double, N>> solveLinear(Mat<N> a, std::array<double, N> b) {
    double scale = 0.0;
    for (const auto& row : a)
        for (double x : row) scale = std::max(scale, std::abs(x));
    if (!(scale > 0.0)) return std::nullopt;
    for (int col = 0; col < N; ++col) {
        int pivot = col;
        for (int r = col + 1; r < N; ++r)
            if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
        if (std::abs(a[pivot][col]) <= 1e-13 * scale) return std::nullopt;
        std::swap(a[pivot], a[col]);
        std::swap(b[pivot], b[col]);
        for (int r = col + 1; r < N; ++r) {
            const double f = a[r][col] / a[col][col];
            for (int k = col; k < N; ++k) a[r][k] -= f * a[col][k];
            b[r] -= f * b[col];
        }
    }
    std::array<double, N> x{};
    for (int r = N - 1; r >= 0; --r) {
        double s = b[r];
        for (int k = r + 1; k < N; ++k) s -= a[r][k] * x[k];
        x[r] = s / a[r][r];
    }
    return x;
}

// ---- the points ----

struct Point {
    glm::dvec3 world;
    glm::dvec2 pixel;  // display-window pixel coordinates of the pixel centre
    double depth;      // the depth pass value (NaN without one)
};

struct Normaliser {
    glm::dvec2 image_centre{0.0};
    double image_scale = 1.0;
    glm::dvec3 world_centre{0.0};
    double world_scale = 1.0;
};

Normaliser normaliserFor(const std::vector<const Point*>& points) {
    Normaliser n;
    for (const Point* p : points) {
        n.image_centre += p->pixel;
        n.world_centre += p->world;
    }
    n.image_centre /= double(points.size());
    n.world_centre /= double(points.size());
    double image_distance = 0.0, world_distance = 0.0;
    for (const Point* p : points) {
        image_distance += glm::length(p->pixel - n.image_centre);
        world_distance += glm::length(p->world - n.world_centre);
    }
    image_distance /= double(points.size());
    world_distance /= double(points.size());
    n.image_scale = image_distance > 0.0 ? std::sqrt(2.0) / image_distance : 1.0;
    n.world_scale = world_distance > 0.0 ? std::sqrt(3.0) / world_distance : 1.0;
    return n;
}

// A 3x4 projection as three rows acting on homogeneous world points.
struct Projective {
    std::array<glm::dvec4, 3> rows;
    glm::dvec2 project(const glm::dvec3& x) const {
        const glm::dvec4 h(x, 1.0);
        const double w = glm::dot(rows[2], h);
        return {glm::dot(rows[0], h) / w, glm::dot(rows[1], h) / w};
    }
};

// Undoes the normalisation: P_pixel = Ti^-1 * P' * Tw.
Projective denormalise(const std::array<double, 12>& p, const Normaliser& n) {
    glm::dmat4 tw(n.world_scale);  // world: x' = s (x - c)
    tw[3] = glm::dvec4(-n.world_scale * n.world_centre, 1.0);
    std::array<glm::dvec4, 3> normalised;
    for (int r = 0; r < 3; ++r) normalised[r] = glm::dvec4(p[r * 4 + 0], p[r * 4 + 1], p[r * 4 + 2], p[r * 4 + 3]);
    // rows in world coordinates: row' . (Tw x) = (Tw^T row') . x
    std::array<glm::dvec4, 3> world_rows;
    for (int r = 0; r < 3; ++r) world_rows[r] = glm::transpose(tw) * normalised[r];
    // image: u' = s (u - c)  =>  u = u'/s + c, rows: (r0/s + c r2, r1/s + c r2, r2)
    Projective out;
    out.rows[2] = world_rows[2];
    out.rows[0] = world_rows[0] / n.image_scale + n.image_centre.x * world_rows[2];
    out.rows[1] = world_rows[1] / n.image_scale + n.image_centre.y * world_rows[2];
    return out;
}

// One DLT solve, each point's equations weighted (1 / its projective depth for the reweighting).
std::optional<Projective> fitProjective(const std::vector<const Point*>& points, const Normaliser& n,
                                        const Projective* previous) {
    Mat<12> ata{};
    for (const Point* p : points) {
        const glm::dvec3 x = n.world_scale * (p->world - n.world_centre);
        const glm::dvec2 u = n.image_scale * (p->pixel - n.image_centre);
        double weight = 1.0;
        if (previous) {
            const double w = glm::dot(previous->rows[2], glm::dvec4(p->world, 1.0));
            if (!(std::abs(w) > 0.0) || !std::isfinite(w)) continue;
            weight = 1.0 / (w * w);
        }
        const std::array<double, 4> xh = {x.x, x.y, x.z, 1.0};
        std::array<double, 12> a{}, b{};
        for (int k = 0; k < 4; ++k) {
            a[k] = xh[k];
            a[8 + k] = -u.x * xh[k];
            b[4 + k] = xh[k];
            b[8 + k] = -u.y * xh[k];
        }
        for (int i = 0; i < 12; ++i)
            for (int j = i; j < 12; ++j) ata[i][j] += weight * (a[i] * a[j] + b[i] * b[j]);
    }
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < i; ++j) ata[i][j] = ata[j][i];
    // Normalise the weights' overall scale so Jacobi's tolerances stay meaningful.
    double trace = 0.0;
    for (int i = 0; i < 12; ++i) trace += ata[i][i];
    if (!(trace > 0.0) || !std::isfinite(trace)) return std::nullopt;
    for (auto& row : ata)
        for (double& v : row) v /= trace;
    return denormalise(smallestEigenvector<12>(ata), n);
}

// ndc_x, ndc_y affine in the world point (orthographic), least squares in normalised coordinates.
struct Affine {
    glm::dvec4 x_row{0.0}, y_row{0.0};  // pixel u = x_row . (X, 1), v = y_row . (X, 1)
    glm::dvec2 project(const glm::dvec3& x) const {
        const glm::dvec4 h(x, 1.0);
        return {glm::dot(x_row, h), glm::dot(y_row, h)};
    }
};

std::optional<Affine> fitAffine(const std::vector<const Point*>& points, const Normaliser& n) {
    Mat<4> ata{};
    std::array<double, 4> atu{}, atv{};
    for (const Point* p : points) {
        const glm::dvec3 x = n.world_scale * (p->world - n.world_centre);
        const std::array<double, 4> xh = {x.x, x.y, x.z, 1.0};
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) ata[i][j] += xh[i] * xh[j];
            atu[i] += xh[i] * (p->pixel.x - n.image_centre.x);
            atv[i] += xh[i] * (p->pixel.y - n.image_centre.y);
        }
    }
    const auto a = solveLinear<4>(ata, atu), b = solveLinear<4>(ata, atv);
    if (!a || !b) return std::nullopt;
    // u - c = a . (s (X - C), 1)  =>  u = s a_xyz . X + (a_w - s a_xyz . C + c)
    Affine out;
    const glm::dvec3 ax((*a)[0], (*a)[1], (*a)[2]), bx((*b)[0], (*b)[1], (*b)[2]);
    out.x_row = glm::dvec4(n.world_scale * ax, (*a)[3] - n.world_scale * glm::dot(ax, n.world_centre) + n.image_centre.x);
    out.y_row = glm::dvec4(n.world_scale * bx, (*b)[3] - n.world_scale * glm::dot(bx, n.world_centre) + n.image_centre.y);
    return out;
}

template <typename Model>
double residualPx(const Model& model, const Point& p) {
    const glm::dvec2 q = model.project(p.world);
    const double e = glm::length(q - p.pixel);
    return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
}

struct Stats {
    double rms = 0.0, max = 0.0;
};

template <typename Model>
Stats statsOf(const Model& model, const std::vector<const Point*>& points) {
    Stats s;
    double sum = 0.0;
    for (const Point* p : points) {
        const double e = residualPx(model, *p);
        sum += e * e;
        s.max = std::max(s.max, e);
    }
    s.rms = points.empty() ? 0.0 : std::sqrt(sum / double(points.size()));
    return s;
}

// How flat the points are: the smallest over the largest spread of their principal axes (0 for
// points on one plane, where a 3x4 projection is not determined).
double flatness(const std::vector<const Point*>& points) {
    glm::dvec3 centre(0.0);
    for (const Point* p : points) centre += p->world;
    centre /= double(points.size());
    Mat<3> cov{};
    for (const Point* p : points) {
        const glm::dvec3 d = p->world - centre;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) cov[i][j] += d[i] * d[j];
    }
    const Eigen<3> e = symmetricEigen<3>(cov);
    const double lo = std::min({e.values[0], e.values[1], e.values[2]});
    const double hi = std::max({e.values[0], e.values[1], e.values[2]});
    return hi > 0.0 ? std::sqrt(std::max(lo, 0.0) / hi) : 0.0;
}

// An even subset of at most `limit` points for the fits (the residuals always use every point).
std::vector<const Point*> subset(const std::vector<const Point*>& points, std::size_t limit) {
    if (points.size() <= limit) return points;
    std::vector<const Point*> out;
    const double step = double(points.size()) / double(limit);
    for (std::size_t i = 0; i < limit; ++i) out.push_back(points[std::size_t(double(i) * step)]);
    return out;
}

void setRow(glm::dmat4& m, int r, const glm::dvec4& v) {
    for (int c = 0; c < 4; ++c) m[c][r] = v[c];
}

std::vector<Point> collectPoints(const GBuffer& g) {
    std::vector<Point> points;
    const auto position = g.planes.find(Attribute::Position);
    if (position == g.planes.end()) return points;
    const Plane* depth = g.has(Attribute::Depth) ? &g.planes.at(Attribute::Depth) : nullptr;
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = std::size_t(y) * g.width + x;
            if (!isGeometryPixel(g, i)) continue;
            const glm::dvec3 world(position->second.at(i, 0), position->second.at(i, 1), position->second.at(i, 2));
            if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) continue;
            points.push_back({world, {x + g.origin_x + 0.5, y + g.origin_y + 0.5},
                              depth ? double(depth->at(i, 0)) : std::numeric_limits<double>::quiet_NaN()});
        }
    return points;
}

std::string solveFailure(const std::string& label, const std::string& what) {
    return fmt::format("{}: cannot solve the camera from the position pass: {}", label, what);
}

// Planar depth range of the points in front of the camera (z_cam < 0).
std::pair<double, double> depthRange(const glm::dmat4& world_to_camera, const std::vector<const Point*>& points) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Point* p : points) {
        const double d = -(world_to_camera * glm::dvec4(p->world, 1.0)).z;
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    return {lo, hi};
}

// The depth pass as OpenGL ndc z (reversed-Z undone).
double ndcZ(const GBuffer& g, double d01) { return g.reversed_z ? 1.0 - 2.0 * d01 : 2.0 * d01 - 1.0; }

// Fits the projection's z row to an ndc depth pass: perspective ndc_z * (-z) = a z + b, orthographic
// ndc_z = a z + b.
std::optional<std::pair<double, double>> fitNdcRow(const GBuffer& g, const glm::dmat4& world_to_camera,
                                                   const std::vector<const Point*>& points, bool orthographic,
                                                   double* rms_out) {
    Mat<2> ata{};
    std::array<double, 2> atb{};
    std::size_t n = 0;
    for (const Point* p : points) {
        if (!std::isfinite(p->depth)) continue;
        const double z = (world_to_camera * glm::dvec4(p->world, 1.0)).z;
        const double target = orthographic ? ndcZ(g, p->depth) : -ndcZ(g, p->depth) * z;
        const std::array<double, 2> row = {z, 1.0};
        for (int i = 0; i < 2; ++i) {
            for (int j = 0; j < 2; ++j) ata[i][j] += row[i] * row[j];
            atb[i] += row[i] * target;
        }
        ++n;
    }
    if (n < 2) return std::nullopt;
    const auto ab = solveLinear<2>(ata, atb);
    if (!ab) return std::nullopt;
    double sum = 0.0;
    for (const Point* p : points) {
        if (!std::isfinite(p->depth)) continue;
        const double z = (world_to_camera * glm::dvec4(p->world, 1.0)).z;
        const double predicted = orthographic ? (*ab)[0] * z + (*ab)[1] : ((*ab)[0] * z + (*ab)[1]) / -z;
        const double e = predicted - ndcZ(g, p->depth);
        sum += e * e;
    }
    if (rms_out) *rms_out = std::sqrt(sum / double(n));
    return std::make_pair((*ab)[0], (*ab)[1]);
}

// Decomposes a pixel-space projective fit into world_to_camera and the x, y, w rows of an OpenGL
// projection: M = K Q by RQ (K upper triangular, K[2][2] = -1 so the camera looks down -Z).
bool decomposePerspective(const Projective& pixel_fit, const GBuffer& g, const std::vector<const Point*>& points,
                          Camera& camera, CameraSolveReport& report) {
    // Pixel -> NDC: ndc_x = 2u/W - 1, ndc_y = 1 - 2v/H (rows in clip space).
    std::array<glm::dvec4, 3> p;
    const double W = g.display_width, H = g.display_height;
    p[0] = 2.0 / W * pixel_fit.rows[0] - pixel_fit.rows[2];
    p[1] = pixel_fit.rows[2] - 2.0 / H * pixel_fit.rows[1];
    p[2] = pixel_fit.rows[2];
    // The w row is the distance in front of the camera: positive for the points.
    double mean_w = 0.0;
    for (const Point* pt : points) mean_w += glm::dot(p[2], glm::dvec4(pt->world, 1.0));
    if (mean_w < 0.0)
        for (auto& row : p) row = -row;
    const glm::dvec3 m0(p[0]), m1(p[1]), m2(p[2]);
    const double s = glm::length(m2);
    if (!(s > 0.0) || !std::isfinite(s)) return false;
    const glm::dvec3 q2 = -m2 / s;  // K[2][2] = -1 after dividing by s
    const double k12 = glm::dot(m1, q2) / s;
    glm::dvec3 r1 = m1 / s - k12 * q2;
    const double k11 = glm::length(r1);
    if (!(k11 > 0.0)) return false;
    const glm::dvec3 q1 = r1 / k11;
    const double k02 = glm::dot(m0, q2) / s, k01 = glm::dot(m0, q1) / s;
    glm::dvec3 r0 = m0 / s - k01 * q1 - k02 * q2;
    const double k00 = glm::length(r0);
    if (!(k00 > 0.0)) return false;
    const glm::dvec3 q0 = r0 / k00;
    // t = K^-1 p4, K = [[k00 k01 k02] [0 k11 k12] [0 0 -1]]
    const glm::dvec3 p4(p[0].w / s, p[1].w / s, p[2].w / s);
    const double t2 = -p4.z;
    const double t1 = (p4.y - k12 * t2) / k11;
    const double t0 = (p4.x - k01 * t1 - k02 * t2) / k00;

    glm::dmat4 v(1.0);
    setRow(v, 0, glm::dvec4(q0, t0));
    setRow(v, 1, glm::dvec4(q1, t1));
    setRow(v, 2, glm::dvec4(q2, t2));
    report.mirrored = glm::dot(glm::cross(q0, q1), q2) < 0.0;
    camera.world_to_camera = v;
    camera.projection = glm::dmat4(0.0);
    setRow(camera.projection, 0, {k00, k01, k02, 0.0});
    setRow(camera.projection, 1, {0.0, k11, k12, 0.0});
    setRow(camera.projection, 3, {0.0, 0.0, -1.0, 0.0});
    return true;
}

// The orthographic counterpart: ndc x, y rows = K2 [q0; q1] X + offsets; the view axis and its
// offset come from the depth pass (its sign, and for planar depth the offset), else right-handed
// with the nearest point at distance 1.
bool decomposeOrthographic(const Affine& pixel_fit, const GBuffer& g, const std::vector<const Point*>& points,
                           Camera& camera, CameraSolveReport& report) {
    const double W = g.display_width, H = g.display_height;
    const glm::dvec4 ax = 2.0 / W * pixel_fit.x_row - glm::dvec4(0, 0, 0, 1);
    const glm::dvec4 ay = glm::dvec4(0, 0, 0, 1) - 2.0 / H * pixel_fit.y_row;
    const glm::dvec3 a1(ax), b1(ay);
    const double k11 = glm::length(b1);
    if (!(k11 > 0.0)) return false;
    const glm::dvec3 q1 = b1 / k11;
    const double k01 = glm::dot(a1, q1);
    const glm::dvec3 r = a1 - k01 * q1;
    const double k00 = glm::length(r);
    if (!(k00 > 0.0)) return false;
    const glm::dvec3 q0 = r / k00;
    // Offsets into the camera position: ndc = K2 (q . X + t), no principal offset.
    const double t1 = ay.w / k11;
    const double t0 = (ax.w - k01 * t1) / k00;
    glm::dvec3 q2 = glm::cross(q0, q1);

    // Depth d as an affine function of q2 . X: planar/radial d = -(q2 . X + t2) (slope -1, or +1
    // when mirrored); ndc grows with distance (falls with reversed-Z).
    double t2 = 0.0;
    bool have_t2 = false;
    const bool has_depth = g.has(Attribute::Depth) && g.depth_convention != DepthConvention::Position;
    if (has_depth) {
        Mat<2> ata{};
        std::array<double, 2> atb{};
        std::size_t n = 0;
        for (const Point* p : points) {
            if (!std::isfinite(p->depth)) continue;
            const std::array<double, 2> row = {glm::dot(q2, p->world), 1.0};
            for (int i = 0; i < 2; ++i) {
                for (int j = 0; j < 2; ++j) ata[i][j] += row[i] * row[j];
                atb[i] += row[i] * p->depth;
            }
            ++n;
        }
        const auto fit = n >= 2 ? solveLinear<2>(ata, atb) : std::nullopt;
        if (fit) {
            const double slope = (*fit)[0], offset = (*fit)[1];
            const bool ndc = g.depth_convention == DepthConvention::Ndc;
            const double away = ndc && g.reversed_z ? -slope : slope;  // > 0: depth grows along +q2
            if (away > 0.0) {
                q2 = -q2;
                report.mirrored = true;
            }
            if (!ndc) {
                if (std::abs(std::abs(slope) - 1.0) > 1e-3)
                    report.notes.push_back(fmt::format(
                        "the depth pass scales {:.6g} against the view axis (1 expected for planar/radial depth)",
                        std::abs(slope)));
                t2 = -offset;  // d = -(q2 . X + t2) with q2 already signed
                have_t2 = true;
            }
        }
    }
    if (!have_t2) {
        double nearest = -std::numeric_limits<double>::infinity();
        for (const Point* p : points) nearest = std::max(nearest, glm::dot(q2, p->world));
        t2 = -1.0 - nearest;  // the nearest point lies at distance 1
        report.notes.push_back("orthographic camera position along the view axis is arbitrary: nearest point at distance 1");
    }
    glm::dmat4 v(1.0);
    setRow(v, 0, glm::dvec4(q0, t0));
    setRow(v, 1, glm::dvec4(q1, t1));
    setRow(v, 2, glm::dvec4(q2, t2));
    camera.world_to_camera = v;
    camera.projection = glm::dmat4(1.0);
    setRow(camera.projection, 0, {k00, k01, 0.0, 0.0});
    setRow(camera.projection, 1, {0.0, k11, 0.0, 0.0});
    return true;
}

// Completes the projection's z row (OpenGL: z = -near -> -1, z = -far -> +1).
void finishDepthRange(const GBuffer& g, const std::vector<const Point*>& points, Camera& camera,
                      CameraSolveReport& report, const std::string& label) {
    const bool ortho = report.orthographic;
    const bool ndc = g.depth_convention == DepthConvention::Ndc && g.has(Attribute::Depth);
    double a = 0.0, b = 0.0;
    if (ndc) {
        double rms = 0.0;
        const auto row = fitNdcRow(g, camera.world_to_camera, points, ortho, &rms);
        if (!row) throw inputError(solveFailure(label, "the ndc depth pass does not fit a projection's z row"));
        a = row->first;
        b = row->second;
        report.near_plane = ortho ? (b + 1.0) / a : b / (a - 1.0);
        report.far_plane = ortho ? (b - 1.0) / a : b / (a + 1.0);
        report.near_far_rule = fmt::format("fitted to the ndc depth pass (RMS {:.3g} in ndc z)", rms);
        if (!std::isfinite(report.near_plane) || !std::isfinite(report.far_plane) ||
            !(report.far_plane > report.near_plane) || (!ortho && !(report.near_plane > 0.0)))
            throw inputError(solveFailure(label, fmt::format("the ndc depth pass gives near {:.6g}, far {:.6g}",
                                                             report.near_plane, report.far_plane)));
    } else {
        const auto [lo, hi] = depthRange(camera.world_to_camera, points);
        if (ortho) {
            const double margin = 0.5 * (hi - lo) + 1e-3 * std::max(1.0, std::abs(hi));
            report.near_plane = lo - margin;
            report.far_plane = hi + margin;
            report.near_far_rule = "depth range of the position pass widened by half its extent";
        } else {
            if (!(lo > 0.0)) throw inputError(solveFailure(label, "some points lie behind the solved camera"));
            report.near_plane = 0.5 * lo;
            report.far_plane = 2.0 * hi;
            report.near_far_rule = "half the nearest and twice the farthest depth of the position pass";
        }
        const double n = report.near_plane, f = report.far_plane;
        a = ortho ? -2.0 / (f - n) : -(f + n) / (f - n);
        b = ortho ? -(f + n) / (f - n) : -2.0 * f * n / (f - n);
    }
    setRow(camera.projection, 2, {0.0, 0.0, a, b});
}

}  // namespace

std::string CameraSolveReport::summary() const {
    std::string s = fmt::format("{}{}, reprojection RMS {:.4g} px, max {:.4g} px over {} pixels",
                                orthographic ? "orthographic" : "perspective", mirrored ? " (mirrored world)" : "",
                                rms_px, max_px, points - outliers);
    if (outliers > 0)
        s += fmt::format(" ({} outliers beyond the fit left out; all pixels: RMS {:.4g} px, max {:.4g} px)", outliers,
                         rms_all_px, max_all_px);
    return s;
}

Camera solveCamera(const GBuffer& g, const std::string& label, CameraSolveReport* report_out,
                   const CameraSolveOptions& options) {
    if (!g.has(Attribute::Position)) throw inputError(solveFailure(label, "no position pass"));
    if (g.display_width <= 0 || g.display_height <= 0) throw inputError(solveFailure(label, "empty display window"));
    const std::vector<Point> all = collectPoints(g);
    if (all.size() < 12)
        throw inputError(solveFailure(label, fmt::format("{} valid pixels; at least 12 are needed", all.size())));
    std::vector<const Point*> every;
    for (const Point& p : all) every.push_back(&p);

    CameraSolveReport report;
    report.points = all.size();
    const double flat = flatness(subset(every, options.max_fit_points));
    if (flat < 1e-4)
        throw inputError(solveFailure(
            label, fmt::format("the visible geometry is flat (thickness {:.2g} of its extent): one plane does not "
                               "determine a camera; pass --camera camera.json",
                               flat)));
    if (flat < 1e-2)
        report.notes.push_back(fmt::format("the visible geometry is nearly flat (thickness {:.2g} of its extent): the "
                                           "solve is poorly conditioned",
                                           flat));

    // Projective fit with outlier rounds: antialiased edge pixels average positions of different
    // surfaces and land off their pixel; they are left out once a first fit exists.
    std::vector<const Point*> inliers = every;
    std::optional<Projective> projective;
    double previous_threshold = -1.0;
    for (int round = 0; round < 8; ++round) {
        const std::vector<const Point*> fit_points = subset(inliers, options.max_fit_points);
        const Normaliser n = normaliserFor(fit_points);
        std::optional<Projective> fit = fitProjective(fit_points, n, nullptr);
        for (int i = 0; fit && i < 4; ++i)
            if (auto refined = fitProjective(fit_points, n, &*fit)) fit = refined;
        if (!fit) throw inputError(solveFailure(label, "the position pass is degenerate (all points on a line?)"));
        projective = fit;
        // The threshold shrinks towards outlier_px as the fit improves (a first fit pulled by
        // outliers is off everywhere; three times the median residual keeps the bulk).
        std::vector<double> residuals;
        residuals.reserve(every.size());
        for (const Point* p : every) residuals.push_back(residualPx(*projective, *p));
        const double threshold = std::max(options.outlier_px, 3.0 * geometry::median(residuals));
        std::vector<const Point*> next;
        for (std::size_t i = 0; i < every.size(); ++i)
            if (residuals[i] <= threshold) next.push_back(every[i]);
        if (next.size() < 12) break;
        const bool stable = next.size() == inliers.size() && threshold == previous_threshold;
        inliers = next;
        previous_threshold = threshold;
        if (stable && threshold == options.outlier_px) break;
    }
    // Affine fit on the same pixels: an orthographic camera when it does as well.
    const std::vector<const Point*> fit_points = subset(inliers, options.max_fit_points);
    const std::optional<Affine> affine = fitAffine(fit_points, normaliserFor(fit_points));
    const Stats projective_stats = statsOf(*projective, inliers);
    if (affine) {
        const Stats affine_stats = statsOf(*affine, inliers);
        report.orthographic = affine_stats.rms <= 1.5 * projective_stats.rms + 1e-3;
    }

    Camera camera;
    const bool decomposed = report.orthographic ? decomposeOrthographic(*affine, g, inliers, camera, report)
                                                : decomposePerspective(*projective, g, inliers, camera, report);
    if (!decomposed) throw inputError(solveFailure(label, "the fitted projection is degenerate"));
    finishDepthRange(g, inliers, camera, report, label);

    // The residuals of the final camera, as used downstream.
    auto residual = [&](const Point& p) {
        const glm::dvec4 clip = camera.projection * camera.world_to_camera * glm::dvec4(p.world, 1.0);
        const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
        const glm::dvec2 expected = displayPixelToNdc(g, p.pixel);
        const double dx = (ndc.x - expected.x) * 0.5 * g.display_width, dy = (ndc.y - expected.y) * 0.5 * g.display_height;
        const double e = std::sqrt(dx * dx + dy * dy);
        return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
    };
    double sum_in = 0.0, sum_all = 0.0;
    std::size_t inlier_count = 0;
    for (const Point& p : all) {
        const double e = residual(p);
        sum_all += e * e;
        report.max_all_px = std::max(report.max_all_px, e);
        if (e <= options.outlier_px) {
            sum_in += e * e;
            report.max_px = std::max(report.max_px, e);
            ++inlier_count;
        }
    }
    report.outliers = all.size() - inlier_count;
    report.rms_all_px = std::sqrt(sum_all / double(all.size()));
    report.rms_px = inlier_count ? std::sqrt(sum_in / double(inlier_count)) : std::numeric_limits<double>::infinity();
    report.near_plane = camera.nearPlane();
    report.far_plane = camera.farPlane();
    camera.source = fmt::format("{} (solved from the position pass: {})", label, report.summary());
    if (report_out) *report_out = report;

    const double outlier_fraction = double(report.outliers) / double(all.size());
    if (inlier_count < 12 || outlier_fraction > options.max_outlier_fraction || !(report.rms_px <= options.max_rms_px))
        throw inputError(solveFailure(
            label, fmt::format("reprojection error too large: RMS {:.4g} px, max {:.4g} px over all {} valid pixels, "
                               "{} of them ({:.1f}%) beyond {} px (limits: RMS {} px over the rest, {:.0f}% outliers); "
                               "pass --camera camera.json",
                               report.rms_all_px, report.max_all_px, all.size(), report.outliers,
                               100.0 * outlier_fraction, options.outlier_px, options.max_rms_px,
                               100.0 * options.max_outlier_fraction)));
    return camera;
}

Reprojection reprojectionError(const GBuffer& g, const Camera& camera) {
    Reprojection r;
    double sum = 0.0;
    for (const Point& p : collectPoints(g)) {
        const glm::dvec4 clip = camera.projection * camera.world_to_camera * glm::dvec4(p.world, 1.0);
        const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
        const glm::dvec2 expected = displayPixelToNdc(g, p.pixel);
        const double dx = (ndc.x - expected.x) * 0.5 * g.display_width, dy = (ndc.y - expected.y) * 0.5 * g.display_height;
        double e = std::sqrt(dx * dx + dy * dy);
        if (!std::isfinite(e)) e = std::numeric_limits<double>::infinity();
        sum += e * e;
        r.max_px = std::max(r.max_px, e);
        ++r.points;
    }
    r.rms_px = r.points ? std::sqrt(sum / double(r.points)) : 0.0;
    return r;
}

}  // namespace decalcomp
