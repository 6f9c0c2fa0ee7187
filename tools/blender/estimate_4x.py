#!/usr/bin/python3
"""The 4x-supersampled estimate for our own antialiased datasets (issue 15), independent of decalcomp.

    /usr/bin/python3 tools/blender/estimate_4x.py data/blender-aa-gauss [--cache DIR] [--fit gaussian|box|...]

1. Renders (once; kept in --cache, default /tmp/decalcomp-own-4x) the same scene at 4x resolution
   (1280x960), 1 sample per pixel, pixel filter box 0.01 px (no antialiasing: every pass samples
   the sub-pixel centre), without decals (gbuffer.exr) and with them (truth.exr), through
   tools/blender/own_scene.py.
2. Composites the dataset's scene.json (box and frustum decals, nearest texels, sRGB PNG with
   straight alpha, 'over' in list order) onto the 4x G-buffer's DiffCol with numpy, from its
   Position pass, and checks it against Blender's own 4x truth (must be far above 100 dB).
3. Fits the pixel filter: filters Blender's 4x truth DiffCol down to 320x240 with a separable
   filter of each candidate width and scores it against the dataset's antialiased truth.
   Widths follow decalcomp's --pixel-filter conventions (docs/pixel-filter.md): gaussian:W is
   exp(-2 (2x/W)^2) (sigma = W/4), box:W is 1 on |x| <= W/2, blackman-harris:W the 4-term window
   over W.
4. The estimate: the numpy 4x composite filtered down with the fitted filter, scored as
   data/README.md scores (PSNR of DiffCol R,G,B, peak 1, over the truth's DecalMask > 0.5).
   Also: the same with the nominal width, point-sampled (the 4x composite's sub-pixel nearest the
   pixel centre is not a pixel centre, so the point figure comes from decalcomp's tests), and
   untouched.

Prints a summary and writes it to DATASET/estimate.json.
"""
import argparse
import hashlib
import json
import os
import subprocess
import sys
import zlib

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
SCALE = 4


def read_channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT)
    out = []
    for n in names:
        if n not in spec.channelnames:
            raise SystemExit(f"{path}: no channel {n}")
        out.append(pixels[..., spec.channelnames.index(n)].astype(np.float64))
    return np.stack(out, -1)


