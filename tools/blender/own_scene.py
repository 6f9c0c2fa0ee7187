"""Our own Blender truth scene for decalcomp (issue 14 and 15 datasets).

Builds, from Blender's factory startup, a slanted ground plane, a tilted two-material box, a
cylinder and a torus under one sun, with 4 box decals and 1 frustum projector decal built into
every material by Blender's own shader nodes, and renders with Cycles (CPU, fixed seed):

    nice blender -b --factory-startup --python tools/blender/own_scene.py -- \
        --out DIR --filter gaussian|box|blackman-harris --filter-width W --samples N \
        [--scale K] [--light-passes] [--renders gbuffer,truth] [--no-crypto] [--threads T]

Writes into DIR: gbuffer.exr (the scene without decals), truth.exr (with the decals, plus the
shader AOVs DecalMask, DecalMaskBox, DecalMaskFrustum: 1 inside any decal / a decal of that
kind), camera.json (the sidecar format of ../../data/blender-aa/camera.json), scene.json
(decalcomp's scene format, docs/scene-format.md) and the decal textures (textures.py).

Conventions (../../docs/conventions.md, the same as the shared Blender datasets): each decal has a
world matrix M (local -> world); local = inverse(M) @ P comes from a Texture Coordinate node's
Object output of an Empty whose matrix_world is M. Box: inside iff |x|,|y|,|z| <= 0.5, s = x + 0.5,
t = 0.5 - y (Blender's v = 1 - t = y + 0.5). Frustum: looks down local -Z, d = -z, h = tan(fov_y/2):
inside iff near <= d <= far, |x| <= d h aspect, |y| <= d h; s = 0.5 + x / (2 d h aspect),
t = 0.5 - y / (2 d h). Image Texture: Closest, EXTEND, sRGB 8-bit PNG with straight alpha.
Blend: colour = mix(colour, texture, alpha * opacity * inside) in list order into the base colour.
"""
import argparse
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import textures  # noqa: E402

WIDTH, HEIGHT = 320, 240


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--out", required=True)
    p.add_argument("--filter", choices=["gaussian", "box", "blackman-harris"], required=True)
    p.add_argument("--filter-width", type=float, required=True)
    p.add_argument("--samples", type=int, required=True)
    p.add_argument("--scale", type=int, default=1, help="resolution multiplier (4: the 4x estimate)")
    p.add_argument("--light-passes", action="store_true", help="diffuse/glossy/emit/env light passes")
    p.add_argument("--renders", default="gbuffer,truth")
    p.add_argument("--no-crypto", action="store_true")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    return p.parse_args(argv)


# ---------------------------------------------------------------------------------------------
# The scene
# ---------------------------------------------------------------------------------------------

GROUND_ROT = (math.radians(4.0), math.radians(-3.0), 0.0)


def ground_matrix():
    return Matrix.LocRotScale(Vector((0, 0, 0)), euler(GROUND_ROT), Vector((1, 1, 1)))


def euler(xyz):
    from mathutils import Euler
    return Euler(xyz, "XYZ")


def ground_z(x, y):
    n = ground_matrix().to_3x3() @ Vector((0, 0, 1))
    return -(n.x * x + n.y * y) / n.z


BOX = dict(loc=(-1.7, 0.5), size=1.5, rot=(math.radians(8.0), math.radians(-6.0), math.radians(28.0)))
CYL = dict(loc=(1.6, 1.3), radius=0.55, depth=1.8, rot=(math.radians(5.0), math.radians(4.0), 0.0))
TORUS = dict(loc=(0.25, -1.5), major=0.75, minor=0.25, rot=(math.radians(62.0), 0.0, math.radians(18.0)))


def box_matrix():
    x, y = BOX["loc"]
    return Matrix.LocRotScale(Vector((x, y, ground_z(x, y) + 0.72)), euler(BOX["rot"]), Vector((1, 1, 1)))


