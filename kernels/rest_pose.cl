/* The rest pass of texture-space decals (docs/texture-space.md), per binding, before shading:
 * dc_rest_lookup finds each object pixel's rest point through its UV; dc_rest_frame then turns the
 * mesh's tangent frame there into the pixel's rest -> camera rotation, for normals. */
#include "reconstruct.h"
#include "rest_pose.h"
#include "shared_types.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

/* Bake-mode bindings (uv_only) get points[i] = (u, v, 0, 1) for the object's pixels instead.
 * Writes points[i] = (rest point, triangle + 1), or 0 where the pixel is not the object's or no
 * triangle holds its UV (within 1e-5 barycentric: the most inside of the cell's candidates), and
 * weights[i] = the triangle's barycentric weights. Triangle numbers stay exact below 2^24. */
__kernel void dc_rest_lookup(__constant const DcFrame* frame, __global const DcRestBinding* bindings, int b,
                             __global const float2* uv_plane, __global const float* mask_weights,
                             __global const float4* vertices, __global const int4* triangles,
                             __global const int* cells, __global const int* cell_triangles,
                             __global const float4* uv_triangles, __global float4* rest_points,
                             __global float4* rest_frames) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    const size_t pixels = (size_t)frame->width * frame->height, i = (size_t)y * frame->width + x;
    __global const DcRestBinding* g = &bindings[b];
    float4 out = (float4)(0.0f), weights = (float4)(0.0f);
    float2 uv = uv_plane[i];
    if (g->flip_v) uv.y = 1.0f - uv.y;
    const bool selected = g->mask < 0 || mask_weights[(size_t)g->mask * pixels + i] > 0.0f;
    if (g->uv_only) { /* bake mode: the pixel's UV is all its decals need (rest_pose.h) */
        rest_points[(size_t)b * pixels + i] = selected && all(isfinite(uv)) ? (float4)(uv, 0.0f, 1.0f) : (float4)(0.0f);
        rest_frames[(size_t)b * pixels + i] = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
        return;
    }
    const float2 cell = (uv - vload2(0, g->uv_origin)) * vload2(0, g->cells_per_uv);
    if (selected && all(isfinite(uv)) && cell.x >= -1e-3f && cell.y >= -1e-3f && cell.x <= g->cells_x + 1e-3f &&
        cell.y <= g->cells_y + 1e-3f) {
        const int cx = clamp((int)floor(cell.x), 0, g->cells_x - 1), cy = clamp((int)floor(cell.y), 0, g->cells_y - 1);
        const int c = g->first_cell + cy * g->cells_x + cx;
        float best = -1e30f;
        int best_triangle = -1;
        float3 best_w = (float3)(0.0f);
        for (int k = cells[c]; k < cells[c + 1]; ++k) {
            const int t = cell_triangles[k];
            /* the triangle's UV corner, edges and 1 / det, two contiguous loads (rest_pass.cpp) */
            const float4 r0 = uv_triangles[2 * t], r1 = uv_triangles[2 * t + 1];
            const float2 e0 = r0.zw, e1 = r1.xy, dp = uv - r0.xy;
            if (!(r1.z != 0.0f)) continue; /* degenerate in UV */
            const float wb = (dp.x * e1.y - dp.y * e1.x) * r1.z, wc = (e0.x * dp.y - e0.y * dp.x) * r1.z;
            const float3 w = (float3)(1.0f - wb - wc, wb, wc);
            const float inside = fmin(w.x, fmin(w.y, w.z));
            if (inside > best) {
                best = inside;
                best_triangle = t;
                best_w = w;
            }
        }
        if (best_triangle >= 0 && best >= -1e-5f) {
            const int4 tri = triangles[best_triangle];
            const float3 p = vertices[3 * tri.x].xyz * best_w.x + vertices[3 * tri.y].xyz * best_w.y +
                             vertices[3 * tri.z].xyz * best_w.z;
            out = (float4)(p, (float)(best_triangle + 1));
            weights = (float4)(best_w, 0.0f);
        }
    }
    rest_points[(size_t)b * pixels + i] = out;
    if (frame->rest_frames) rest_frames[(size_t)b * pixels + i] = weights; /* only dc_rest_frame reads them */
}

/* The neighbour of (x, y) one step along (dx, dy) or against it, whichever is on the mesh and nearer
 * in camera space: the differences of rest and camera points towards it. */
inline bool dc_rest_difference(__constant const DcFrame* f, __global const float* depth_plane,
                               __global const float4* position_plane, __global const float4* points, int x, int y,
                               int dx, int dy, float3 p_rest, float3 p_cam, float3* d_rest, float3* d_cam) {
    float best = MAXFLOAT;
    for (int side = 1; side >= -1; side -= 2) {
        const int nx = x + side * dx, ny = y + side * dy;
        if (nx < 0 || ny < 0 || nx >= f->width || ny >= f->height) continue;
        const float4 r = points[(size_t)ny * f->width + nx];
        float3 c;
        if (!(r.w > 0.0f) || !dc_reconstruct(f, depth_plane, position_plane, nx, ny, &c)) continue;
        const float dist = length(c - p_cam);
        if (dist < best) {
            best = dist;
            *d_rest = r.xyz - p_rest;
            *d_cam = c - p_cam;
        }
    }
    return best < MAXFLOAT && length(*d_rest) > 0.0f;
}

/* Rotation taking unit vector a to unit vector b along the shortest arc. */
inline float4 dc_quat_between(float3 a, float3 b) {
    const float c = dot(a, b);
    if (c < -0.999999f) {
        const float3 axis = normalize(fabs(a.x) < 0.9f ? cross(a, (float3)(1, 0, 0)) : cross(a, (float3)(0, 1, 0)));
        return (float4)(axis, 0.0f);
    }
    return normalize((float4)(cross(a, b), 1.0f + c));
}

