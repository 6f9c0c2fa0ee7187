"""A second deforming sequence for texture-space decals (issue 11), built from scratch in Blender.

    nice blender -b --factory-startup --python tools/blender/deform_sequence.py -- \
        --out data/blender-deform-own

Scene: a ball (a UV sphere built triangle by triangle, flat-shaded, a box-projection UV layout of our own: 6
non-overlapping islands with seams between them, see box_unwrap) that is
twisted, squashed and rippled over the frames (Simple Deform TWIST, Simple Deform STRETCH and a
Wave modifier, after a Geometry Nodes modifier that stores the REST position in the point
attribute 'rest_position'), a twin ball sharing the mesh and its UVs (another pass index, no decal,
deformed the same way), a floor, a sun and a static camera. Two box decals are placed in the ball's
REST pose (matrix: decal local -> rest-pose object space); both cross UV island borders.

The truth puts the decals into the ball's material with Blender's own nodes: the Attribute node
reads rest_position, the decal's inverse matrix (dot products) gives local (x, y, z), inside iff
|x|, |y|, |z| < 0.5, image vector (x + 0.5, y + 0.5) (= s = x + 0.5, t = 0.5 - y with t = 0 at the
image's top row, Blender's v bottom-up), Image Texture Closest + Clip on an sRGB PNG with straight
alpha, mixed "over" the base colour (MixRGB Mix, factor = inside * alpha), shader AOVs DecalMask
(inside), DecalCoverage (blend factor) and RestPosition.

Every frame is rendered twice with Cycles (1 spp, seed 0, Blackman-Harris 0.01 px so the passes are
unfiltered): gbuffer.NNNN.exr without the decals, truth.NNNN.exr with them. Blender's multilayer
EXRs are cut to channel subsets with OpenImageIO (values bit for bit, float32, ZIP), and the
attributes that change from run to run (Date, render times) are dropped. A second run gives the
same pixels (sequence.json records their sha256) and the same text files; the EXR bytes differ
only in the DateTime attribute that OpenImageIO's writer adds. Smooth shading and a Wave along the
normals were left out for that reason: Blender sums vertex normals in threads and their last bits
changed from run to run.

Written to --out: gbuffer.NNNN.exr, truth.NNNN.exr, mesh_rest.obj, camera.json, decal_label.png,
decal_badge.png, scene.json (decalcomp, space object_rest), scene_world.json (the same boxes as
world decals at the rest pose: the negative control), sequence.json (frames, deformation
parameters, per-frame checks).

Check it independently of decalcomp with tools/blender/deform_check.py (numpy).
"""

import argparse
import json
import math
import os
import shutil
import struct
import sys
import tempfile
import zlib

import bpy
import numpy as np
from mathutils import Matrix, Vector

RES = (320, 240)
VIEW_LAYER = "ViewLayer"
BALL_RADIUS = 0.8
BALL_INDEX, TWIN_INDEX, FLOOR_INDEX = 2, 3, 1

# Per frame: Simple Deform TWIST angle (deg, about the ball's Z), Simple Deform STRETCH factor
# (negative squashes towards z = 0, the ball's base), Wave height (along normals) and wave time.
FRAMES = {
    1: {"twist_deg": 0.0, "stretch": 0.0, "wave_height": 0.0},
    2: {"twist_deg": 40.0, "stretch": -0.10, "wave_height": 0.03},
    3: {"twist_deg": 80.0, "stretch": -0.22, "wave_height": 0.05},
    4: {"twist_deg": 110.0, "stretch": -0.12, "wave_height": 0.04},
    5: {"twist_deg": -60.0, "stretch": 0.12, "wave_height": 0.03},
}

# Decals in the ball's rest object space: centre on the sphere at (azimuth, elevation), box axes
# X = horizontal tangent, Y = up tangent, Z = outward normal (the texture is projected along -Z),
# rolled about Z; size (width, height, depth). The ball's centre is at (0, 0, BALL_RADIUS).
DECALS = [
    {"name": "ball_label", "texture": "decal_label.png", "azimuth_deg": -35.0, "elevation_deg": 28.0,
     "roll_deg": 15.0, "size": [0.95, 0.55, 0.7]},
    {"name": "ball_badge", "texture": "decal_badge.png", "azimuth_deg": 10.0, "elevation_deg": -30.0,
     "roll_deg": -25.0, "size": [0.45, 0.45, 0.5]},
]


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="deform_sequence.py")
    p.add_argument("--out", required=True, help="output folder (created)")
    p.add_argument("--frames", default="", help="comma-separated subset of frames (default all)")
    p.add_argument("--threads", type=int, default=2)
    return p.parse_args(argv)


# ---------------------------------------------------------------------------------------------
# Decal textures: written here, byte for byte (PNG RGBA8, straight alpha, sRGB-encoded RGB).
# Alpha is 0 or 255 only and every texture has a transparent border of at least 2 texels, so a
# point on the box's side faces or a texel edge never decides a visible colour by float rounding.