def cyl_matrix():
    x, y = CYL["loc"]
    return Matrix.LocRotScale(Vector((x, y, ground_z(x, y) + 0.88)), euler(CYL["rot"]), Vector((1, 1, 1)))


def torus_matrix():
    x, y = TORUS["loc"]
    return Matrix.LocRotScale(Vector((x, y, ground_z(x, y) + 0.62)), euler(TORUS["rot"]), Vector((1, 1, 1)))


CAMERA = dict(location=(0.6, -7.0, 3.4), target=(-0.1, 0.1, 0.6), lens=40.0, sensor=36.0,
              shift_x=-0.03, shift_y=0.02, clip_start=0.1, clip_end=100.0)


def look_rotation(origin, target, up=(0, 0, 1)):
    """Rotation whose local -Z points from origin to target and local +Y is `up` made perpendicular."""
    f = (Vector(target) - Vector(origin)).normalized()
    z = -f
    y = (Vector(up) - Vector(up).dot(z) * z).normalized()
    x = y.cross(z)
    return Matrix((x, y, z)).transposed()  # columns x, y, z


def decals():
    """The decals, in blend order. Each: name, kind, texture file, matrix (mathutils, local -> world),
    opacity, and the frustum fields."""
    out = []
    # 1. a checker on the slanted ground, spun 25 degrees; its box reaches the torus' lower part
    gx, gy = -0.5, -0.8
    m = Matrix.LocRotScale(Vector((gx, gy, ground_z(gx, gy))),
                           euler((GROUND_ROT[0], GROUND_ROT[1], math.radians(25.0))), Vector((2.4, 2.0, 0.8)))
    out.append(dict(name="ground_checker", kind="box", texture="decal_checker.png", matrix=m, opacity=1.0))
    # 2. glyphs on the box's camera-facing side (-Y face), rolled 12 degrees in the face, crossing
    #    the top edge onto the top face (a crease inside the decal)
    bm = box_matrix()
    ex, ey, ez = (bm.to_3x3() @ Vector(a) for a in ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
    half = BOX["size"] / 2
    centre = bm.translation - ey * half + ez * 0.45
    roll = math.radians(12.0)
    dx = ex * math.cos(roll) + ez * math.sin(roll)
    dy = -ex * math.sin(roll) + ez * math.cos(roll)
    dz = -ey
    rot = Matrix((dx, dy, dz)).transposed()
    m = Matrix.Translation(centre) @ rot.to_4x4() @ Matrix.Diagonal(Vector((1.1, 0.74, 0.6, 1.0)))
    out.append(dict(name="box_glyphs", kind="box", texture="decal_glyphs.png", matrix=m, opacity=1.0))
    # 3. a ring projected horizontally from the camera's side onto the cylinder (wraps around it)
    cm = cyl_matrix()
    c = cm.translation + Vector((0, 0, 0.15))
    cam = Vector(CAMERA["location"])
    towards = Vector((cam.x - c.x, cam.y - c.y, 0)).normalized()
    rot = look_rotation(c + towards, c)  # local -Z from the camera side into the cylinder
    m = Matrix.Translation(c) @ rot.to_4x4() @ Matrix.Diagonal(Vector((1.4, 1.4, 1.4, 1.0)))
    out.append(dict(name="cylinder_ring", kind="box", texture="decal_ring.png", matrix=m, opacity=1.0))
    # 4. stripes at opacity 0.6 over the checker and the torus
    sx, sy = 0.45, -1.15
    m = Matrix.LocRotScale(Vector((sx, sy, ground_z(sx, sy) + 0.3)), euler((0.0, 0.0, math.radians(-20.0))),
                           Vector((1.6, 1.2, 1.2)))
    out.append(dict(name="stripes_overlap", kind="box", texture="decal_stripes.png", matrix=m, opacity=0.6))
    # 5. a frustum projector (blast) from above-left onto the ground and the box's corner
    origin, target = (-3.4, -2.6, 3.0), (-1.0, -0.9, 0.1)
    m = Matrix.Translation(Vector(origin)) @ look_rotation(origin, target).to_4x4()
    out.append(dict(name="ground_splat", kind="frustum", texture="decal_splat.png", matrix=m, opacity=0.9,
                    fov_y_deg=32.0, aspect=1.0, near=0.5, far=10.0))
    return out


# ---------------------------------------------------------------------------------------------
# Decal shader nodes: one node group, used by every material
# ---------------------------------------------------------------------------------------------

class Nodes:
    def __init__(self, tree):
        self.tree = tree
        self.x = 0

    def node(self, kind, **props):
        n = self.tree.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        n.location = (self.x, 0)
        self.x += 20
        return n

    def link(self, out, inp):
        self.tree.links.new(out, inp)

    def feed(self, socket, value):
        if hasattr(value, "is_output"):
            self.link(value, socket)
        else:
            socket.default_value = value

    def math(self, op, a, b=None):
        n = self.node("ShaderNodeMath", operation=op, use_clamp=False)
        self.feed(n.inputs[0], a)
        if b is not None:
            self.feed(n.inputs[1], b)
        return n.outputs[0]

    def not_(self, a):  # 1 - a
        return self.math("SUBTRACT", 1.0, a)


def build_decal_group(decal_list, empties, images):
    group = bpy.data.node_groups.new("Decals", "ShaderNodeTree")
    group.inputs.new("NodeSocketColor", "Base")
    for name in ("Color",):
        group.outputs.new("NodeSocketColor", name)
    for name in ("Mask", "MaskBox", "MaskFrustum"):
        group.outputs.new("NodeSocketFloat", name)
    g = Nodes(group)
    gin = g.node("NodeGroupInput")
    gout = g.node("NodeGroupOutput")
    colour = gin.outputs["Base"]
    mask = {"box": 0.0, "frustum": 0.0}
    for d in decal_list:
        tc = g.node("ShaderNodeTexCoord")
        tc.object = empties[d["name"]]
        sep = g.node("ShaderNodeSeparateXYZ")
        g.link(tc.outputs["Object"], sep.inputs[0])
        x, y, z = sep.outputs[0], sep.outputs[1], sep.outputs[2]
        if d["kind"] == "box":
            m = g.math("MAXIMUM", g.math("MAXIMUM", g.math("ABSOLUTE", x), g.math("ABSOLUTE", y)), g.math("ABSOLUTE", z))
            inside = g.not_(g.math("GREATER_THAN", m, 0.5))
            u = g.math("ADD", x, 0.5)
            v = g.math("ADD", y, 0.5)
        else:  # frustum
            h = math.tan(math.radians(d["fov_y_deg"]) / 2)
            dd = g.math("MULTIPLY", z, -1.0)
            hy = g.math("MULTIPLY", dd, h)
            hx = g.math("MULTIPLY", dd, h * d["aspect"])
            ins = [g.not_(g.math("LESS_THAN", dd, d["near"])), g.not_(g.math("GREATER_THAN", dd, d["far"])),
                   g.not_(g.math("GREATER_THAN", g.math("ABSOLUTE", x), hx)),
                   g.not_(g.math("GREATER_THAN", g.math("ABSOLUTE", y), hy))]
            inside = g.math("MULTIPLY", g.math("MULTIPLY", ins[0], ins[1]), g.math("MULTIPLY", ins[2], ins[3]))
            u = g.math("ADD", g.math("DIVIDE", x, g.math("MULTIPLY", hx, 2.0)), 0.5)
            v = g.math("ADD", g.math("DIVIDE", y, g.math("MULTIPLY", hy, 2.0)), 0.5)
        uv = g.node("ShaderNodeCombineXYZ")
        g.link(u, uv.inputs[0])
        g.link(v, uv.inputs[1])
        uv.inputs[2].default_value = 0.0
        tex = g.node("ShaderNodeTexImage", interpolation="Closest", extension="EXTEND", projection="FLAT")
        tex.image = images[d["texture"]]
        g.link(uv.outputs[0], tex.inputs["Vector"])
        fac = g.math("MULTIPLY", g.math("MULTIPLY", tex.outputs["Alpha"], d["opacity"]), inside)
        mix = g.node("ShaderNodeMixRGB", blend_type="MIX", use_clamp=False)
        g.link(fac, mix.inputs["Fac"])
        g.feed(mix.inputs["Color1"], colour)
        g.link(tex.outputs["Color"], mix.inputs["Color2"])
        colour = mix.outputs["Color"]
        mask[d["kind"]] = g.math("MAXIMUM", mask[d["kind"]], inside)
    g.link(colour, gout.inputs["Color"])
    g.feed(gout.inputs["MaskBox"], mask["box"])
    g.feed(gout.inputs["MaskFrustum"], mask["frustum"])
    g.feed(gout.inputs["Mask"], g.math("MAXIMUM", mask["box"], mask["frustum"]))
    return group


def make_material(name, base, group):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = 0.45
    bsdf.inputs["Specular"].default_value = 0.5
    rgb = nt.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (*base, 1.0)
    if group is None:
        nt.links.new(rgb.outputs[0], bsdf.inputs["Base Color"])
        return mat
    gn = nt.nodes.new("ShaderNodeGroup")
    gn.node_tree = group
    nt.links.new(rgb.outputs[0], gn.inputs["Base"])
    nt.links.new(gn.outputs["Color"], bsdf.inputs["Base Color"])
    for out_name, aov_name in (("Mask", "DecalMask"), ("MaskBox", "DecalMaskBox"), ("MaskFrustum", "DecalMaskFrustum")):
        aov = nt.nodes.new("ShaderNodeOutputAOV")
        aov.name = aov_name  # ShaderNodeOutputAOV's own 'name' is the AOV's name (Blender 3.4)
        nt.links.new(gn.outputs[out_name], aov.inputs["Value"])
    return mat


MATERIALS = {
    "M_Ground": (0.55, 0.50, 0.42),
    "M_BoxSide": (0.22, 0.36, 0.60),
    "M_BoxTop": (0.72, 0.28, 0.20),
    "M_Cylinder": (0.80, 0.74, 0.32),
    "M_Torus": (0.30, 0.58, 0.30),
}


def build_scene(with_decals, args, out_dir):
    # empty the factory scene (cube, light, camera) and the data it holds
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.node_groups,
                 bpy.data.images):
        for block in list(coll):
            if getattr(block, "type", "") not in ("RENDER_RESULT", "COMPOSITING"):
                coll.remove(block)
    scene = bpy.context.scene
    dl = decals()
    group = None
    if with_decals:
        empties = {}
        for d in dl:
            e = bpy.data.objects.new("Decal_" + d["name"], None)
            scene.collection.objects.link(e)
            e.matrix_world = d["matrix"]
            empties[d["name"]] = e
        images = {}
        for d in dl:
            if d["texture"] not in images:
                img = bpy.data.images.load(os.path.join(out_dir, d["texture"]))
                img.colorspace_settings.name = "sRGB"
                img.alpha_mode = "STRAIGHT"
                images[d["texture"]] = img
        group = build_decal_group(dl, empties, images)
    mats = {name: make_material(name, rgb, group) for name, rgb in MATERIALS.items()}

    def add(obj, matrix, materials, index):
        obj.matrix_world = matrix
        obj.pass_index = index
        for m in materials:
            obj.data.materials.append(mats[m])
        return obj

    bpy.ops.mesh.primitive_plane_add(size=16.0)
    ground = add(bpy.context.active_object, ground_matrix(), ["M_Ground"], 1)
    ground.name = "Ground"

    bpy.ops.mesh.primitive_cube_add(size=BOX["size"])
    box = add(bpy.context.active_object, box_matrix(), ["M_BoxSide", "M_BoxTop"], 2)
    box.name = "Box"
    for poly in box.data.polygons:
        poly.material_index = 1 if abs(poly.normal.z) > 0.5 else 0

    bpy.ops.mesh.primitive_cylinder_add(vertices=64, radius=CYL["radius"], depth=CYL["depth"])
    cyl = add(bpy.context.active_object, cyl_matrix(), ["M_Cylinder"], 3)
    cyl.name = "Cylinder"
    bpy.ops.object.shade_smooth()
    cyl.data.use_auto_smooth = True
    cyl.data.auto_smooth_angle = math.radians(30.0)

    bpy.ops.mesh.primitive_torus_add(major_radius=TORUS["major"], minor_radius=TORUS["minor"], major_segments=64,
                                     minor_segments=24)
    torus = add(bpy.context.active_object, torus_matrix(), ["M_Torus"], 4)
    torus.name = "Torus"
    bpy.ops.object.shade_smooth()

    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = 3.5
    sun_data.angle = 0.0  # sharp shadows: no noise from the sun itself
    sun = bpy.data.objects.new("Sun", sun_data)
    scene.collection.objects.link(sun)
    # light travels right, towards the camera and down (elevation about 38 degrees): the box's shadow
    # falls across the ground decals
    sun.matrix_world = look_rotation((0, 0, 0), (0.65, -0.35, -0.62)).to_4x4()

    world = bpy.data.worlds.get("World") or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.32, 0.40, 0.55, 1.0)
    bg.inputs["Strength"].default_value = 0.35

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = CAMERA["lens"]
    cam_data.sensor_width = CAMERA["sensor"]
    cam_data.sensor_fit = "AUTO"
    cam_data.shift_x = CAMERA["shift_x"]
    cam_data.shift_y = CAMERA["shift_y"]
    cam_data.clip_start = CAMERA["clip_start"]
    cam_data.clip_end = CAMERA["clip_end"]
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    cam.matrix_world = Matrix.Translation(Vector(CAMERA["location"])) @ \
        look_rotation(CAMERA["location"], CAMERA["target"]).to_4x4()
    scene.camera = cam
    return dl