/* Rotation matrix (rows r0, r1, r2) as a unit quaternion. */
inline float4 dc_quat_from_rows(float3 r0, float3 r1, float3 r2) {
    const float trace = r0.x + r1.y + r2.z;
    float4 q;
    if (trace > 0.0f) {
        const float s = 2.0f * sqrt(trace + 1.0f);
        q = (float4)((r2.y - r1.z) / s, (r0.z - r2.x) / s, (r1.x - r0.y) / s, 0.25f * s);
    } else if (r0.x > r1.y && r0.x > r2.z) {
        const float s = 2.0f * sqrt(1.0f + r0.x - r1.y - r2.z);
        q = (float4)(0.25f * s, (r0.y + r1.x) / s, (r0.z + r2.x) / s, (r2.y - r1.z) / s);
    } else if (r1.y > r2.z) {
        const float s = 2.0f * sqrt(1.0f + r1.y - r0.x - r2.z);
        q = (float4)((r0.y + r1.x) / s, 0.25f * s, (r1.z + r2.y) / s, (r0.z - r2.x) / s);
    } else {
        const float s = 2.0f * sqrt(1.0f + r2.z - r0.x - r1.y);
        q = (float4)((r0.z + r2.x) / s, (r1.z + r2.y) / s, 0.25f * s, (r1.x - r0.y) / s);
    }
    return normalize(q);
}

/* Replaces rest_frames[i] (the barycentric weights) by the rest -> camera rotation: the mesh's
 * normal goes to the pixel's normal (the normal pass, else the neighbours' cross product), and its
 * tangent to the tangent's image under the local deformation, which the neighbours' rest and camera
 * point differences give. With too few neighbours on the mesh: the shortest arc between the normals. */
__kernel void dc_rest_frame(__constant const DcFrame* frame, int b, __global const float* depth_plane,
                            __global const float4* position_plane, __global const float4* surface1,
                            __global const float4* vertices, __global const int4* triangles,
                            __global const float4* rest_points, __global float4* rest_frames) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    const size_t pixels = (size_t)frame->width * frame->height, i = (size_t)y * frame->width + x;
    __global const float4* points = rest_points + (size_t)b * pixels;
    const float4 r = points[i];
    const float4 identity = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    float3 p_cam;
    if (!(r.w > 0.0f) || !dc_reconstruct(frame, depth_plane, position_plane, x, y, &p_cam)) {
        rest_frames[(size_t)b * pixels + i] = identity;
        return;
    }
    const float3 w = rest_frames[(size_t)b * pixels + i].xyz;
    const int4 tri = triangles[(int)r.w - 1];
    const float3 rest_normal = normalize(vertices[3 * tri.x + 1].xyz * w.x + vertices[3 * tri.y + 1].xyz * w.y +
                                         vertices[3 * tri.z + 1].xyz * w.z);
    float3 rest_tangent = vertices[3 * tri.x + 2].xyz * w.x + vertices[3 * tri.y + 2].xyz * w.y +
                          vertices[3 * tri.z + 2].xyz * w.z;
    rest_tangent = normalize(rest_tangent - rest_normal * dot(rest_normal, rest_tangent));

    float3 a = 0.0f, ac = 0.0f, bb = 0.0f, bc = 0.0f;
    const bool has_x = dc_rest_difference(frame, depth_plane, position_plane, points, x, y, 1, 0, r.xyz, p_cam, &a, &ac);
    const bool has_y = dc_rest_difference(frame, depth_plane, position_plane, points, x, y, 0, 1, r.xyz, p_cam, &bb, &bc);
    float3 n;
    if (frame->has_normal) {
        n = normalize(dc_world_to_camera_vector(frame, surface1[i].xyz));
    } else if (has_x && has_y) {
        n = normalize(cross(ac, bc));
        if (dot(n, p_cam) > 0.0f) n = -n; /* towards the camera */
    } else {
        rest_frames[(size_t)b * pixels + i] = identity;
        return;
    }
    float4 q = dc_quat_between(rest_normal, n);
    if (has_x && has_y) {
        /* the tangent in the basis of the two rest differences (least squares), mapped by their
         * camera twins: the deformation gradient applied to it */
        const float aa = dot(a, a), ab = dot(a, bb), b2 = dot(bb, bb), det = aa * b2 - ab * ab;
        if (det > 1e-12f * aa * b2) {
            const float ta = dot(rest_tangent, a), tb = dot(rest_tangent, bb);
            const float alpha = (ta * b2 - tb * ab) / det, beta = (tb * aa - ta * ab) / det;
            float3 t = alpha * ac + beta * bc;
            t -= n * dot(n, t);
            if (length(t) > 1e-12f) {
                const float3 f1 = normalize(t), f2 = cross(n, f1);
                const float3 e1 = rest_tangent, e2 = cross(rest_normal, rest_tangent), e3 = rest_normal;
                /* R = f1 e1^T + f2 e2^T + n e3^T, by rows */
                const float3 r0 = f1.x * e1 + f2.x * e2 + n.x * e3;
                const float3 r1 = f1.y * e1 + f2.y * e2 + n.y * e3;
                const float3 r2 = f1.z * e1 + f2.z * e2 + n.z * e3;
                q = dc_quat_from_rows(r0, r1, r2);
            }
        }
    }
    rest_frames[(size_t)b * pixels + i] = q;
}

#endif /* DC_SHADING_PROGRAM */
