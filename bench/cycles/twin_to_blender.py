"""Render a photoscene twin folder with Blender Cycles (CPU).

    blender --background --factory-startup --python bench/cycles/twin_to_blender.py -- \
        --twin DIR --out IMAGE.exr --spp N --width W --height H [--camera CAMERA.json] \
        [--lights LIGHTS.json] [--seed S] [--threads T]

Builds the scene the way the blender-room ground truth was rendered (see
shared/data/examples/blender-room/README.txt and gt/twin/README.txt):

* geometry: the OBJ of scene.json, parsed here (not bpy.ops.import_scene.obj): one material slot per
  usemtl part, per-corner normals (vn) as custom split normals, the OBJ uv as layer "UVMap";
  our Y-up world maps to Blender's Z-up world by (x, y, z) -> (x, -z, y).
* materials (materials/<part>.json, spec section 3): Principled BSDF (GGX), base colour =
  clamp(albedo_scale * (albedo map (sRGB) + albedo_offset), 0, 1) or homogeneous.albedo,
  roughness = clamp(roughness_scale * map) or homogeneous.roughness, metallic (map or value),
  specular = homogeneous.specular (default 0.5; F0 = 0.08 specular as in Principled), normal map
  (tangent space, UV layer "TexUV" = the transformed coordinates, so the tangent frame turns with
  the mapping).  Texture lookups go UVMap -> Mapping (Point: t = R(rot) S uv + offset) -> image
  (Linear interpolation, Repeat).  A purely Lambertian material (specular 0, metallic 0: the
  contract's model is then exactly Lambert) is a Diffuse BSDF of roughness 0, as gt/lambert_view0.exr
  was rendered; Principled would add Burley's retro-reflection.
* emitters: OBJ parts (lights.json `part`) or rectangles (center, edge_u, edge_v) as one-sided
  Emission (strength max(rgb), colour rgb / max; black on the back face); window parts
  (environment.window_parts) fully transparent.
* world: environment image (equirect) x radiance, Generated -> Mapping (Point, rotation Z = rot)
  -> Environment Texture; or a constant colour.
* camera: OpenCV intrinsics/extrinsics (scene.json view 0 or CAMERA.json; position/look_at/up/fov_y_deg
  also accepted) -> horizontal sensor fit, lens = fx sensor_width / W, shift_x = (W/2 - 0.5 - cx) / W,
  shift_y = (cy - H/2 + 0.5) / W, matrix_world = inverse(diag(1,-1,-1,1) world_to_camera blender_to_world).
  The render resolution may differ from the camera's (same aspect): lens and shift are relative
  to the image width, which is photoscene's Camera::resized.
* Cycles: CPU, bounces 12 / diffuse 6 / glossy 4, filter glossy 0, no clamping, no denoiser, adaptive
  sampling off, Blackman-Harris 1.5 px, fixed seed, --threads threads; 32-bit float EXR, linear.

Prints "CYCLES_BUILD_SECONDS x" (scene construction) and "CYCLES_RENDER_SECONDS x" (the render call).
"""

import argparse
import json
import math
import os
import sys
import time

import bpy
import mathutils