def configure_render(args, with_decals, light_passes):
    scene = bpy.context.scene
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = WIDTH * args.scale
    r.resolution_y = HEIGHT * args.scale
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.threads_mode = "FIXED"
    r.threads = args.threads
    r.use_compositing = False
    r.use_sequencer = False
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    r.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args.samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = args.seed
    c.use_animated_seed = False
    c.pixel_filter_type = {"gaussian": "GAUSSIAN", "box": "BOX", "blackman-harris": "BLACKMAN_HARRIS"}[args.filter]
    c.filter_width = args.filter_width
    # direct light only: low noise, and the beauty model's passes then hold all the light
    c.max_bounces = 4
    c.diffuse_bounces = 0
    c.glossy_bounces = 0
    c.transmission_bounces = 0
    c.volume_bounces = 0
    c.caustics_reflective = False
    c.caustics_refractive = False
    c.use_auto_tile = False
    vl = scene.view_layers[0]
    assert vl.name == "ViewLayer"
    vl.use_pass_combined = True
    vl.use_pass_z = True
    vl.use_pass_normal = True
    vl.use_pass_position = True
    vl.use_pass_diffuse_color = True
    vl.use_pass_object_index = True
    vl.use_pass_uv = True
    crypto = not args.no_crypto
    vl.use_pass_cryptomatte_object = crypto
    vl.use_pass_cryptomatte_material = crypto
    if light_passes:
        vl.use_pass_diffuse_direct = True
        vl.use_pass_diffuse_indirect = True
        vl.use_pass_glossy_direct = True
        vl.use_pass_glossy_indirect = True
        vl.use_pass_glossy_color = True
        vl.use_pass_emit = True
        vl.use_pass_environment = True
    while len(vl.aovs):
        vl.aovs.remove(vl.aovs[0])
    if with_decals:
        for name in ("DecalMask", "DecalMaskBox", "DecalMaskFrustum"):
            aov = vl.aovs.add()
            aov.name = name
            aov.type = "VALUE"


