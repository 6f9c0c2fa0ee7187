"""Decal textures of our own datasets (data/blender-aa-gauss, -box, blender-beauty-aa).

Pure numpy + zlib, no randomness: the same bytes on every run. 8-bit sRGB RGBA PNGs with straight
alpha; alpha is 0 or 255 only (Cycles premultiplies 8-bit straight-alpha images in 8 bits on load,
so partial alphas would round differently in the renderer and in a compositor; the partial blend
comes from a decal's opacity instead). Usable from Blender's Python and from /usr/bin/python3.

    python3 tools/blender/textures.py OUTDIR      # writes the five PNGs
"""
import os
import struct
import sys
import zlib

import numpy as np


def write_png(path, rgba):
    """rgba: uint8 array (h, w, 4), row 0 = top row. Plain PNG, no colour chunks (sRGB by default)."""
    h, w, _ = rgba.shape
    raw = b"".join(b"\x00" + rgba[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def rgba(h, w, colour, alpha=255):
    img = np.zeros((h, w, 4), np.uint8)
    img[..., :3] = colour
    img[..., 3] = alpha
    return img


def checker():
    """64x64, 8x8 cells of 8 px in two colours, a 2-px dark frame: fully opaque."""
    img = rgba(64, 64, (230, 220, 40))
    y, x = np.mgrid[0:64, 0:64]
    dark = ((x // 8) + (y // 8)) % 2 == 1
    img[dark, :3] = (30, 60, 170)
    frame = (x < 2) | (x >= 62) | (y < 2) | (y >= 62)
    img[frame, :3] = (15, 15, 15)
    return img


GLYPHS = {
    # 5x7 bitmaps of "D", "E", "C", "A", "L": text-like detail with sharp, thin strokes
    "D": ["1110.", "1..1.", "1...1", "1...1", "1...1", "1..1.", "1110."],
    "E": ["11111", "1....", "1....", "1111.", "1....", "1....", "11111"],
    "C": [".1111", "1....", "1....", "1....", "1....", "1....", ".1111"],
    "A": [".111.", "1...1", "1...1", "11111", "1...1", "1...1", "1...1"],
    "L": ["1....", "1....", "1....", "1....", "1....", "1....", "11111"],
}


def glyphs():
    """48x32: 'DEC' over 'AL' in 5x7 glyphs of 2-px cells, white on a red plate with transparent
    corners; the letters are opaque white, the plate opaque red, outside the plate transparent."""
    h, w = 32, 48
    img = rgba(h, w, (0, 0, 0), 0)
    img[2:30, 1:47, :3] = (200, 30, 25)
    img[2:30, 1:47, 3] = 255
    for text, y0 in (("DEC", 3), ("AL", 17)):
        x0 = 3 if len(text) == 3 else 11
        for k, ch in enumerate(text):
            rows = GLYPHS[ch]
            for gy, row in enumerate(rows):
                for gx, c in enumerate(row):
                    if c == "1":
                        yy, xx = y0 + 2 * gy, x0 + k * 14 + 2 * gx
                        img[yy:yy + 2, xx:xx + 2, :3] = 250
    # cut the plate's corners (alpha edges that are not axis-aligned lines)
    y, x = np.mgrid[0:h, 0:w]
    corner = np.minimum(np.minimum(x - 1, 46 - x), np.minimum(y - 2, 29 - y))
    cut = (np.minimum(x - 1, 46 - x) + np.minimum(y - 2, 29 - y)) < 3
    img[cut & (corner >= 0), 3] = 0
    return img


def ring():
    """128x128: two concentric rings (cyan outer, magenta inner) and a centre dot, transparent
    elsewhere; radii in texels, tested at texel centres."""
    n = 128
    y, x = np.mgrid[0:n, 0:n]
    r = np.hypot(x + 0.5 - n / 2, y + 0.5 - n / 2)
    img = rgba(n, n, (0, 0, 0), 0)
    outer = (r >= 48) & (r <= 60)
    inner = (r >= 26) & (r <= 34)
    dot = r <= 9
    img[outer] = (20, 200, 210, 255)
    img[inner] = (220, 40, 200, 255)
    img[dot] = (250, 250, 250, 255)
    return img


def stripes():
    """32x32: diagonal stripes 4 texels wide, opaque pale pink / transparent."""
    y, x = np.mgrid[0:32, 0:32]
    img = rgba(32, 32, (250, 205, 230), 0)
    img[((x + y) // 4) % 2 == 0, 3] = 255
    return img


def splat():
    """96x96: an eight-armed star burst (orange) with a dark core, transparent elsewhere."""
    n = 96
    y, x = np.mgrid[0:n, 0:n]
    dx, dy = x + 0.5 - n / 2, n / 2 - (y + 0.5)
    r = np.hypot(dx, dy)
    a = np.arctan2(dy, dx)
    reach = 18 + 26 * np.abs(np.cos(4 * a)) ** 3
    img = rgba(n, n, (0, 0, 0), 0)
    img[r <= reach] = (240, 120, 20, 255)
    img[r <= 11] = (60, 20, 10, 255)
    return img


TEXTURES = {
    "decal_checker.png": checker,
    "decal_glyphs.png": glyphs,
    "decal_ring.png": ring,
    "decal_stripes.png": stripes,
    "decal_splat.png": splat,
}


def write_all(folder):
    os.makedirs(folder, exist_ok=True)
    for name, make in TEXTURES.items():
        write_png(os.path.join(folder, name), make())


if __name__ == "__main__":
    write_all(sys.argv[1])
