#!/usr/bin/env python3
"""Writes the small decal textures of data/sample/textures/ (standard library only).

Each texture is an 8-bit RGBA PNG with sRGB-encoded colour and straight (unassociated) alpha,
the convention decalcomp expects of 8-bit decal textures (docs/conventions.md). The images are
drawn analytically with a little supersampling, so running the script again gives identical files.

    python3 tools/make_sample_textures.py [OUTPUT_DIR]   # default: data/sample/textures
"""
import math
import os
import struct
import sys
import zlib

SUPERSAMPLE = 4  # per axis, for anti-aliased edges


def write_png(path, width, height, pixels):
    """pixels: rows top to bottom, each a list of (r, g, b, a) tuples of ints in 0..255."""
    raw = bytearray()
    for row in pixels:
        raw.append(0)  # filter type None
        for r, g, b, a in row:
            raw += bytes((r, g, b, a))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))  # 8-bit RGBA
    png += chunk(b"sRGB", bytes((0,)))  # perceptual rendering intent: the colour is sRGB-encoded
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def linear_to_srgb(c):
    c = min(max(c, 0.0), 1.0)
    return c * 12.92 if c <= 0.0031308 else 1.055 * c ** (1.0 / 2.4) - 0.055


def render(width, height, shader):
    """shader(u, v) -> (r, g, b, a): linear colour, straight alpha; u right, v down, both in [0,1].

    Supersamples with premultiplied averaging, then un-premultiplies, so edge texels keep the
    colour of what covers them rather than fading towards black."""
    rows = []
    n = SUPERSAMPLE
    for j in range(height):
        row = []
        for i in range(width):
            acc = [0.0, 0.0, 0.0, 0.0]
            for sj in range(n):
                for si in range(n):
                    u = (i + (si + 0.5) / n) / width
                    v = (j + (sj + 0.5) / n) / height
                    r, g, b, a = shader(u, v)
                    acc[0] += r * a
                    acc[1] += g * a
                    acc[2] += b * a
                    acc[3] += a
            a = acc[3] / (n * n)
            rgb = [c / acc[3] if acc[3] > 0 else 0.0 for c in acc[:3]]
            row.append(tuple(round(linear_to_srgb(c) * 255) for c in rgb) + (round(min(max(a, 0.0), 1.0) * 255),))
        rows.append(row)
    return rows


def smoothstep(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3 - 2 * t)


def scorch(u, v):
    """A burnt ring: dark sooty centre, a bright ember ring, ragged outer falloff."""
    x, y = 2 * u - 1, 2 * v - 1
    r = math.hypot(x, y)
    angle = math.atan2(y, x)
    ragged = 0.06 * math.sin(7 * angle) + 0.04 * math.sin(13 * angle + 1.3) + 0.03 * math.sin(29 * angle + 0.4)
    outer = 1.0 - smoothstep(0.62 + ragged, 0.95 + ragged, r)
    ember = math.exp(-((r - 0.45) / 0.07) ** 2)
    soot = 0.02
    colour = (soot + 0.9 * ember, soot + 0.25 * ember, soot + 0.03 * ember)
    return colour + (min(1.0, 0.92 * outer + 0.3 * ember),)


def stripes(u, v):
    """A hazard-stripe sign with a dark frame and a white bar at the top (shows which way is up)."""
    frame = 0.07
    w, h = 2.0, 1.0  # the image is twice as wide as high; work in a 2:1 box
    x, y = u * w, v * h
    inside_frame = frame < x < w - frame and frame < y < h - frame
    if not inside_frame:
        return (0.03, 0.03, 0.03, 1.0)
    if y < 0.28:  # top bar
        return (0.9, 0.9, 0.9, 1.0)
    band = math.floor((x + y) / 0.22) % 2
    return (0.95, 0.62, 0.02, 1.0) if band == 0 else (0.05, 0.05, 0.05, 1.0)


def splat(u, v):
    """A paint splat: a lumpy blob with a few droplets, saturated green, hard-ish edges."""
    x, y = 2 * u - 1, 2 * v - 1
    r = math.hypot(x, y)
    angle = math.atan2(y, x)
    radius = 0.55 + 0.12 * math.sin(5 * angle + 0.7) + 0.07 * math.sin(9 * angle + 2.1) + 0.05 * math.sin(17 * angle)
    alpha = 1.0 - smoothstep(radius - 0.03, radius + 0.03, r)
    for dx, dy, dr in ((0.72, -0.55, 0.09), (-0.78, 0.35, 0.07), (0.15, 0.84, 0.06), (-0.5, -0.75, 0.05)):
        d = math.hypot(x - dx, y - dy)
        alpha = max(alpha, 1.0 - smoothstep(dr - 0.02, dr + 0.02, d))
    shade = 0.8 + 0.2 * (1.0 - r)
    return (0.05 * shade, 0.55 * shade, 0.12 * shade, alpha)


def arrow(u, v):
    """An upward arrow on a light disc: makes the texture's orientation obvious (top = t 0)."""
    x, y = 2 * u - 1, 2 * v - 1  # y grows downwards
    disc = 1.0 - smoothstep(0.9, 0.96, math.hypot(x, y))
    head = y < -0.05 and abs(x) < (y + 0.7) * 0.85 and y > -0.7
    shaft = -0.1 <= y < 0.62 and abs(x) < 0.16
    if head or shaft:
        return (0.7, 0.03, 0.03, disc)
    return (0.92, 0.92, 0.88, disc * 0.85)


TEXTURES = [
    ("scorch.png", 128, 128, scorch),
    ("stripes.png", 128, 64, stripes),
    ("splat.png", 96, 96, splat),
    ("arrow.png", 64, 64, arrow),
]


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "sample", "textures")
    os.makedirs(out_dir, exist_ok=True)
    for name, width, height, shader in TEXTURES:
        path = os.path.join(out_dir, name)
        write_png(path, width, height, render(width, height, shader))
        print(f"{os.path.normpath(path)}: {width}x{height}")


if __name__ == "__main__":
    main()