# ---------------------------------------------------------------------------------------------
# Sidecars
# ---------------------------------------------------------------------------------------------

def rows(m):
    return [[float(m[i][j]) for j in range(4)] for i in range(4)]


def camera_json(args):
    scene = bpy.context.scene
    cam = scene.camera
    cd = cam.data
    w, h = scene.render.resolution_x, scene.render.resolution_y
    # float64 copies of the float32 matrix_world, inverted in float64
    c2w = [[float(cam.matrix_world[i][j]) for j in range(4)] for i in range(4)]
    w2c = invert_rigid(c2w)
    # Blender's viewplane (BKE_camera_params_compute_viewplane), sensor fit AUTO -> horizontal for w >= h
    fit = "HORIZONTAL" if w >= h else "VERTICAL"
    viewfac = w if fit == "HORIZONTAL" else h
    pixsize = cd.sensor_width * cd.clip_start / cd.lens / viewfac
    dx, dy = cd.shift_x * viewfac, cd.shift_y * viewfac
    left, right = (-0.5 * w + dx) * pixsize, (0.5 * w + dx) * pixsize
    bottom, top = (-0.5 * h + dy) * pixsize, (0.5 * h + dy) * pixsize
    n, f = cd.clip_start, cd.clip_end
    proj = [[2 * n / (right - left), 0, (right + left) / (right - left), 0],
            [0, 2 * n / (top - bottom), (top + bottom) / (top - bottom), 0],
            [0, 0, -(f + n) / (f - n), -2 * f * n / (f - n)],
            [0, 0, -1, 0]]
    blender_proj = cam.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=w, y=h)
    proj_diff = max(abs(proj[i][j] - blender_proj[i][j]) for i in range(4) for j in range(4))
    fx = fy = cd.lens / cd.sensor_width * viewfac
    cx = w / 2 - dx
    cy = h / 2 + dy
    return {
        "description": "Blender 3.4.1 Cycles camera for gbuffer.exr / truth.exr (tools/blender/own_scene.py)",
        "resolution": [w, h],
        "pixel_aspect": [1.0, 1.0],
        "matrix_layout": "row-major nested lists M[row][col]; matrices act on COLUMN vectors: p_out = M @ [x, y, z, 1]^T "
                         "(translation in the last column, M[0..2][3]). Transpose before passing to APIs that expect "
                         "column-major storage.",
        "world_space": "Blender world: right-handed, +Z up",
        "camera_space": "right-handed; camera looks along its local -Z, +Y is up, +X is right (OpenGL convention); "
                        "visible points have z_cam < 0",
        "world_to_camera": w2c,
        "camera_to_world": c2w,
        "projection": proj,
        "projection_notes": "OpenGL-style clip matrix derived (float64) from sensor/lens/shift/clip exactly like "
                            "Blender's viewplane; equals Camera.calc_matrix_camera(x=W, y=H) (float32) to max abs "
                            f"diff {proj_diff:.3g}. clip = projection @ world_to_camera @ [p,1]; ndc = clip.xyz / "
                            "clip.w in [-1,1]; ndc.z = -1 at clip_start, +1 at clip_end.",
        "pixel_convention": "EXR row 0 is the TOP image row. Pixel (col i, row j) has its centre at ndc_x = "
                            "2*(i+0.5)/W - 1, ndc_y = 1 - 2*(j+0.5)/H. pixel_x = (ndc_x+1)/2*W, pixel_y_from_top = "
                            "(1-ndc_y)/2*H.",
        "intrinsics": {
            "type": "PERSP", "lens_mm": cd.lens, "sensor_width_mm": cd.sensor_width,
            "sensor_height_mm": cd.sensor_height, "sensor_fit": cd.sensor_fit, "effective_sensor_fit": fit,
            "shift_x": cd.shift_x, "shift_y": cd.shift_y, "clip_start": cd.clip_start, "clip_end": cd.clip_end,
            "viewplane_at_clip_start": {"left": left, "right": right, "bottom": bottom, "top": top},
            "pinhole_pixels": "pixel_x = cx + fx * x_cam / (-z_cam); pixel_y_from_top = cy - fy * y_cam / (-z_cam); "
                              "pixel centres at integer + 0.5",
            "fx_pixels": fx, "fy_pixels": fy, "cx_pixels_from_left": cx, "cy_pixels_from_top": cy,
            "fov_x_deg_unshifted": math.degrees(2 * math.atan(w / 2 / fx)),
            "fov_y_deg_unshifted": math.degrees(2 * math.atan(h / 2 / fy)),
        },
        "camera_position_world": [c2w[0][3], c2w[1][3], c2w[2][3]],
        "render": {
            "engine": "CYCLES", "device": "CPU", "samples": args.samples, "seed": args.seed,
            "adaptive_sampling": False,
            "pixel_filter": scene.cycles.pixel_filter_type, "filter_width_px": scene.cycles.filter_width,
            "bounces": {"diffuse": 0, "glossy": 0, "transmission": 0, "volume": 0},
            "denoising": False, "blender_version": bpy.app.version_string,
        },
        "depth": {
            "pass": "ViewLayer.Depth.Z",
            "claimed_meaning": "planar: distance along the camera's viewing axis, Depth = -z_cam = "
                               "-(world_to_camera @ [P,1]).z (NOT the radial ray length). Background (no hit) pixels "
                               "hold 1e10.",
        },
    }


