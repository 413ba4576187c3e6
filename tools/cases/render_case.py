"""The shared render_case.py (../shared/tools/cases) with this folder's scene table and its extra keys.

Run inside Blender by make_cases.sh, with the shared script's arguments:
    blender -b --factory-startup --python-exit-code 1 -P render_case.py -- CASE OUTDIR WORKDIR [--quick] [--reuse]

The shared script is loaded as a module and runs unchanged, except that its `build` is wrapped: the
shared kinds are built by it; then the floor is moved to floor.loc, objects with `rot` are rotated,
and the kinds it does not know (monkey, torus) are added with its own diffuse material. Scenes far
from the origin get their ray casts near it (far_ray_casts). After its
`main`, the scene file's matrices in meta.json are replaced by the double-precision inverses of the
float32 matrix_world that Cycles rendered with (Blender's own inverse is float32: centimetres of error
at 1e5 m; at the origin the two agree to ~1e-7).
"""
import importlib.util
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import scenes  # noqa: E402  (this folder's table; the shared script's `from scenes import` finds it)

_spec = importlib.util.spec_from_file_location("isg_shared_render_case",
                                               os.path.join(scenes.SHARED_TOOLS, "render_case.py"))
rc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rc)

NEW_KINDS = ("monkey", "torus")
SUZANNE_HALF_WIDTH = 1.367   # primitive_monkey_add(size=2): x extent -1.367..1.367 (ears)


def _add_new(kind, p, name):
    if kind == "monkey":
        bpy.ops.mesh.primitive_monkey_add(size=2.0, location=p["loc"])
        o = bpy.context.active_object
        o.scale = (p["r"] / SUZANNE_HALF_WIDTH,) * 3
        bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
        sub = o.modifiers.new("subsurf", "SUBSURF")
        sub.levels = sub.render_levels = 2
    else:
        bpy.ops.mesh.primitive_torus_add(major_radius=p["r"], minor_radius=p["r2"], major_segments=128,
                                         minor_segments=48, location=p["loc"])
        o = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    o.name = name
    o.data.materials.append(rc.diffuse_material(name, p["color"]))
    return o


def build(sc):
    objs = sc["objects"]
    known = [(i, k, p) for i, (k, p) in enumerate(objs) if k not in NEW_KINDS]
    S = _shared_build(dict(sc, objects=[(k, p) for _, k, p in known]))
    S["floor"].location = sc["floor"].get("loc", (0.0, 0.0, 0.0))
    placed = {}
    for j, (i, k, p) in enumerate(known):          # the shared build names them by their index in its list
        placed[i] = bpy.data.objects[f"{k}{j}"]
    for i, (k, p) in enumerate(objs):
        if k in NEW_KINDS:
            placed[i] = _add_new(k, p, f"{k}{i}")
    for i, (k, p) in enumerate(objs):
        if "rot" in p:
            placed[i].rotation_euler = tuple(math.radians(a) for a in p["rot"])
    K = sc.get("key", {})
    if "spot_angle_deg" in K:   # a spot (scenes.py): the shared point key, its type changed and aimed
        S["key"].data.type = "SPOT"
        ld = S["key"].data
        ld.spot_size = math.radians(K["spot_angle_deg"])
        ld.spot_blend = K["spot_blend"]
        rc.look_at(S["key"], K["pos"], sc["cam"]["target"])   # lights shine along -Z, as cameras look
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.view_layer.update()
    for i, (k, p) in enumerate(objs):
        if k in NEW_KINDS:
            print(f"[build] {k}{i}: dimensions {tuple(round(v, 3) for v in placed[i].dimensions)}")
    return S


def far_ray_casts(S, sc_def, work):
    """key.occluder and refl.dist for scenes far from the origin. Blender's scene.ray_cast works in
    float32 and misses most occluders there (93% of contact's umbra pixels at 1e5 m), so the shared
    ray casts run on the scene moved back by its offset, from P - offset formed in float64, with
    the origin lifted along N by 1e-3 m plus P's own float32 step (P is rounded by up to 0.87 step)."""
    off = np.array(sc_def["offset"], np.float64)
    movers = [o for o in bpy.data.objects if o.type in ("MESH", "CAMERA")]
    saved = {o.name: tuple(o.location) for o in movers}
    for o in movers:   # float32 location minus the offset: exact near the origin
        o.location = tuple(float(v) - d for v, d in zip(saved[o.name], off))
    bpy.context.view_layer.update()
    read, eps = rc.read_exr, rc.RAY_EPS

    def read_moved(path):
        d = read(path)
        if path.endswith("/aov.exr"):
            A = d["ViewLayer.Combined.A"].astype(np.float64)
            for c, v in zip("XYZ", off):   # Position is accumulated like colour: P * alpha
                d[f"ViewLayer.Position.{c}"] = d[f"ViewLayer.Position.{c}"].astype(np.float64) - v * A
        return d

    step = float(np.spacing(np.float32(np.abs(off).max() + sc_def["floor"]["size"])))
    rc.read_exr, rc.RAY_EPS = read_moved, 1e-3 + step
    try:
        moved = dict(sc_def, key=dict(sc_def["key"], pos=tuple(np.array(sc_def["key"]["pos"]) - off)))
        return _shared_ray_casts(S, moved, work)
    finally:
        rc.read_exr, rc.RAY_EPS = read, eps
        for o in movers:
            o.location = saved[o.name]
        bpy.context.view_layer.update()


def ray_casts(S, sc_def, work):
    return far_ray_casts(S, sc_def, work) if sc_def.get("far") else _shared_ray_casts(S, sc_def, work)


def exact_matrices(work):
    """world_to_camera / world_to_light as float64 inverses of the float32 transforms Cycles used."""
    path = f"{work}/meta.json"
    meta = json.load(open(path))
    for key, obj, field in (("camera", "camera", "world_to_camera"), ("shadowmap", "smcam", "world_to_light")):
        m = np.array(bpy.data.objects[obj].matrix_world, dtype=np.float64)
        meta[key][field] = np.linalg.inv(m).tolist()
        meta[key]["matrix_world_float32"] = m.tolist()
    json.dump(meta, open(path, "w"), indent=1)


_shared_build, _shared_ray_casts = rc.build, rc.ray_casts
rc.build, rc.ray_casts = build, ray_casts

if __name__ == "__main__":
    rc.main()
    exact_matrices(rc.parse_args()[2])
