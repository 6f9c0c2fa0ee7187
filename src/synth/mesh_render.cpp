#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "decalcomp/synth_mesh.hpp"

namespace decalcomp::synth {

RestMesh tubeMesh(int around, int along, double radius, double height) {
    RestMesh mesh;
    mesh.source = "synthetic tube";
    // k = around duplicates k = 0's positions with u at the seam's other side
    for (int j = 0; j <= along; ++j)
        for (int k = 0; k <= around; ++k) {
            const double a = 2.0 * std::numbers::pi * k / around, z = height * j / along;
            RestVertex v;
            v.position = glm::vec3(float(radius * std::cos(a)), float(radius * std::sin(a)), float(z));
            v.uv = glm::vec2(float(0.05 + 0.9 * k / around), float(0.05 + 0.9 * j / along));
            mesh.vertices.push_back(v);
        }
    const int row = around + 1;
    for (int j = 0; j < along; ++j)
        for (int k = 0; k < around; ++k) {
            const int a = j * row + k, b = a + 1, c = a + row, d = c + 1;
            mesh.triangles.emplace_back(a, b, d);  // counter-clockwise seen from outside
            mesh.triangles.emplace_back(a, d, c);
        }
    finishRestMesh(mesh);
    return mesh;
}

std::vector<glm::vec3> twistAndBend(const RestMesh& mesh, double twist_deg, double bend_deg, double height) {
    std::vector<glm::vec3> out;
    const double twist = twist_deg * std::numbers::pi / 180.0, bend = bend_deg * std::numbers::pi / 180.0;
    for (const RestVertex& v : mesh.vertices) {
        const double t = twist * v.position.z / height, c = std::cos(t), s = std::sin(t);
        double x = c * v.position.x - s * v.position.y, y = s * v.position.x + c * v.position.y, z = v.position.z;
        if (std::abs(bend) > 1e-9) {  // an arc of radius R = height / bend through the base, towards +X
            const double r = height / bend, phi = z / r;
            const double nx = r - (r - x) * std::cos(phi), nz = (r - x) * std::sin(phi);
            x = nx;
            z = nz;
        }
        out.emplace_back(float(x), float(y), float(z));
    }
    return out;
}

namespace {

std::vector<glm::dvec3> vertexNormals(const RestMesh& rest, const std::vector<glm::vec3>& positions) {
    std::vector<glm::dvec3> normals(positions.size(), glm::dvec3(0.0));
    for (const glm::ivec3& t : rest.triangles) {
        const glm::dvec3 a(positions[std::size_t(t.x)]), b(positions[std::size_t(t.y)]), c(positions[std::size_t(t.z)]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        for (int k = 0; k < 3; ++k) normals[std::size_t(t[k])] += n;
    }
    for (glm::dvec3& n : normals) n = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
    return normals;
}

}  // namespace

MeshFrame renderMeshes(const std::vector<PosedMesh>& meshes, const Camera& camera, int width, int height) {
    MeshFrame out;
    GBuffer& g = out.gbuffer;
    g.width = g.display_width = width;
    g.height = g.display_height = height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    auto plane = [&](Attribute a, int components, float fill) {
        Plane& p = g.planes[a];
        p.components = components;
        p.samples.assign(pixels * std::size_t(components), fill);
        return &p;
    };
    Plane* depth = plane(Attribute::Depth, 1, 1e10f);
    Plane* albedo = plane(Attribute::Albedo, 3, 0.0f);
    Plane* normal = plane(Attribute::Normal, 3, 0.0f);
    Plane* position = plane(Attribute::Position, 3, 0.0f);
    Plane* id = plane(Attribute::ObjectId, 1, 0.0f);
    Plane* uv = plane(Attribute::UV, 2, 0.0f);
    out.rest_points.assign(pixels, std::nullopt);
    out.object.assign(pixels, -1);
    std::vector<double> nearest(pixels, std::numeric_limits<double>::infinity());
    const glm::dmat4 to_clip = camera.projection * camera.world_to_camera;
    const glm::dmat4 clip_to_world = glm::inverse(to_clip);
    const glm::dvec3 eye(glm::inverse(camera.world_to_camera)[3]);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const PosedMesh& mesh = meshes[m];
        const std::vector<glm::dvec3> normals = vertexNormals(*mesh.rest, mesh.positions);
        for (const glm::ivec3& t : mesh.rest->triangles) {
            const glm::dvec3 p[3] = {glm::dvec3(mesh.positions[std::size_t(t.x)]), glm::dvec3(mesh.positions[std::size_t(t.y)]),
                                     glm::dvec3(mesh.positions[std::size_t(t.z)])};
            // screen box of the triangle (it lies in front of the camera in these scenes)
            double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
            for (const glm::dvec3& q : p) {
                const glm::dvec4 c = to_clip * glm::dvec4(q, 1.0);
                const double sx = (c.x / c.w * 0.5 + 0.5) * width, sy = (0.5 - c.y / c.w * 0.5) * height;
                x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
            }
            const int px0 = std::max(0, int(std::floor(x0 - 0.5))), px1 = std::min(width - 1, int(std::ceil(x1)));
            const int py0 = std::max(0, int(std::floor(y0 - 0.5))), py1 = std::min(height - 1, int(std::ceil(y1)));
            const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
            for (int y = py0; y <= py1; ++y)
                for (int x = px0; x <= px1; ++x) {
                    const glm::dvec4 far = clip_to_world * glm::dvec4(2.0 * (x + 0.5) / width - 1.0,
                                                                      1.0 - 2.0 * (y + 0.5) / height, 1.0, 1.0);
                    const glm::dvec3 dir = glm::normalize(glm::dvec3(far) / far.w - eye);
                    // Moller-Trumbore
                    const glm::dvec3 h = glm::cross(dir, e2);
                    const double det = glm::dot(e1, h);
                    if (std::abs(det) < 1e-14) continue;
                    const glm::dvec3 s = eye - p[0];
                    const double b1 = glm::dot(s, h) / det;
                    const glm::dvec3 q = glm::cross(s, e1);
                    const double b2 = glm::dot(dir, q) / det, dist = glm::dot(e2, q) / det;
                    if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 || !(dist > 0.0)) continue;
                    const std::size_t i = std::size_t(y) * width + x;
                    if (dist >= nearest[i]) continue;
                    nearest[i] = dist;
                    const glm::dvec3 w(1.0 - b1 - b2, b1, b2);
                    const glm::dvec3 hit = eye + dir * dist;
                    glm::dvec3 n(0.0), rest(0.0);
                    glm::dvec2 tex(0.0);
                    for (int k = 0; k < 3; ++k) {
                        const RestVertex& v = mesh.rest->vertices[std::size_t(t[k])];
                        n += w[k] * normals[std::size_t(t[k])];
                        rest += w[k] * glm::dvec3(v.position);
                        tex += w[k] * glm::dvec2(v.uv);
                    }
                    n = glm::normalize(n);
                    depth->at(i, 0) = float(-(camera.world_to_camera * glm::dvec4(hit, 1.0)).z);
                    for (int c = 0; c < 3; ++c) {
                        albedo->at(i, c) = mesh.albedo[c];
                        normal->at(i, c) = float(n[c]);
                        position->at(i, c) = float(hit[c]);
                    }
                    id->at(i, 0) = float(mesh.object_id);
                    uv->at(i, 0) = float(tex.x);
                    uv->at(i, 1) = float(tex.y);
                    out.rest_points[i] = rest;
                    out.object[i] = int(m);
                }
        }
    }
    return out;
}

}  // namespace decalcomp::synth
