#!/usr/bin/python3
"""Independent numpy check of a texture-space decal sequence (not decalcomp's code):

    /usr/bin/python3 tools/blender/deform_check.py data/blender-deform-own [--world]

For every pixel of the decal's object (IndexOB == pass_index): its UV from the gbuffer's UV pass,
the mesh_rest.obj triangle holding it (brute force over all triangles, largest smallest barycentric
weight), the rest point by barycentric interpolation, then each decal of scene.json in order: local
= inverse(matrix) @ P_rest, inside iff |x|, |y|, |z| <= 0.5, s = x + 0.5, t = 0.5 - y, the nearest
texel (column floor(s*w), row floor(t*h) from the top, clamped), sRGB decoded, straight alpha,
albedo = albedo * (1 - a) + rgb * a. With --world it evaluates scene_world.json at the Position pass
instead (every pixel). Prints the PSNR of DiffCol against truth.NNNN.exr over DecalMask > 0.5.
Needs numpy and OpenImageIO's Python module (Debian: python3-numpy, python3-openimageio).
"""
import argparse
import glob
import json
import math
import os
import re

import numpy as np
import OpenImageIO as oiio


def read_exr(path):
    buf = oiio.ImageBuf(path)
    pixels = buf.get_pixels(oiio.FLOAT)
    return {n: pixels[:, :, i] for i, n in enumerate(buf.spec().channelnames)}


def read_obj(path):
    v, vt, faces = [], [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                v.append([float(x) for x in p[1:4]])
            elif p[0] == "vt":
                vt.append([float(x) for x in p[1:3]])
            elif p[0] == "f":
                faces.append([[int(i) - 1 for i in c.split("/")[:2]] for c in p[1:]])
    f = np.array(faces)  # (T, 3, 2): vertex, vt
    return np.array(v)[f[:, :, 0]], np.array(vt, np.float64)[f[:, :, 1]]


def rest_points(tri_pos, tri_uv, uv):
    """(P_rest, found) for UVs (N, 2): the triangle whose smallest barycentric weight is largest."""
    best_w = np.full(len(uv), -np.inf)
    best = np.zeros((len(uv), 3))
    for (a, b, c), pos in zip(tri_uv, tri_pos):
        e1, e2 = b - a, c - a
        det = e1[0] * e2[1] - e1[1] * e2[0]
        if det == 0:
            continue
        d = uv - a
        w1 = (d[:, 0] * e2[1] - d[:, 1] * e2[0]) / det
        w2 = (e1[0] * d[:, 1] - e1[1] * d[:, 0]) / det
        w = np.stack([1 - w1 - w2, w1, w2], 1)
        m = w.min(1)
        better = m > best_w
        best_w[better] = m[better]
        best[better] = w[better] @ pos
    return best, best_w >= -1e-5


def srgb_eotf(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def apply_decals(albedo, points, decals, folder):
    for d in decals:
        inv = np.linalg.inv(np.array(d["matrix"], np.float64))
        local = points @ inv[:3, :3].T + inv[:3, 3]
        inside = np.all(np.abs(local) <= 0.5, axis=1)
        tex = d["texture"]["albedo"] if isinstance(d["texture"], dict) else d["texture"]
        img = oiio.ImageBuf(os.path.join(folder, tex)).get_pixels(oiio.UINT8).astype(np.float64) / 255.0
        h, w = img.shape[:2]
        col = np.clip(np.floor((local[:, 0] + 0.5) * w), 0, w - 1).astype(int)
        row = np.clip(np.floor((0.5 - local[:, 1]) * h), 0, h - 1).astype(int)
        texel = img[row, col]
        a = np.where(inside, texel[:, 3], 0.0)[:, None]
        albedo = albedo * (1 - a) + srgb_eotf(texel[:, :3]) * a
    return albedo


def main():
    p = argparse.ArgumentParser()
    p.add_argument("folder")
    p.add_argument("--world", action="store_true", help="score scene_world.json (the negative control)")
    args = p.parse_args()
    scene = json.load(open(os.path.join(args.folder, "scene_world.json" if args.world else "scene.json")))
    decals = scene["decals"]
    tri_pos, tri_uv = read_obj(os.path.join(args.folder, "mesh_rest.obj"))
    for path in sorted(glob.glob(os.path.join(args.folder, "gbuffer.[0-9][0-9][0-9][0-9].exr"))):
        frame = int(re.search(r"(\d{4})\.exr$", path).group(1))
        g = read_exr(path)
        t = read_exr(os.path.join(args.folder, f"truth.{frame:04d}.exr"))
        albedo = np.stack([g["ViewLayer.DiffCol." + c] for c in "RGB"], -1).astype(np.float64)
        out = albedo.copy()
        if args.world:
            sel = g["ViewLayer.Depth.Z"] < 1e9
            pts = np.stack([g["ViewLayer.Position." + c] for c in "XYZ"], -1)[sel].astype(np.float64)
            out[sel] = apply_decals(albedo[sel], pts, decals, args.folder)
            missed = 0
        else:
            sel = g["ViewLayer.IndexOB.X"] == decals[0]["pass_index"]
            uv = np.stack([g["ViewLayer.UV.U"][sel], g["ViewLayer.UV.V"][sel]], -1).astype(np.float64)
            pts, found = rest_points(tri_pos, tri_uv, uv)
            res = albedo[sel]
            res[found] = apply_decals(res[found], pts[found], decals, args.folder)
            out[sel] = res
            missed = int((~found).sum())
        mask = t["ViewLayer.DecalMask.X"] > 0.5
        truth = np.stack([t["ViewLayer.DiffCol." + c] for c in "RGB"], -1).astype(np.float64)
        out32 = out.astype(np.float32).astype(np.float64)
        mse = np.mean((out32[mask] - truth[mask]) ** 2)
        psnr = math.inf if mse == 0 else 10 * math.log10(1.0 / mse)
        print(f"frame {frame}: {psnr:.1f} dB over {int(mask.sum())} decal pixels"
              f" (max abs diff {np.abs(out32[mask] - truth[mask]).max():.3g}, UVs off the mesh: {missed})")


if __name__ == "__main__":
    main()