def read_png(path):
    """8-bit RGBA PNG as tools/blender/textures.py writes it (filter 0 rows): uint8 (h, w, 4), top row first."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", None
    while pos < len(data):
        length = int.from_bytes(data[pos:pos + 4], "big")
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h = int.from_bytes(body[0:4], "big"), int.from_bytes(body[4:8], "big")
            assert body[8:10] == b"\x08\x06", "8-bit RGBA only"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + 4 * w)
    assert (raw[:, 0] == 0).all(), "filter type 0 rows only"
    return raw[:, 1:].reshape(h, w, 4)


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def composite(scene_path, position, albedo, background):
    """The decals of scene_path over `albedo` (h, w, 3) at the points `position` (h, w, 3)."""
    folder = os.path.dirname(scene_path)
    scene = json.load(open(scene_path))
    out = albedo.copy()
    p = np.concatenate([position, np.ones(position.shape[:2] + (1,))], -1)
    for d in scene["decals"]:
        tex = scene["textures"][d["texture"]]["albedo"]
        img = read_png(os.path.join(folder, tex)).astype(np.float64) / 255.0
        th, tw = img.shape[:2]
        m = np.array(d["matrix"], np.float64)
        local = p @ np.linalg.inv(m).T
        x, y, z = local[..., 0], local[..., 1], local[..., 2]
        if d["kind"] == "box":
            inside = (np.abs(x) <= 0.5) & (np.abs(y) <= 0.5) & (np.abs(z) <= 0.5)
            s, t = x + 0.5, 0.5 - y
        elif d["kind"] == "frustum":
            h = np.tan(np.radians(d["fov_y_deg"]) / 2)
            dd = -z
            with np.errstate(divide="ignore", invalid="ignore"):
                inside = (dd >= d["near"]) & (dd <= d["far"]) & (np.abs(x) <= dd * h * d["aspect"]) & \
                         (np.abs(y) <= dd * h)
                s = 0.5 + x / (2 * dd * h * d["aspect"])
                t = 0.5 - y / (2 * dd * h)
        else:
            raise SystemExit(f"kind {d['kind']} not handled")
        inside &= ~background
        s, t = np.where(inside, s, 0), np.where(inside, t, 0)
        col = np.clip(np.floor(s * tw), 0, tw - 1).astype(int)
        row = np.clip(np.floor(t * th), 0, th - 1).astype(int)
        texel = img[row, col]
        colour = srgb_to_linear(texel[..., :3])
        f = np.where(inside, texel[..., 3] * d.get("opacity", 1.0), 0.0)[..., None]
        out = out * (1 - f) + colour * f
    return out


def blend_into_filtered_albedo(scene_path, position, albedo, background, kind, width):
    """What exact per-decal coverage can reach when each filtered decal is blended into the pixel's
    FILTERED albedo (the only albedo a filtered G-buffer holds), one decal at a time in list order:
    result = result * (1 - filter(f)) + filter(f * colour). It differs from the 4x estimate where
    the albedo under a decal varies across the footprint (silhouettes, a decal over another's edges)."""
    scene = json.load(open(scene_path))
    result = filter_down(albedo, kind, width)
    zero, one = np.zeros_like(albedo), np.ones_like(albedo)
    for d in scene["decals"]:
        single = dict(scene, decals=[d])
        path = scene_path + ".single.json"
        with open(path, "w") as f:
            json.dump(single, f)
        try:
            over_zero = composite(path, position, zero, background)  # f * colour
            over_one = composite(path, position, one, background)  # 1 - f + f * colour
        finally:
            os.remove(path)
        result = result * (1 - filter_down(1 - (over_one - over_zero), kind, width)) + \
            filter_down(over_zero, kind, width)
    return result


def filter_weights(kind, width):
    """Per-axis weight of an offset x in low-res pixels."""
    if kind == "gaussian":
        return (lambda x: np.exp(-2 * (2 * x / width) ** 2)), 1.5 * width  # Cycles' table: 6 sigma
    if kind == "box":
        return (lambda x: (np.abs(x) <= width / 2).astype(np.float64)), width / 2
    if kind == "blackman-harris":
        def bh(x):
            u = x / width + 0.5
            v = 0.35875 - 0.48829 * np.cos(2 * np.pi * u) + 0.14128 * np.cos(4 * np.pi * u) - \
                0.01168 * np.cos(6 * np.pi * u)
            return np.where(np.abs(x) <= width / 2, v, 0.0)
        return bh, width / 2
    raise ValueError(kind)


def down_matrix(n_low, kind, width):
    """(n_low, SCALE*n_low): row i holds the weights of the sub-pixel samples for low-res pixel i."""
    f, _ = filter_weights(kind, width)
    centres_hi = (np.arange(SCALE * n_low) + 0.5) / SCALE
    offset = centres_hi[None, :] - (np.arange(n_low) + 0.5)[:, None]
    w = f(offset)
    return w / w.sum(1, keepdims=True)


def filter_down(img, kind, width):
    h, w = img.shape[0] // SCALE, img.shape[1] // SCALE
    wy, wx = down_matrix(h, kind, width), down_matrix(w, kind, width)
    return np.stack([wy @ img[..., c] @ wx.T for c in range(img.shape[2])], -1)


def psnr(a, b, mask):
    d = (a - b)[mask]
    return float(10 * np.log10(1.0 / max(np.mean(d * d), 1e-30)))


def render_4x(dataset, cache):
    cam = json.load(open(os.path.join(dataset, "camera.json")))
    done = os.path.join(cache, "done")
    if os.path.exists(done):
        return
    os.makedirs(cache, exist_ok=True)
    cmd = ["nice", "blender", "-b", "--factory-startup", "--python", os.path.join(HERE, "own_scene.py"), "--",
           "--out", cache, "--filter", "box", "--filter-width", "0.01", "--samples", "1", "--scale", str(SCALE),
           "--no-crypto", "--seed", str(cam["render"]["seed"])]
    print("rendering the 4x frames:", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    open(done, "w").write("ok\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dataset")
    ap.add_argument("--cache", help="where the 4x frames are kept (default: /tmp/decalcomp-own-4x-<hash of the "
                    "scene scripts>, so that a changed scene renders again)")
    args = ap.parse_args()
    if not args.cache:
        digest = hashlib.sha1()
        for name in ("own_scene.py", "textures.py"):
            digest.update(open(os.path.join(HERE, name), "rb").read())
        args.cache = "/tmp/decalcomp-own-4x-" + digest.hexdigest()[:10]
    dataset = os.path.abspath(args.dataset)
    render_4x(dataset, args.cache)
    rgb = ["ViewLayer.DiffCol." + c for c in "RGB"]
    g4 = os.path.join(args.cache, "gbuffer.exr")
    t4 = os.path.join(args.cache, "truth.exr")
    pos4 = read_channels(g4, ["ViewLayer.Position." + c for c in "XYZ"])
    depth4 = read_channels(g4, ["ViewLayer.Depth.Z"])[..., 0]
    alb4 = read_channels(g4, rgb)
    truth4 = read_channels(t4, rgb)
    mask4 = read_channels(t4, ["ViewLayer.DecalMask.X"])[..., 0] > 0.5
    background4 = depth4 >= 1e10
    comp4 = composite(os.path.join(dataset, "scene.json"), pos4, alb4, background4)
    summary = {"numpy_4x_vs_blender_4x_db": psnr(comp4, truth4, mask4), "decal_pixels_4x": int(mask4.sum())}

    # the camera against the unfiltered 4x passes: planar depth
    cam = json.load(open(os.path.join(dataset, "camera.json")))
    w2c = np.array(cam["world_to_camera"])
    hit = ~background4
    pc = np.concatenate([pos4, np.ones(pos4.shape[:2] + (1,))], -1) @ w2c.T
    summary["planar_depth_max_abs_err_4x"] = float(np.abs(-pc[..., 2] - depth4)[hit].max())
    summary["radial_depth_max_abs_err_4x"] = float(np.abs(np.linalg.norm(pc[..., :3], axis=-1) - depth4)[hit].max())

    truth = read_channels(os.path.join(dataset, "truth.exr"), rgb)
    gbuf = read_channels(os.path.join(dataset, "gbuffer.exr"), rgb)
    mask = read_channels(os.path.join(dataset, "truth.exr"), ["ViewLayer.DecalMask.X"])[..., 0] > 0.5
    everything = np.ones(mask.shape, bool)
    summary["decal_pixels"] = int(mask.sum())
    summary["untouched_db"] = psnr(gbuf, truth, mask)
    kind = {"GAUSSIAN": "gaussian", "BOX": "box", "BLACKMAN_HARRIS": "blackman-harris"}[cam["render"]["pixel_filter"]]
    nominal = cam["render"]["filter_width_px"]
    if kind == "gaussian":
        widths = np.round(np.arange(1.0, 4.01, 0.1), 2)
    elif kind == "box":
        widths = np.array([0.5, 1.0, 1.5, 2.0])  # distinct sub-pixel sets on the 4x grid (0.75 = 1.0 there)
    else:
        widths = np.round(np.arange(1.0, 4.01, 0.25), 2)
    fit = []
    for wdt in widths:
        f4 = filter_down(truth4, kind, wdt)
        fit.append((float(wdt), psnr(f4, truth, mask), psnr(f4, truth, everything)))
        print(f"  fit {kind}:{wdt:g}: blender 4x truth filtered vs AA truth: decal pixels {fit[-1][1]:.2f} dB, "
              f"all pixels {fit[-1][2]:.2f} dB", flush=True)
    best = max(fit, key=lambda r: (round(r[1], 6), -abs(r[0] - nominal)))  # ties: the nominal width
    summary["filter"] = {"cycles": f"{cam['render']['pixel_filter']} {nominal:g} px", "family": kind,
                         "fit": [{"width": w, "decal_db": a, "all_db": b} for w, a, b in fit],
                         "best_width": best[0], "best_decal_db": best[1]}
    summary["estimate_db"] = psnr(filter_down(comp4, kind, best[0]), truth, mask)
    summary["estimate_db_all_pixels"] = psnr(filter_down(comp4, kind, best[0]), truth, everything)
    summary["blend_into_filtered_albedo_db"] = psnr(
        blend_into_filtered_albedo(os.path.join(dataset, "scene.json"), pos4, alb4, background4, kind, best[0]), truth,
        mask)
    per_kind = {}
    for k in ("Box", "Frustum"):
        mk = read_channels(os.path.join(dataset, "truth.exr"), [f"ViewLayer.DecalMask{k}.X"])[..., 0] > 0.5
        per_kind[k.lower()] = psnr(filter_down(comp4, kind, best[0]), truth, mk)
    summary["estimate_db_per_kind"] = per_kind
    if not np.isclose(best[0], nominal):
        summary["estimate_db_nominal_width"] = psnr(filter_down(comp4, kind, nominal), truth, mask)
    print(json.dumps({k: v for k, v in summary.items() if k != "filter"}, indent=2))
    print(f"best width {kind}:{best[0]:g} ({best[1]:.2f} dB)")
    summary["command"] = "/usr/bin/python3 tools/blender/estimate_4x.py " + os.path.relpath(dataset, os.path.dirname(
        os.path.dirname(HERE)))
    with open(os.path.join(dataset, "estimate.json"), "w") as f:
        json.dump(summary, f, indent=2)


if __name__ == "__main__":
    sys.exit(main())