def write_png(path, rgba):
    h, w, _ = rgba.shape
    raw = b"".join(b"\x00" + rgba[j].astype(np.uint8).tobytes() for j in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    png += chunk(b"sRGB", b"\x00") + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def label_texture():
    """64 x 32: a yellow plate with a dark 'F' glyph and a red corner block (mirrors and flips show)."""
    w, h = 64, 32
    img = np.zeros((h, w, 4), np.int32)
    img[2:h - 2, 2:w - 2] = (235, 190, 30, 255)
    glyph = ["XXXX..",
             "X.....",
             "XXX...",
             "X.....",
             "X....."]
    for r, row in enumerate(glyph):  # 4x4-texel cells, top-left at (6, 6)
        for c, ch in enumerate(row):
            if ch == "X":
                img[6 + 4 * r:10 + 4 * r, 6 + 4 * c:10 + 4 * c, :3] = (20, 30, 90)
    img[6:14, 44:58, :3] = (200, 25, 25)  # top-right block
    img[18:26, 36:58, :3] = (25, 140, 60)  # lower-right bar
    return img


def badge_texture():
    """32 x 32: white and blue rings with an off-centre magenta dot; a cut-out notch at the bottom."""
    w = h = 32
    img = np.zeros((h, w, 4), np.int32)
    for j in range(2, h - 2):
        for i in range(2, w - 2):
            ring = max(abs(i - 15.5), abs(j - 15.5)) // 4
            img[j, i] = (245, 245, 245, 255) if ring % 2 == 0 else (30, 80, 220, 255)
    img[6:12, 8:14, :3] = (220, 20, 200)
    img[24:30, 14:18, 3] = 0  # transparent notch
    return img


# ---------------------------------------------------------------------------------------------
# Scene


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras, bpy.data.images,
                 bpy.data.node_groups):
        for block in list(coll):
            coll.remove(block)


def make_ball_mesh(segments=40, rings=20):
    """A UV-sphere-like ball of triangles built vertex by vertex (bmesh.ops.triangulate started its
    triangles on another corner from run to run), base at z = 0 (the twist and squash origin)."""
    verts = [(0.0, 0.0, 0.0)]
    for k in range(1, rings):
        theta = math.pi * k / rings  # from the bottom pole
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            verts.append((BALL_RADIUS * math.sin(theta) * math.cos(phi), BALL_RADIUS * math.sin(theta) * math.sin(phi),
                          BALL_RADIUS * (1.0 - math.cos(theta))))
    verts.append((0.0, 0.0, 2.0 * BALL_RADIUS))
    top = len(verts) - 1

    def ring(k, j):
        return 1 + (k - 1) * segments + j % segments

    faces = []
    for j in range(segments):
        faces.append((0, ring(1, j + 1), ring(1, j)))
        for k in range(1, rings - 1):
            a, b, c, d = ring(k, j), ring(k, j + 1), ring(k + 1, j + 1), ring(k + 1, j)
            faces += [(a, b, c), (a, c, d)]
        faces.append((ring(rings - 1, j), ring(rings - 1, j + 1), top))
    centre = Vector((0, 0, BALL_RADIUS))
    oriented = []
    for f in faces:  # counter-clockwise seen from outside
        a, b, c = (Vector(verts[i]) for i in f)
        outward = (b - a).cross(c - a).dot((a + b + c) / 3 - centre) > 0
        oriented.append(f if outward else (f[0], f[2], f[1]))
    me = bpy.data.meshes.new("Blob")
    me.from_pydata(verts, [], oriented)
    me.update()
    ob = bpy.data.objects.new("Blob", me)
    bpy.context.scene.collection.objects.link(ob)
    box_unwrap(me)
    # Flat shading: Cycles' normals are then the triangles' own; smooth vertex normals are summed in
    # threads by Blender and differ in the last bit from run to run (the files would not repeat).
    for poly in me.polygons:
        poly.use_smooth = False
    ob.name = me.name = "Blob"
    return ob