def invert_rigid(m):
    """float64 inverse of a rigid 4x4 (rows): R^T, -R^T t (the camera has scale 1)."""
    r = [[m[j][i] for j in range(3)] for i in range(3)]
    t = [m[0][3], m[1][3], m[2][3]]
    out = [[r[i][0], r[i][1], r[i][2], -sum(r[i][k] * t[k] for k in range(3))] for i in range(3)]
    return out + [[0.0, 0.0, 0.0, 1.0]]


def scene_json(dl):
    textures_out, decals_out = {}, []
    for d in dl:
        key = d["texture"][len("decal_"):-len(".png")]
        textures_out[key] = {"albedo": d["texture"]}
        e = {"name": d["name"], "kind": d["kind"], "matrix": rows(d["matrix"]), "opacity": d["opacity"],
             "filter": "nearest", "texture": key}
        if d["kind"] == "frustum":
            e.update(fov_y_deg=d["fov_y_deg"], aspect=d["aspect"], near=d["near"], far=d["far"])
        decals_out.append(e)
    return {
        "_comment": "Our own Blender scene (tools/blender/own_scene.py): 4 box decals and 1 frustum projector, "
                    "built into every material by Blender's shader nodes (Image Texture 'Closest', EXTEND, sRGB PNG "
                    "with straight alpha, 'over' in list order). Nearest filtering like Cycles' closest.",
        "textures": textures_out,
        "decals": decals_out,
    }


def render(path):
    scene = bpy.context.scene
    scene.render.filepath = path
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    textures.write_all(out)
    for which in args.renders.split(","):
        with_decals = which == "truth"
        dl = build_scene(with_decals, args, out)
        configure_render(args, with_decals, args.light_passes)
        render(os.path.join(out, which + ".exr"))
    with open(os.path.join(out, "camera.json"), "w") as f:
        json.dump(camera_json(args), f, indent=2)
    with open(os.path.join(out, "scene.json"), "w") as f:
        json.dump(scene_json(dl), f, indent=2)


main()