T_START = time.time()


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="twin_to_blender.py")
    ap.add_argument("--twin", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--width", type=int, default=0)
    ap.add_argument("--height", type=int, default=0)
    ap.add_argument("--camera", default=None)
    ap.add_argument("--lights", default=None)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
    return ap.parse_args(argv)


def load_json(path):
    with open(path, "r") as f:
        return json.load(f)


def to_blender(p):
    """Y-up world (photoscene) -> Z-up world (Blender)."""
    return (p[0], -p[2], p[1])


# ----------------------------------------------------------------------------------------- OBJ
def read_obj(path):
    V, VT, VN = [], [], []
    faces = []  # (part, [(vi, ti, ni), ...])
    part = "default"
    with open(path, "r") as f:
        for line in f:
            if not line or line[0] == "#":
                continue
            tok = line.split()
            if not tok:
                continue
            k = tok[0]
            if k == "v":
                V.append((float(tok[1]), float(tok[2]), float(tok[3])))
            elif k == "vt":
                VT.append((float(tok[1]), float(tok[2])))
            elif k == "vn":
                VN.append((float(tok[1]), float(tok[2]), float(tok[3])))
            elif k == "usemtl":
                part = tok[1] if len(tok) > 1 else "default"
            elif k == "f":
                corners = []
                for c in tok[1:]:
                    s = c.split("/")
                    vi = int(s[0])
                    ti = int(s[1]) if len(s) > 1 and s[1] else 0
                    ni = int(s[2]) if len(s) > 2 and s[2] else 0
                    vi = vi - 1 if vi > 0 else len(V) + vi
                    ti = (ti - 1 if ti > 0 else len(VT) + ti) if ti != 0 else -1
                    ni = (ni - 1 if ni > 0 else len(VN) + ni) if ni != 0 else -1
                    corners.append((vi, ti, ni))
                # fan-triangulate polygons (the path tracer triangulates the same way)
                for i in range(1, len(corners) - 1):
                    faces.append((part, [corners[0], corners[i], corners[i + 1]]))
    return V, VT, VN, faces


def uv_transform_matrix(ut):
    rot = math.radians(float(ut.get("rotation_deg", 0.0)))
    sc = ut.get("scale", 1.0)
    su, sv = (float(sc[0]), float(sc[1])) if isinstance(sc, (list, tuple)) else (float(sc), float(sc))
    off = ut.get("offset", [0.0, 0.0])
    return rot, su, sv, (float(off[0]), float(off[1]))


def apply_uv_transform(uv, ut):
    rot, su, sv, off = ut
    x, y = su * uv[0], sv * uv[1]
    c, s = math.cos(rot), math.sin(rot)
    return (c * x - s * y + off[0], s * x + c * y + off[1])


# ----------------------------------------------------------------------------------------- materials
def resolve_path(path):
    """Follow symlink placeholders: a checkout without symlink support turns a link (e.g.
    gt/twin_lambert/textures) into a small text file holding the target."""
    path = os.path.abspath(path)
    if os.path.exists(path):
        return path
    parts = path.split(os.sep)
    for i in range(1, len(parts)):
        head = os.sep.join(parts[:i + 1]) or os.sep
        if os.path.isfile(head) and os.path.getsize(head) < 1024 and i + 1 < len(parts):
            with open(head, "r") as f:
                target = f.read().strip()
            base = os.path.join(os.path.dirname(head), target)
            return resolve_path(os.path.join(base, *parts[i + 1:]))
    return path


def img_node(nt, path, colorspace):
    n = nt.nodes.new("ShaderNodeTexImage")
    img = bpy.data.images.load(resolve_path(path), check_existing=True)
    img.colorspace_settings.name = colorspace
    n.image = img
    n.interpolation = "Linear"
    n.extension = "REPEAT"
    return n


def make_emission_material(name, radiance):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    strength = max(radiance)
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (*(c / strength if strength > 0 else 0.0 for c in radiance), 1.0)
    em.inputs["Strength"].default_value = strength
    black = nt.nodes.new("ShaderNodeBsdfDiffuse")
    black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
    nt.links.new(em.outputs["Emission"], mix.inputs[1])     # front: emission
    nt.links.new(black.outputs["BSDF"], mix.inputs[2])      # back: black
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return mat


def make_window_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    tr = nt.nodes.new("ShaderNodeBsdfTransparent")
    tr.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    nt.links.new(tr.outputs["BSDF"], out.inputs["Surface"])
    return mat


def make_part_material(name, mj, twin_dir, ut):
    """mj: materials/<part>.json (or {} when missing)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    hom = mj.get("homogeneous", {}) or {}
    maps = mj.get("maps", {}) or {}
    maps = {k: v for k, v in maps.items() if v}
    albedo = hom.get("albedo", [0.5, 0.5, 0.5])
    rough = float(hom.get("roughness", 0.5))
    metal = float(hom.get("metallic", 0.0))
    spec = float(hom.get("specular", 0.5))
    a_scale = float(mj.get("albedo_scale", 1.0))
    a_off = mj.get("albedo_offset", [0.0, 0.0, 0.0]) or [0.0, 0.0, 0.0]
    r_scale = float(mj.get("roughness_scale", 1.0))

    lambert = spec == 0.0 and metal == 0.0 and "metallic" not in maps
    if lambert:
        bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Roughness"].default_value = 0.0
        color_in = bsdf.inputs["Color"]
    else:
        bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
        bsdf.distribution = "GGX"
        bsdf.inputs["Specular"].default_value = spec
        bsdf.inputs["Roughness"].default_value = rough
        bsdf.inputs["Metallic"].default_value = metal
        color_in = bsdf.inputs["Base Color"]
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    color_in.default_value = (*[float(c) for c in albedo], 1.0)

    if not maps:
        return mat
    rot, su, sv, off = ut
    uvn = nt.nodes.new("ShaderNodeUVMap")
    uvn.uv_map = "UVMap"
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.vector_type = "POINT"
    mp.inputs["Location"].default_value = (off[0], off[1], 0.0)
    mp.inputs["Rotation"].default_value = (0.0, 0.0, rot)
    mp.inputs["Scale"].default_value = (su, sv, 1.0)
    nt.links.new(uvn.outputs["UV"], mp.inputs["Vector"])
    tvec = mp.outputs["Vector"]

    if "albedo" in maps:
        tex = img_node(nt, os.path.join(twin_dir, maps["albedo"]), "sRGB")
        nt.links.new(tvec, tex.inputs["Vector"])
        col = tex.outputs["Color"]
        if any(float(o) != 0.0 for o in a_off):
            add = nt.nodes.new("ShaderNodeVectorMath")
            add.operation = "ADD"
            add.inputs[1].default_value = tuple(float(o) for o in a_off)
            nt.links.new(col, add.inputs[0])
            col = add.outputs["Vector"]
        if a_scale != 1.0 or any(float(o) != 0.0 for o in a_off):
            mul = nt.nodes.new("ShaderNodeMixRGB")   # clamp(scale * (map + offset), 0, 1)
            mul.blend_type = "MULTIPLY"
            mul.use_clamp = True
            mul.inputs["Fac"].default_value = 1.0
            mul.inputs["Color2"].default_value = (a_scale, a_scale, a_scale, 1.0)
            nt.links.new(col, mul.inputs["Color1"])
            col = mul.outputs["Color"]
        nt.links.new(col, color_in)

    if lambert:
        return mat

    def scalar_map(key, scale, target):
        tex = img_node(nt, os.path.join(twin_dir, maps[key]), "Non-Color")
        nt.links.new(tvec, tex.inputs["Vector"])
        sep = nt.nodes.new("ShaderNodeSeparateColor")
        nt.links.new(tex.outputs["Color"], sep.inputs["Color"])
        val = sep.outputs[0]
        m = nt.nodes.new("ShaderNodeMath")
        m.operation = "MULTIPLY"
        m.use_clamp = True
        m.inputs[1].default_value = scale
        nt.links.new(val, m.inputs[0])
        nt.links.new(m.outputs["Value"], target)

    if "roughness" in maps:
        scalar_map("roughness", r_scale, bsdf.inputs["Roughness"])
    if "metallic" in maps:
        scalar_map("metallic", 1.0, bsdf.inputs["Metallic"])
    if "normal" in maps:
        tex = img_node(nt, os.path.join(twin_dir, maps["normal"]), "Non-Color")
        nt.links.new(tvec, tex.inputs["Vector"])
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.space = "TANGENT"
        nm.uv_map = "TexUV"
        nm.inputs["Strength"].default_value = 1.0
        nt.links.new(tex.outputs["Color"], nm.inputs["Color"])
        nt.links.new(nm.outputs["Normal"], bsdf.inputs["Normal"])
    return mat


# ----------------------------------------------------------------------------------------- camera
def camera_from_desc(c):
    W, H = int(c["width"]), int(c["height"])
    if "world_to_camera" in c:
        fx, fy, cx, cy = float(c["fx"]), float(c["fy"]), float(c["cx"]), float(c["cy"])
        w2c = mathutils.Matrix([list(map(float, r)) for r in c["world_to_camera"]])
    else:  # position / look_at / up / fov_y_deg
        pos = mathutils.Vector(c["position"])
        z = (mathutils.Vector(c["look_at"]) - pos).normalized()
        up = mathutils.Vector(c.get("up", [0, 1, 0]))
        x = z.cross(up).normalized()
        y = z.cross(x)
        R = mathutils.Matrix([x, y, z])
        t = -(R @ pos)
        w2c = mathutils.Matrix([[*R[0], t[0]], [*R[1], t[1]], [*R[2], t[2]], [0, 0, 0, 1]])
        fy = 0.5 * H / math.tan(math.radians(float(c["fov_y_deg"])) / 2)
        fx, cx, cy = fy, W / 2 - 0.5, H / 2 - 0.5
    return W, H, fx, fy, cx, cy, w2c


def setup_camera(scene, desc, rw, rh):
    W, H, fx, fy, cx, cy, w2c = camera_from_desc(desc)
    cam_data = bpy.data.cameras.new("cam")
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.sensor_width = 36.0
    cam_data.lens = fx * cam_data.sensor_width / W
    cam_data.shift_x = (W / 2 - 0.5 - cx) / W
    cam_data.shift_y = (cy - H / 2 + 0.5) / W
    cam_data.clip_start = 0.001
    cam_data.clip_end = 1000.0
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    b2w = mathutils.Matrix([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]])  # blender -> world
    flip = mathutils.Matrix.Diagonal((1, -1, -1, 1))
    cam.matrix_world = (flip @ w2c @ b2w).inverted()
    scene.camera = cam
    if rw <= 0:
        rw, rh = W, H
    scene.render.resolution_x = rw
    scene.render.resolution_y = rh
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = 1.0
    scene.render.pixel_aspect_y = fy / fx if fx != fy else 1.0
    if abs(rw * H - rh * W) > 1e-6 * W * H:
        print("warning: render aspect differs from the camera's", file=sys.stderr)


# ----------------------------------------------------------------------------------------- main
def main():
    args = parse_args()
    twin = os.path.abspath(args.twin)
    scene_json = load_json(os.path.join(twin, "scene.json"))
    up = scene_json.get("up", [0, 1, 0])
    if [float(u) for u in up] != [0.0, 1.0, 0.0]:
        raise SystemExit("twin_to_blender.py: only up = [0, 1, 0] is supported")
    lights_path = args.lights or os.path.join(twin, "lights.json")
    if os.path.exists(lights_path):
        lj = load_json(lights_path)
        emitters = lj.get("emitters", [])
        env = lj.get("environment")
        exposure = (lj.get("exposure") or [1.0])[0] if not args.camera else 1.0
        lights_dir = os.path.dirname(os.path.abspath(lights_path))
    else:
        sl = scene_json.get("lights", {})
        emitters, env, exposure, lights_dir = sl.get("area", []), sl.get("environment"), 1.0, twin
    if not args.lights and os.path.exists(lights_path):
        lights_dir = twin

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    # geometry
    obj_path = os.path.join(twin, scene_json["geometry"])
    V, VT, VN, faces = read_obj(obj_path)
    parts = []
    part_index = {}
    for p, _ in faces:
        if p not in part_index:
            part_index[p] = len(parts)
            parts.append(p)
    window_parts = set((env or {}).get("window_parts", []) or [])
    emit_parts = {e["part"]: e for e in emitters if e.get("part")}

    mats = {}
    uts = {}
    for p in parts:
        mpath = os.path.join(twin, "materials", p + ".json")
        mj = load_json(mpath) if os.path.exists(mpath) else {}
        uts[p] = uv_transform_matrix(mj.get("uv_transform", {}) or {})
        if p in emit_parts:
            mats[p] = make_emission_material(p, [float(c) for c in emit_parts[p]["radiance"]])
        elif p in window_parts:
            mats[p] = make_window_material(p)
        else:
            mats[p] = make_part_material(p, mj, twin, uts[p])

    mesh = bpy.data.meshes.new("twin")
    verts = [to_blender(v) for v in V]
    mesh.from_pydata(verts, [], [[c[0] for c in f] for _, f in faces])
    for p in parts:
        mesh.materials.append(mats[p])
    mesh.polygons.foreach_set("material_index", [part_index[p] for p, _ in faces])
    uv0 = mesh.uv_layers.new(name="UVMap")
    uv1 = mesh.uv_layers.new(name="TexUV")
    flat_uv, flat_tuv = [], []
    for p, f in faces:
        for _, ti, _ in f:
            uv = VT[ti] if ti >= 0 else (0.0, 0.0)
            tuv = apply_uv_transform(uv, uts[p])
            flat_uv += [uv[0], uv[1]]
            flat_tuv += [tuv[0], tuv[1]]
    uv0.data.foreach_set("uv", flat_uv)
    uv1.data.foreach_set("uv", flat_tuv)
    mesh.polygons.foreach_set("use_smooth", [True] * len(faces))
    if VN:
        normals = []
        for _, f in faces:
            for _, _, ni in f:
                normals.append(to_blender(VN[ni]) if ni >= 0 else (0.0, 0.0, 0.0))  # 0 = auto
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi
        mesh.normals_split_custom_set(normals)
    mesh.update()
    ob = bpy.data.objects.new("twin", mesh)
    scene.collection.objects.link(ob)

    # rectangle emitters
    for e in emitters:
        if e.get("part"):
            continue
        c = [float(x) for x in e["center"]]
        eu = [float(x) for x in e["edge_u"]]
        ev = [float(x) for x in e["edge_v"]]
        corners = []
        for a, b in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
            corners.append(to_blender([c[i] + a * eu[i] + b * ev[i] for i in range(3)]))
        rm = bpy.data.meshes.new(e.get("name", "rect"))
        rm.from_pydata(corners, [], [[0, 1, 2, 3]])  # normal = edge_u x edge_v (rotation keeps it)
        rm.materials.append(make_emission_material(e.get("name", "rect"), [float(x) for x in e["radiance"]]))
        rm.update()
        ro = bpy.data.objects.new(e.get("name", "rect"), rm)
        scene.collection.objects.link(ro)

    # world
    world = bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    wout = nt.nodes.new("ShaderNodeOutputWorld")
    bg = nt.nodes.new("ShaderNodeBackground")
    nt.links.new(bg.outputs["Background"], wout.inputs["Surface"])
    if env:
        rad = env.get("radiance", env.get("strength", [1.0, 1.0, 1.0]))
        if not isinstance(rad, (list, tuple)):
            rad = [float(rad)] * 3
        rad = [float(r) for r in rad]
        if env.get("image"):
            tc = nt.nodes.new("ShaderNodeTexCoord")
            mp = nt.nodes.new("ShaderNodeMapping")
            mp.vector_type = "POINT"
            mp.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(float(env.get("rotation_deg", 0.0))))
            et = nt.nodes.new("ShaderNodeTexEnvironment")
            et.image = bpy.data.images.load(os.path.abspath(os.path.join(lights_dir, env["image"])))
            et.interpolation = "Linear"
            et.projection = "EQUIRECTANGULAR"
            nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
            nt.links.new(mp.outputs["Vector"], et.inputs["Vector"])
            s = max(rad) if max(rad) > 0 else 1.0
            mul = nt.nodes.new("ShaderNodeMixRGB")
            mul.blend_type = "MULTIPLY"
            mul.inputs["Fac"].default_value = 1.0
            mul.inputs["Color2"].default_value = (rad[0] / s, rad[1] / s, rad[2] / s, 1.0)
            nt.links.new(et.outputs["Color"], mul.inputs["Color1"])
            nt.links.new(mul.outputs["Color"], bg.inputs["Color"])
            bg.inputs["Strength"].default_value = s
        else:
            bg.inputs["Color"].default_value = (*rad, 1.0)
            bg.inputs["Strength"].default_value = 1.0
    else:
        bg.inputs["Strength"].default_value = 0.0

    # camera
    if args.camera:
        cam_desc = load_json(args.camera)
        cam_desc = cam_desc.get("camera", cam_desc)
    else:
        cam_desc = scene_json["views"][0]["camera"]
    setup_camera(scene, cam_desc, args.width, args.height)

    # Cycles, as the blender-room case was rendered
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = args.spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.max_bounces = 12
    cy.diffuse_bounces = 6
    cy.glossy_bounces = 4
    cy.blur_glossy = 0.0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.pixel_filter_type = "BLACKMAN_HARRIS"
    cy.filter_width = 1.5
    cy.seed = args.seed
    cy.use_animated_seed = False
    cy.film_exposure = float(exposure)
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.render.dither_intensity = 0.0
    if args.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = args.threads
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = os.path.abspath(args.out)

    t_build = time.time() - T_START
    print("CYCLES_BUILD_SECONDS %.3f" % t_build, flush=True)
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    t_render = time.time() - t0
    print("CYCLES_RENDER_SECONDS %.3f" % t_render, flush=True)


if __name__ == "__main__":
    try:
        main()
    except SystemExit:
        raise
    except Exception:
        import traceback
        traceback.print_exc()
        sys.exit(1)