def box_unwrap(me, margin=0.025):
    """UV map 'UVMap': each triangle goes to the axis its rest normal is closest to (+X, -X, +Y, -Y,
    +Z, -Z), the connected regions of each axis become islands, projected orthographically along
    their axis (one-to-one: every normal of an island is within 55 degrees of it) with one common
    scale, and shelf-packed into [0, 1]^2 with `margin` between islands. Deterministic: a first
    version used bpy.ops.uv.smart_project on a bmesh-triangulated sphere and its islands changed
    from run to run (the triangulation's corner order did too; which of the two caused it was not
    pinned down)."""
    co = np.array([v.co for v in me.vertices], np.float64)
    tris = [tuple(p.vertices) for p in me.polygons]
    axis_of = []
    for t in tris:
        a, b, c = co[list(t)]
        n = np.cross(b - a, c - a)
        k = int(np.argmax(np.abs(n)))
        axis_of.append(2 * k + (0 if n[k] > 0 else 1))
    # islands: triangles of one axis sharing an edge
    parent = list(range(len(tris)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    edges = {}
    for i, t in enumerate(tris):
        for k in range(3):
            e = (min(t[k], t[(k + 1) % 3]), max(t[k], t[(k + 1) % 3]))
            edges.setdefault(e, []).append(i)
    for faces in edges.values():
        if len(faces) == 2 and axis_of[faces[0]] == axis_of[faces[1]]:
            ra, rb = find(faces[0]), find(faces[1])
            parent[max(ra, rb)] = min(ra, rb)
    islands = {}
    for i in range(len(tris)):
        islands.setdefault(find(i), []).append(i)
    # (u, v) per axis, right-handed seen from outside: u to the right, v up
    project = {0: lambda p: (p[1], p[2]), 1: lambda p: (-p[1], p[2]), 2: lambda p: (-p[0], p[2]),
               3: lambda p: (p[0], p[2]), 4: lambda p: (p[0], p[1]), 5: lambda p: (p[0], -p[1])}
    shapes = []
    for root in sorted(islands):
        faces = islands[root]
        f = project[axis_of[faces[0]]]
        uv = {vi: np.array(f(co[vi])) for i in faces for vi in tris[i]}
        lo = np.min(list(uv.values()), axis=0)
        hi = np.max(list(uv.values()), axis=0)
        shapes.append((faces, {vi: q - lo for vi, q in uv.items()}, hi - lo))
    order = sorted(range(len(shapes)), key=lambda i: (-shapes[i][2][1], i))

    def pack(scale):
        x = y = margin
        shelf = 0.0
        place = {}
        for i in order:
            w, h = shapes[i][2] * scale
            if x + w + margin > 1.0:
                x, y, shelf = margin, y + shelf + margin, 0.0
            place[i] = (x, y)
            x += w + margin
            shelf = max(shelf, h)
        return place if y + shelf + margin <= 1.0 else None

    lo_s, hi_s = 0.0, 1.0
    for _ in range(40):  # the largest common scale that fits
        mid = 0.5 * (lo_s + hi_s)
        lo_s, hi_s = (mid, hi_s) if pack(mid) else (lo_s, mid)
    place = pack(lo_s)
    for uv in list(me.uv_layers):
        me.uv_layers.remove(uv)
    layer = me.uv_layers.new(name="UVMap")
    for i, (faces, uv, _) in enumerate(shapes):
        ox, oy = place[i]
        for fi in faces:
            p = me.polygons[fi]
            for loop in range(p.loop_start, p.loop_start + p.loop_total):
                q = uv[me.loops[loop].vertex_index] * lo_s
                layer.data[loop].uv = (ox + q[0], oy + q[1])
    return len(shapes)


def store_rest_node_group():
    ng = bpy.data.node_groups.new("StoreRestPosition", "GeometryNodeTree")
    ng.inputs.new("NodeSocketGeometry", "Geometry")
    ng.outputs.new("NodeSocketGeometry", "Geometry")
    gin = ng.nodes.new("NodeGroupInput")
    gout = ng.nodes.new("NodeGroupOutput")
    store = ng.nodes.new("GeometryNodeStoreNamedAttribute")
    store.data_type = "FLOAT_VECTOR"
    store.domain = "POINT"
    store.inputs["Name"].default_value = "rest_position"
    pos = ng.nodes.new("GeometryNodeInputPosition")
    value = next(s for s in store.inputs if s.name == "Value" and s.type == "VECTOR")
    ng.links.new(gin.outputs["Geometry"], store.inputs["Geometry"])
    ng.links.new(pos.outputs["Position"], value)
    ng.links.new(store.outputs["Geometry"], gout.inputs["Geometry"])
    return ng


def add_deformers(ob, rest_group):
    gn = ob.modifiers.new("StoreRest", "NODES")
    gn.node_group = rest_group
    tw = ob.modifiers.new("Twist", "SIMPLE_DEFORM")
    tw.deform_method = "TWIST"
    tw.deform_axis = "Z"
    st = ob.modifiers.new("Squash", "SIMPLE_DEFORM")
    st.deform_method = "STRETCH"
    st.deform_axis = "Z"
    wv = ob.modifiers.new("Ripple", "WAVE")
    wv.use_normal = False  # along the object's Z: per vertex, no dependence on normals summed in threads
    wv.use_x = wv.use_y = True
    wv.width = 0.35
    wv.narrowness = 1.5
    wv.speed = 0.12
    wv.start_position_x = 0.3
    wv.start_position_y = -0.2
    wv.time_offset = 0.0


def set_frame_deformation(ob, params):
    ob.modifiers["Twist"].angle = math.radians(params["twist_deg"])
    ob.modifiers["Squash"].factor = params["stretch"]
    ob.modifiers["Ripple"].height = params["wave_height"]


def decal_matrix(d):
    az, el, roll = (math.radians(d[k]) for k in ("azimuth_deg", "elevation_deg", "roll_deg"))
    n = Vector((math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)))
    centre = Vector((0, 0, BALL_RADIUS)) + BALL_RADIUS * n
    x = Vector((0, 0, 1)).cross(n).normalized()
    y = n.cross(x).normalized()
    c, s = math.cos(roll), math.sin(roll)
    x, y = c * x + s * y, -s * x + c * y
    w, h, depth = d["size"]
    m = Matrix.Identity(4)
    for r in range(3):
        m[r][0], m[r][1], m[r][2], m[r][3] = x[r] * w, y[r] * h, n[r] * depth, centre[r]
    return m


def node(nodes, kind, **props):
    n = nodes.new(kind)
    for k, v in props.items():
        setattr(n, k, v)
    return n


def math_node(nodes, links, op, a, b=None):
    n = node(nodes, "ShaderNodeMath", operation=op)
    for i, v in enumerate((a, b)):
        if v is None:
            continue
        if isinstance(v, (int, float)):
            n.inputs[i].default_value = v
        else:
            links.new(v, n.inputs[i])
    return n.outputs[0]


def ball_material(decals, images):
    mat = bpy.data.materials.new("M_Blob")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = node(nodes, "ShaderNodeOutputMaterial")
    bsdf = node(nodes, "ShaderNodeBsdfDiffuse")
    links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    rest = node(nodes, "ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name="rest_position")
    # Base colour: a checker on the rest position (it moves with the surface, like the decals).
    checker = node(nodes, "ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 3.0
    checker.inputs["Color1"].default_value = (0.18, 0.32, 0.55, 1)
    checker.inputs["Color2"].default_value = (0.30, 0.52, 0.38, 1)
    links.new(rest.outputs["Vector"], checker.inputs["Vector"])
    colour = checker.outputs["Color"]
    decal_on = node(nodes, "ShaderNodeValue", name="DecalOn", label="DecalOn")
    decal_on.outputs[0].default_value = 1.0
    mask = coverage = None
    for d, img in zip(decals, images):
        inv = d["matrix_blender"].inverted()
        local = []
        for r in range(3):
            dot = node(nodes, "ShaderNodeVectorMath", operation="DOT_PRODUCT")
            dot.inputs[1].default_value = (inv[r][0], inv[r][1], inv[r][2])
            links.new(rest.outputs["Vector"], dot.inputs[0])
            local.append(math_node(nodes, links, "ADD", dot.outputs["Value"], inv[r][3]))
        absmax = math_node(nodes, links, "MAXIMUM", math_node(nodes, links, "ABSOLUTE", local[0]),
                           math_node(nodes, links, "ABSOLUTE", local[1]))
        absmax = math_node(nodes, links, "MAXIMUM", absmax, math_node(nodes, links, "ABSOLUTE", local[2]))
        inside = math_node(nodes, links, "LESS_THAN", absmax, 0.5)
        uvw = node(nodes, "ShaderNodeCombineXYZ")
        links.new(math_node(nodes, links, "ADD", local[0], 0.5), uvw.inputs[0])
        links.new(math_node(nodes, links, "ADD", local[1], 0.5), uvw.inputs[1])
        tex = node(nodes, "ShaderNodeTexImage", interpolation="Closest", extension="CLIP", image=img)
        links.new(uvw.outputs["Vector"], tex.inputs["Vector"])
        fac = math_node(nodes, links, "MULTIPLY", inside, tex.outputs["Alpha"])
        fac = math_node(nodes, links, "MULTIPLY", fac, decal_on.outputs[0])
        mix = node(nodes, "ShaderNodeMixRGB", blend_type="MIX", use_clamp=False)
        links.new(fac, mix.inputs["Fac"])
        links.new(colour, mix.inputs["Color1"])
        links.new(tex.outputs["Color"], mix.inputs["Color2"])
        colour = mix.outputs["Color"]
        mask = inside if mask is None else math_node(nodes, links, "MAXIMUM", mask, inside)
        coverage = fac if coverage is None else math_node(nodes, links, "MAXIMUM", coverage, fac)
    links.new(colour, bsdf.inputs["Color"])
    for name, socket, kind in (("DecalMask", mask, "Value"), ("DecalCoverage", coverage, "Value"),
                               ("RestPosition", rest.outputs["Vector"], "Color")):
        aov = nodes.new("ShaderNodeOutputAOV")
        aov.name = name  # ShaderNodeOutputAOV.name is the AOV's name in Blender 3.4
        links.new(socket, aov.inputs[kind])
    return mat


def flat_material(name, rgb):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = node(nodes, "ShaderNodeOutputMaterial")
    bsdf = node(nodes, "ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*rgb, 1)
    mat.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def build_scene(out_dir):
    clear_scene()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = min(FRAMES), max(FRAMES)

    images = []
    for d, make in zip(DECALS, (label_texture, badge_texture)):
        path = os.path.join(out_dir, d["texture"])
        write_png(path, make())
        img = bpy.data.images.load(path)
        img.colorspace_settings.name = "sRGB"
        img.alpha_mode = "STRAIGHT"
        images.append(img)

    ball = make_ball_mesh()
    ball.location = (0.05, 0.1, 0.0)  # object space is not world space (rotated 25 degrees about Z)
    ball.rotation_euler = (0.0, 0.0, math.radians(25.0))
    ball.pass_index = BALL_INDEX
    add_deformers(ball, store_rest_node_group())
    for d in DECALS:
        d["matrix_blender"] = decal_matrix(d)
    ball.data.materials.append(ball_material(DECALS, images))

    twin = ball.copy()  # shares the mesh (same UVs); its own copy of the modifiers
    twin.name = "BlobTwin"
    twin.location = (1.95, 0.9, 0.0)
    twin.rotation_euler = (0, 0, math.radians(35))
    twin.scale = (0.8, 0.8, 0.8)
    twin.pass_index = TWIN_INDEX
    scene.collection.objects.link(twin)
    twin.material_slots[0].link = "OBJECT"
    twin.material_slots[0].material = flat_material("M_Twin", (0.55, 0.35, 0.25))

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0.6, 1.0, 0.0))
    floor = bpy.context.active_object
    floor.name = floor.data.name = "Floor"
    floor.pass_index = FLOOR_INDEX
    floor.data.materials.append(flat_material("M_Floor", (0.45, 0.45, 0.42)))

    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = 3.0
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
    scene.collection.objects.link(sun)

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 35.0
    cam_data.sensor_width, cam_data.sensor_height, cam_data.sensor_fit = 36.0, 24.0, "AUTO"
    cam_data.clip_start, cam_data.clip_end = 0.1, 100.0
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (0.45, -3.2, 1.55)
    target = Vector((0.7, 0.35, 0.72))
    cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = RES[0], RES[1], 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_motion_blur = False
    r.film_transparent = False
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    c = scene.cycles
    c.device = "CPU"
    c.samples = 1
    c.seed = 0
    c.use_animated_seed = False
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.pixel_filter_type = "BLACKMAN_HARRIS"
    c.filter_width = 0.01
    c.max_bounces = 2
    vl = scene.view_layers[0]
    vl.name = VIEW_LAYER
    for p in ("use_pass_combined", "use_pass_z", "use_pass_normal", "use_pass_position", "use_pass_uv",
              "use_pass_object_index", "use_pass_diffuse_color", "use_pass_cryptomatte_object",
              "use_pass_cryptomatte_material"):
        setattr(vl, p, True)
    vl.pass_cryptomatte_depth = 6
    for name, kind in (("DecalMask", "VALUE"), ("DecalCoverage", "VALUE"), ("RestPosition", "COLOR")):
        aov = vl.aovs.add()
        aov.name, aov.type = name, kind
    return scene, ball, twin, cam


# ---------------------------------------------------------------------------------------------
# Files


def rows(m):
    return [[float(m[r][c]) for c in range(4)] for r in range(4)]


def write_obj(path, ob):
    """The rest mesh (mesh data before modifiers, object space) with the UV map the UV pass shows."""
    me = ob.data
    me.calc_loop_triangles()
    uv = me.uv_layers["UVMap"].data
    vts, vt_index, faces = [], {}, []
    for tri in me.loop_triangles:
        corner = []
        for loop in tri.loops:
            key = tuple(np.float32(uv[loop].uv))
            if key not in vt_index:
                vt_index[key] = len(vts)
                vts.append(key)
            corner.append((me.loops[loop].vertex_index + 1, vt_index[key] + 1))
        faces.append(corner)
    lo = [min(v.co[i] for v in me.vertices) for i in range(3)]
    hi = [max(v.co[i] for v in me.vertices) for i in range(3)]
    with open(path, "w") as f:
        f.write(f"# mesh_rest.obj - object '{ob.name}' in its REST pose: the mesh data before modifiers, in OBJECT\n"
                "# space (world = object_to_world in sequence.json @ [v, 1]). Triangles = Blender's loop triangles\n"
                "# (the mesh is triangulated, the deformers keep them). vt = UV map 'UVMap' (box_unwrap islands):\n"
                "# u to the right, v UP (Blender / OpenGL) - the same numbers as the UV pass (ViewLayer.UV.U/V).\n"
                f"# rest bounding box min {lo} max {hi}\n"
                "# written by tools/blender/deform_sequence.py\n")
        f.write(f"o {ob.name}\n")
        for v in me.vertices:
            f.write("v %.9g %.9g %.9g\n" % tuple(float(np.float32(c)) for c in v.co))
        for u, v in vts:
            f.write("vt %.9g %.9g\n" % (float(u), float(v)))
        for corner in faces:
            f.write("f " + " ".join(f"{a}/{b}" for a, b in corner) + "\n")
    return len(faces), len(me.vertices)


def uv_islands(me):
    """Island id per polygon: polygons joined by an edge whose two corners share UVs on both sides."""
    uv = me.uv_layers["UVMap"].data
    parent = list(range(len(me.polygons)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    edge_sides = {}
    for p in me.polygons:
        n = p.loop_total
        for k in range(n):
            l0, l1 = p.loop_start + k, p.loop_start + (k + 1) % n
            v0, v1 = me.loops[l0].vertex_index, me.loops[l1].vertex_index
            key = (min(v0, v1), max(v0, v1))
            uvs = {v0: tuple(uv[l0].uv), v1: tuple(uv[l1].uv)}
            edge_sides.setdefault(key, []).append((p.index, uvs))
    for sides in edge_sides.values():
        if len(sides) == 2 and sides[0][1] == sides[1][1]:
            parent[find(sides[0][0])] = find(sides[1][0])
    return [find(p.index) for p in me.polygons]


def decal_islands(me, islands, m):
    """The UV islands whose triangles have a corner inside the decal box (rest pose)."""
    inv = m.inverted()
    found = set()
    for p in me.polygons:
        for vi in p.vertices:
            local = inv @ me.vertices[vi].co
            if max(abs(local.x), abs(local.y), abs(local.z)) < 0.5:
                found.add(islands[p.index])
    return len(found)


def camera_json(scene, cam, depsgraph):
    W, H = RES
    cd = cam.data
    c2w = np.array(cam.matrix_world, dtype=np.float64)
    w2c = np.linalg.inv(c2w)
    fit = "HORIZONTAL" if (cd.sensor_fit == "AUTO" and W >= H) or cd.sensor_fit == "HORIZONTAL" else "VERTICAL"
    sensor = cd.sensor_height if cd.sensor_fit == "VERTICAL" else cd.sensor_width  # AUTO: the width
    near, far = cd.clip_start, cd.clip_end
    viewfac = W if fit == "HORIZONTAL" else H
    pixsize = sensor * near / cd.lens / viewfac
    left, right = -0.5 * W * pixsize + cd.shift_x * viewfac * pixsize, 0.5 * W * pixsize + cd.shift_x * viewfac * pixsize
    bottom, top = -0.5 * H * pixsize + cd.shift_y * viewfac * pixsize, 0.5 * H * pixsize + cd.shift_y * viewfac * pixsize
    proj = np.array([[2 * near / (right - left), 0, (right + left) / (right - left), 0],
                     [0, 2 * near / (top - bottom), (top + bottom) / (top - bottom), 0],
                     [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
                     [0, 0, -1, 0]])
    blender_proj = np.array(cam.calc_matrix_camera(depsgraph, x=W, y=H), dtype=np.float64)
    fx = near / pixsize  # pixels per unit of x_cam / -z_cam
    return {
        "description": "Blender 3.4.1 Cycles camera for every frame of this sequence (static): gbuffer.NNNN.exr / truth.NNNN.exr",
        "resolution": [W, H],
        "pixel_aspect": [1.0, 1.0],
        "matrix_layout": "row-major nested lists M[row][col]; matrices act on COLUMN vectors: p_out = M @ [x, y, z, 1]^T (translation in the last column, M[0..2][3]). Transpose before passing to APIs that expect column-major storage.",
        "world_space": "Blender world: right-handed, +Z up",
        "camera_space": "right-handed; camera looks along its local -Z, +Y is up, +X is right (OpenGL convention); visible points have z_cam < 0",
        "world_to_camera": w2c.tolist(),
        "camera_to_world": c2w.tolist(),
        "projection": proj.tolist(),
        "projection_notes": "OpenGL-style clip matrix derived (float64) from sensor/lens/shift/clip exactly like Blender's viewplane; equals Camera.calc_matrix_camera(x=W, y=H) (float32) to max abs diff %.3g. clip = projection @ world_to_camera @ [p,1]; ndc = clip.xyz / clip.w in [-1,1]; ndc.z = -1 at clip_start, +1 at clip_end." % float(np.abs(proj - blender_proj).max()),
        "pixel_convention": "EXR row 0 is the TOP image row. Pixel (col i, row j) has its centre at ndc_x = 2*(i+0.5)/W - 1, ndc_y = 1 - 2*(j+0.5)/H. pixel_x = (ndc_x+1)/2*W, pixel_y_from_top = (1-ndc_y)/2*H.",
        "intrinsics": {
            "type": cd.type, "lens_mm": cd.lens, "sensor_width_mm": cd.sensor_width,
            "sensor_height_mm": cd.sensor_height, "sensor_fit": cd.sensor_fit, "effective_sensor_fit": fit,
            "shift_x": cd.shift_x, "shift_y": cd.shift_y, "clip_start": near, "clip_end": far,
            "viewplane_at_clip_start": {"left": left, "right": right, "bottom": bottom, "top": top},
            "pinhole_pixels": "pixel_x = cx + fx * x_cam / (-z_cam); pixel_y_from_top = cy - fy * y_cam / (-z_cam); pixel centres at integer + 0.5",
            "fx_pixels": fx, "fy_pixels": fx,
            "cx_pixels_from_left": W / 2 - (right + left) / 2 / pixsize,
            "cy_pixels_from_top": H / 2 + (top + bottom) / 2 / pixsize,
            "fov_x_deg_unshifted": math.degrees(2 * math.atan(0.5 * W / fx)),
            "fov_y_deg_unshifted": math.degrees(2 * math.atan(0.5 * H / fx)),
        },
        "camera_position_world": c2w[:3, 3].tolist(),
        "render": {"engine": "CYCLES", "device": "CPU", "samples": scene.cycles.samples, "seed": scene.cycles.seed,
                   "pixel_filter": scene.cycles.pixel_filter_type, "filter_width_px": scene.cycles.filter_width,
                   "denoising": False, "blender_version": bpy.app.version_string},
        "depth": {"pass": "ViewLayer.Depth.Z",
                  "claimed_meaning": "planar: distance along the camera's viewing axis, Depth = -z_cam = -(world_to_camera @ [P,1]).z  (NOT the radial ray length). Background (no hit) pixels hold 1e10."},
    }


def verify_frame(gbuf, cam_doc):
    """Depth convention and projection checks from the frame's own Position and Depth passes."""
    W, H = RES
    w2c = np.array(cam_doc["world_to_camera"])
    proj = np.array(cam_doc["projection"])
    c2w = np.array(cam_doc["camera_to_world"])
    depth = gbuf["ViewLayer.Depth.Z"].astype(np.float64)
    P = np.stack([gbuf["ViewLayer.Position." + c] for c in "XYZ"], -1).astype(np.float64)
    hit = depth < 1e9
    Ph = np.concatenate([P[hit], np.ones((hit.sum(), 1))], 1)
    cam_pts = Ph @ w2c.T
    planar = np.abs(depth[hit] + cam_pts[:, 2])
    radial = np.abs(depth[hit] - np.linalg.norm(P[hit] - c2w[:3, 3], axis=1))
    clip = cam_pts @ proj.T
    ndc = clip[:, :3] / clip[:, 3:4]
    px, py = (ndc[:, 0] + 1) / 2 * W, (1 - ndc[:, 1]) / 2 * H
    jj, ii = np.nonzero(hit)
    pix_err = np.hypot(px - (ii + 0.5), py - (jj + 0.5))
    return {"pixels_hit": int(hit.sum()),
            "verdict": "PLANAR (z-depth along the view axis): Depth = -(world_to_camera @ [P,1]).z"
            if planar.max() < 1e-3 < radial.max() else "NOT PLANAR",
            "planar_max_abs_err": float(planar.max()), "radial_max_abs_err": float(radial.max()),
            "max_pixel_error": float(pix_err.max())}


def read_exr(path):
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT)
    return {name: pixels[:, :, i] for i, name in enumerate(spec.channelnames)}


def subset_exr(src, dst, keep):
    """Copy channels `keep` of Blender's multilayer EXR `src` to `dst` (float32, ZIP, values bit for
    bit), dropping the attributes that differ from run to run."""
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(src)
    names = list(buf.spec().channelnames)
    missing = [c for c in keep if c not in names]
    if missing:
        raise RuntimeError(f"{src}: no channels {missing}")
    order = sorted(keep)
    out = oiio.ImageBufAlgo.channels(buf, tuple(order))
    spec = out.spec()
    for attr in [a.name for a in spec.extra_attribs]:
        if attr in ("DateTime", "Date", "RenderTime") or attr.endswith("_time"):
            spec.erase_attribute(attr)
    spec.attribute("compression", "zip")
    out.set_write_format(oiio.FLOAT)
    if not out.write(dst):
        raise RuntimeError(out.geterror())
    check = read_exr(dst)
    ref = read_exr(src)
    for c in order:
        if check[c].tobytes() != ref[c].tobytes():
            raise RuntimeError(f"{dst}: channel {c} not copied bit for bit")


GBUFFER_LAYERS = ("CryptoMaterial", "CryptoObject", "Depth", "DiffCol", "IndexOB", "Normal", "Position", "UV")
TRUTH_LAYERS = ("DecalCoverage", "DecalMask", "DiffCol", "IndexOB", "RestPosition")


def channels_of(path, layers):
    import OpenImageIO as oiio
    names = oiio.ImageBuf(path).spec().channelnames
    return [n for n in names if n.split(".")[1].rstrip("0123456789") in layers or n.split(".")[1] in layers]


def pixel_digest(path):
    """sha256 of the float32 pixels of every channel (sorted by name): what a second run must repeat
    (the files' bytes differ in the DateTime attribute that OpenImageIO's writer adds)."""
    import hashlib
    planes = read_exr(path)
    h = hashlib.sha256()
    for name in sorted(planes):
        h.update(name.encode() + np.ascontiguousarray(planes[name], np.float32).tobytes())
    return h.hexdigest()


def render(scene, path):
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    out_dir = os.path.abspath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    frames = sorted(FRAMES) if not args.frames else [int(f) for f in args.frames.split(",")]
    scene, ball, twin, cam = build_scene(out_dir)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads

    n_tri, n_vert = write_obj(os.path.join(out_dir, "mesh_rest.obj"), ball)
    islands = uv_islands(ball.data)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam_doc = camera_json(scene, cam, depsgraph)
    obj_to_world = ball.matrix_world.copy()

    scene_doc = {
        "format": "decalcomp-scene/1",
        "description": "Texture-space box decals on the ball 'Blob' of data/blender-deform-own, placed in its REST pose "
                       "(matrix: decal local -> rest-pose object space, as in mesh_rest.obj); written by "
                       "tools/blender/deform_sequence.py.",
        "interpolation": "closest",
        "decals": [],
    }
    world_doc = {
        "format": "decalcomp-scene/1",
        "description": "Negative control: the same boxes used as WORLD decals where they sit at the rest pose "
                       "(object_to_world @ matrix). They stay put while the ball deforms, so they slide off it.",
        "interpolation": "closest",
        "decals": [],
    }
    decal_notes = []
    for d in DECALS:
        m = d["matrix_blender"]
        scene_doc["decals"].append({
            "name": d["name"], "kind": "box", "space": "object_rest", "mesh": "mesh_rest.obj",
            "pass_index": BALL_INDEX, "cryptomatte_object": ball.name, "matrix": rows(m),
            "texture": {"albedo": d["texture"], "alpha": "straight"},
        })
        world_doc["decals"].append({
            "name": d["name"] + "_world", "kind": "box", "matrix": rows(obj_to_world @ m),
            "texture": {"albedo": d["texture"], "alpha": "straight"},
        })
        decal_notes.append({"name": d["name"], "placement": {k: d[k] for k in ("azimuth_deg", "elevation_deg",
                                                                               "roll_deg", "size")},
                            "uv_islands_under_decal": decal_islands(ball.data, islands, m)})
    with open(os.path.join(out_dir, "scene.json"), "w") as f:
        json.dump(scene_doc, f, indent=2)
    with open(os.path.join(out_dir, "scene_world.json"), "w") as f:
        json.dump(world_doc, f, indent=2)

    ball_mat = ball.data.materials[0]
    decal_on = ball_mat.node_tree.nodes["DecalOn"].outputs[0]
    tmp = tempfile.mkdtemp(prefix="deform_sequence_")
    per_frame, verification = {}, {}
    try:
        for f in frames:
            params = FRAMES[f]
            scene.frame_set(f)
            for ob in (ball, twin):
                set_frame_deformation(ob, params)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            depsgraph.update()
            ev = ball.evaluated_get(depsgraph).data
            rest = np.array([v.co for v in ball.data.vertices])
            cur = np.array([v.co for v in ev.vertices])
            attr = ev.attributes.get("rest_position")
            rest_attr = np.array([a.vector for a in attr.data]) if attr else None
            ev.calc_loop_triangles()
            same_tris = [tuple(t.vertices) for t in ev.loop_triangles] == \
                [tuple(t.vertices) for t in ball.data.loop_triangles]
            per_frame[str(f)] = dict(params, **{
                "max_vertex_displacement_from_rest": float(np.linalg.norm(cur - rest, axis=1).max()),
                "loop_triangles_same_as_rest": bool(same_tris),
                "rest_position_attribute_equals_rest_mesh": bool(rest_attr is not None and
                                                                 np.array_equal(rest_attr, rest)),
                "evaluated_uv_maps": [uv.name for uv in ev.uv_layers],
            })
            raw = {}
            for kind, on in (("gbuffer", 0.0), ("truth", 1.0)):
                decal_on.default_value = on
                raw[kind] = os.path.join(tmp, f"{kind}.{f:04d}.exr")
                render(scene, raw[kind])
            g_out = os.path.join(out_dir, f"gbuffer.{f:04d}.exr")
            t_out = os.path.join(out_dir, f"truth.{f:04d}.exr")
            subset_exr(raw["gbuffer"], g_out, channels_of(raw["gbuffer"], GBUFFER_LAYERS))
            subset_exr(raw["truth"], t_out, channels_of(raw["truth"], TRUTH_LAYERS))
            g, t, traw = read_exr(g_out), read_exr(raw["gbuffer"]), read_exr(raw["truth"])
            check = verify_frame(g, cam_doc)
            mask = traw["ViewLayer.DecalMask.X"] > 0.5
            ball_px = g["ViewLayer.IndexOB.X"] == BALL_INDEX
            # Both renders trace the same rays: their geometry passes should agree sample for sample.
            geometry_diff = {c.split(".", 1)[1]: int((traw[c] != t[c]).sum()) for c in
                             ("ViewLayer.Position.X", "ViewLayer.Depth.Z", "ViewLayer.UV.U", "ViewLayer.UV.V",
                              "ViewLayer.IndexOB.X")}
            diffcol_changed = np.zeros_like(mask)
            for c in "RGB":
                diffcol_changed |= traw["ViewLayer.DiffCol." + c] != t["ViewLayer.DiffCol." + c]
            check.update({
                "ball_pixels": int(ball_px.sum()),
                "decal_mask_pixels": int(mask.sum()),
                "decal_mask_outside_ball": int((mask & ~ball_px).sum()),
                "truth_vs_gbuffer_pixels_differing": geometry_diff,
                "diffcol_changed_outside_decal_mask": int((diffcol_changed & ~mask).sum()),
                "diffcol_changed_inside_decal_mask": int((diffcol_changed & mask).sum()),
            })
            check["pixel_sha256"] = {os.path.basename(p): pixel_digest(p) for p in (g_out, t_out)}
            verification[str(f)] = check
            print(f"deform_sequence: frame {f}: {json.dumps(check)}", flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    cam_doc["verification_per_frame"] = verification
    with open(os.path.join(out_dir, "camera.json"), "w") as f:
        json.dump(cam_doc, f, indent=2)
    seq = {
        "format": "decal-sequence/1",
        "mode": "deform",
        "description": "blender-deform-own: a ball (box-projection UV islands) twisted, squashed and rippled, with two "
                       "texture-space (rest-pose) box decals, a twin ball with the same UVs, static camera",
        "script": "tools/blender/deform_sequence.py",
        "frames": frames,
        "resolution": list(RES),
        "objects": {"Blob": {"pass_index": BALL_INDEX, "object_to_world": rows(obj_to_world),
                             "rest_triangles": n_tri, "rest_vertices": n_vert,
                             "uv_islands": len(set(islands))},
                    "BlobTwin": {"pass_index": TWIN_INDEX, "note": "same mesh and UVs, no decal: must stay untouched"},
                    "Floor": {"pass_index": FLOOR_INDEX}},
        "deformation": "modifier stack: Geometry Nodes StoreRestPosition (point attribute 'rest_position' = position), "
                       "Simple Deform TWIST about Z (angle twist_deg), Simple Deform STRETCH along Z (factor stretch), "
                       "Wave along normals (height wave_height, width 0.35, narrowness 1.5, speed 0.12, start (0.3, -0.2), "
                       "time = frame)",
        "decals": decal_notes,
        "frame_parameters": per_frame,
        "verification_per_frame": verification,
        "truth": "truth.NNNN.exr: DiffCol with the decals (Blender nodes at the rest position), IndexOB, DecalMask "
                 "(1 inside a decal box), DecalCoverage (blend factor), RestPosition (the rest_position attribute).",
        "render": {"samples": 1, "seed": 0, "animated_seed": False, "pixel_filter": "BLACKMAN_HARRIS 0.01 px",
                   "interp": "closest", "blender_version": bpy.app.version_string},
    }
    with open(os.path.join(out_dir, "sequence.json"), "w") as f:
        json.dump(seq, f, indent=2)
    print("deform_sequence: wrote", out_dir, flush=True)


if __name__ == "__main__":
    main()
