"""The project's own Cycles cases: the shared scene table (../shared/tools/cases/scenes.py) plus the
scenes below, read by this folder's wrappers of the shared generator (make_cases.sh). Pure data.

Keys beyond the shared table's (its docstring lists those):
  floor.loc   the floor plane's centre (default the origin)
  objects     two more kinds: "monkey" (Blender's Suzanne, subdivided twice and smooth shaded;
              r = half its width, so scale = r / 1.37; h = its height, for the README) and "torus"
              (r = major radius, r2 = minor radius; h = 2 r2; lying flat); any object may carry
              rot = Euler XYZ in degrees
  far         float32 positions far from the origin: the shared post-processing's matrix checks
              assert sub-pixel reprojection of P, which P's own float32 step (1e5: 7.8 mm,
              1e6: 62.5 mm) cannot give; they are measured and reported, not asserted
  notes       extra README paragraph
  key.spot_angle_deg, key.spot_blend
              the key is a Blender spot (size = the cone's full angle, blend) of the key's radius,
              its axis from key.pos toward cam.target, as the shadow map's (the contract's `spot`:
              its map looks down the axis); the scene file's light becomes type `spot` with
              `normal`, `spot_angle_deg` and `spot_blend` (post_case.py)
"""
import copy
import importlib.util
import os

_here = os.path.dirname(os.path.realpath(__file__))
SHARED_TOOLS = os.environ.get("ISG_CASES_SHARED_TOOLS") or os.path.normpath(
    os.path.join(_here, "..", "..", "..", "shared", "tools", "cases"))
_spec = importlib.util.spec_from_file_location("isg_shared_scenes", os.path.join(SHARED_TOOLS, "scenes.py"))
_shared = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_shared)

DEFAULT_SPP, DRT_SPP, SM, W, H = _shared.DEFAULT_SPP, _shared.DRT_SPP, _shared.SM, _shared.W, _shared.H
spp = _shared.spp
SCENES = dict(_shared.SCENES)


def shifted(sc, d):
    """Scene `sc` translated by the vector d (objects, floor, key, camera and its target)."""
    s = copy.deepcopy(sc)
    add = lambda p: tuple(a + b for a, b in zip(p, d))
    for _, p in s["objects"]:
        p["loc"] = add(p["loc"])
    s["floor"]["loc"] = add(s["floor"].get("loc", (0.0, 0.0, 0.0)))
    s["key"]["pos"] = add(s["key"]["pos"])
    s["cam"]["pos"], s["cam"]["target"] = add(s["cam"]["pos"]), add(s["cam"]["target"])
    s["far"], s["offset"] = True, tuple(d)
    return s


# Sample counts of our own scenes, cut so that a case renders in ~20 minutes on a shared 2-core machine:
# the soft visibility (what the shadow benchmark measures) at 1024 spp (two seeds of 512: noise ~1.3e-3 over
# the mask on contact's geometry, 30x below doing nothing), the beauty reference at 512 spp (noise ~1e-3,
# 10x below the AOV beauty's own error). The AOV render keeps the shared cases' 128 spp: the inputs are
# what a user would have. Each case's README gives its measured noise.
OWN_SPP = dict(aov=128, soft=1024, ref=512)

for exp in (5, 6):
    off = 10.0 ** exp
    s = shifted(SCENES["contact"], (off, off, off))
    s["about"] = (f"The shared `contact` scene translated by ({off:.0e}, {off:.0e}, {off:.0e}) m: every object, the "
                  "floor, the key and the camera. Nothing else changes, so any difference from `contact` in a method's "
                  f"error comes from float32 precision: Cycles writes P as float32, whose step is "
                  f"{2.0 ** ((16 if exp == 5 else 19) - 23):.4g} m at this distance. " + SCENES["contact"]["about"])
    s["spp"] = dict(OWN_SPP)
    s["notes"] = ("Far from the origin Cycles itself works in float32: its vertices (transformed to world space), hit "
                  "points and P carry errors of the order of P's step, so the tessellated sphere is visibly bumpy and "
                  "self-shadows in key.shadow and in the reference alike; world_to_camera and world_to_light here are "
                  "the double-precision inverses of Blender's float32 matrix_world, i.e. of the transforms Cycles "
                  "rendered with. key.occluder and refl.dist come from ray casts on the scene moved back to the origin "
                  "(Blender's float32 scene.ray_cast misses most occluders out here), from P - offset formed in "
                  "float64, the origin lifted along N by 1e-3 m plus P's step. The matrix checks are measured and "
                  "reported but not asserted (see above).")
    SCENES[f"contact-far1e{exp}"] = s

SCENES["lowlight"] = dict(
    about=("A large, low sphere light (radius 0.7 m, centre 1.35 m above the floor, 12 to 20 degrees above the horizon "
           "seen from the objects) over curved objects: Suzanne (subdivided, smooth) floating 0.2 m above the floor, a torus "
           "lying on the floor, a sphere resting on it and a thin upright slab. Penumbrae are wide and long; the torus's "
           "hole and the sphere's contact keep hard contact shadows inside them; the light grazes the floor and the "
           "tops of the torus and the sphere (self-shadowing of curved receivers). The key is invisible to glossy rays "
           "(as in the shared `gloss` case): the mirror-like floor would otherwise show the big light's reflection in "
           "the references, which the point-light AOV render cannot contain."),
    objects=[
        ("monkey", dict(loc=(-0.3, 1.9, 0.55), r=0.5, h=0.7, color=(0.72, 0.55, 0.3), rot=(0.0, 0.0, 25.0))),
        ("torus", dict(loc=(-0.6, -1.0, 0.14), r=0.42, r2=0.14, h=0.28, color=(0.3, 0.6, 0.45))),
        ("sphere", dict(loc=(1.6, 1.4, 0.35), r=0.35, color=(0.75, 0.32, 0.22))),
        ("box", dict(loc=(1.6, -1.2, 0.3), size=(0.06, 0.8, 0.6), color=(0.35, 0.45, 0.75), rot=(0.0, 0.0, -20.0))),
    ],
    floor=dict(size=14.0, color=(0.55, 0.53, 0.5), gloss_color=(1.0, 0.92, 0.8), rough=0.0, fresnel_ior=1.5),
    key=dict(pos=(4.5, 2.0, 1.35), power=1400.0, radius=0.7),
    key_glossy=False,
    world=(0.07, 0.075, 0.085),
    cam=dict(pos=(0.3, -6.0, 2.9), target=(0.0, 0.2, 0.35), focal=40.0, sensor=36.0, fstop=2.8, focus=None),
    sm_fov=110.0,
    spp=dict(OWN_SPP),
)

SCENES["grazing"] = dict(
    about=("Receivers lit at grazing angles: a sphere light (radius 0.35 m) 0.75 m above the floor and 5 m to the "
           "side, about 8 degrees above the horizon at the middle of the set. A sphere resting on the floor, a "
           "cube, a thin pole, a ramp tilted 12 degrees towards the light (lit at about 20 degrees) and a cylinder "
           "lying on its side. The floor, the ramp and the tops of the sphere and cylinder receive light almost "
           "along their surface, where a depth bias proportional to the slope grows without bound; shadows are "
           "several metres long."),
    objects=[
        ("sphere", dict(loc=(-1.0, 0.3, 0.4), r=0.4, color=(0.75, 0.32, 0.22))),
        ("box", dict(loc=(0.4, 1.2, 0.2), size=(0.4, 0.4, 0.4), color=(0.25, 0.45, 0.75))),
        ("cylinder", dict(loc=(1.0, -0.4, 0.6), r=0.035, h=1.2, color=(0.8, 0.8, 0.75))),
        ("box", dict(loc=(-0.6, -1.2, 0.12), size=(1.6, 0.9, 0.04), color=(0.6, 0.6, 0.35), rot=(0.0, 12.0, 0.0))),
        ("cylinder", dict(loc=(-1.3, 1.9, 0.22), r=0.22, h=1.4, color=(0.45, 0.7, 0.5), rot=(90.0, 0.0, 15.0))),
    ],
    floor=dict(size=16.0, color=(0.55, 0.53, 0.5), gloss_color=(1.0, 0.92, 0.8), rough=0.0, fresnel_ior=1.5),
    key=dict(pos=(4.9, 0.8, 0.75), power=1600.0, radius=0.35),
    key_glossy=False,
    world=(0.07, 0.075, 0.085),
    cam=dict(pos=(0.2, -6.2, 2.6), target=(0.0, 0.3, 0.3), focal=35.0, sensor=36.0, fstop=2.8, focus=None),
    sm_fov=100.0,
    spp=dict(OWN_SPP),
)

# The same scene with a 4096² shadow map (the shared 1024² over 100 degrees puts a texel 8 cm long on
# the floor at 8 degrees, two to three pixels; the map methods' edges land that far off): what the
# map methods reach on grazing receivers when the map resolves them (issue 19).
SCENES["grazing-sm4096"] = dict(copy.deepcopy(SCENES["grazing"]), sm_size=4096,
                                notes="`grazing` with a 4096² shadow map (1024² there): the same renders otherwise.")

SCENES["overlap"] = dict(
    about=("Blockers at different heights whose shadows overlap under a large sphere light (radius 0.55 m, about 40 "
           "degrees above the set): a thin shelf floating 1.1 m up casts a wide soft shadow over a sphere resting on "
           "the floor, whose own contact shadow lies inside the shelf's penumbra; Suzanne floating 0.8 m up shadows "
           "a torus lying on the floor; a thin pole stands apart. Receivers in the overlaps see two blocker depths "
           "in one kernel, and kernels are wide (the shelf's penumbra is over a metre): where the prefiltered "
           "methods' single depth distribution leaks light (issue 19)."),
    objects=[
        ("box", dict(loc=(0.2, 0.6, 1.1), size=(1.6, 1.2, 0.05), color=(0.4, 0.7, 0.4))),
        ("sphere", dict(loc=(-1.0, 2.0, 0.3), r=0.3, color=(0.75, 0.32, 0.22))),
        ("monkey", dict(loc=(2.0, 1.4, 0.8), r=0.4, h=0.56, color=(0.72, 0.55, 0.3), rot=(0.0, 0.0, 30.0))),
        ("torus", dict(loc=(1.65, 2.35, 0.1), r=0.35, r2=0.1, h=0.2, color=(0.3, 0.6, 0.45))),
        ("cylinder", dict(loc=(0.6, -1.0, 0.7), r=0.04, h=1.4, color=(0.8, 0.8, 0.75))),
    ],
    floor=dict(size=14.0, color=(0.55, 0.53, 0.5), gloss_color=(1.0, 0.92, 0.8), rough=0.0, fresnel_ior=1.5),
    key=dict(pos=(3.0, -1.5, 3.2), power=1600.0, radius=0.55),
    key_glossy=False,
    world=(0.07, 0.075, 0.085),
    cam=dict(pos=(0.2, -5.8, 3.4), target=(-0.4, 1.1, 0.5), focal=35.0, sensor=36.0, fstop=2.8, focus=None),
    sm_fov=100.0,
    spp=dict(OWN_SPP),
)

# The shared `contact` scene under a low sun instead of its sphere key: the one case of a distant light
# (issue 19), so the methods' sun paths (orthographic map, penumbrae set by an angle, not a radius) meet a
# Cycles reference. Elevation 30 degrees: shadows 1.7x their blockers' heights, long enough that the pole's
# and the box's reach well across the floor, not so low that the map turns grazing (`grazing` covers that).
# Azimuth -45 degrees (to the camera's right and behind it, as contact's key at about -30): the shadows fall
# away from the camera and to the left, all inside the frame, and the sun stays far from every mirror
# direction of the glossy floor (post_case.py asserts the references cannot show its disk). Strength 4 W/m^2:
# 2 W/m^2 on the floor at 30 degrees, the irradiance of contact's key on its lit floor (1100 W at 5.2 m,
# median 1.9 W/m^2 measured from its key.direct), so the two cases expose alike.
# The generator frames the orthographic map on everything the camera sees (frame_sun_map): 12.75 m square
# here at the shared 1024^2, a texel 1.25 cm across the rays, 2.5 cm along the floor; the box's penumbra
# is about 6 texels wide across the rays.
SCENES["sun"] = dict(
    copy.deepcopy({k: v for k, v in SCENES["contact"].items() if k not in ("key", "sm_fov")}),
    about=("The shared `contact` scene (a sphere resting on the floor, a box floating 0.8 m above it, a thin pole) "
           "with its key replaced by a low sun: 30 degrees above the horizon, from the camera's right and behind it "
           "(azimuth -45 degrees), angular diameter 2.5 degrees in the references (about five times the real sun's). "
           "Shadows are 1.7 times their blockers' heights long and fall away from the camera and to the left. The "
           "penumbra is d * 0.044 wide across the rays, d the distance from blocker to receiver along the ray, and "
           "1/sin(30) = 2 times that along the ground in the sun's azimuth: sharp where the sphere and the pole touch "
           "the floor, 7 cm (across the rays) under the box's lower face (1.6 m along the ray), 14 cm at the pole's "
           "tip (3.2 m). The shadow map is orthographic."),
    sun=dict(direction=_shared.sun_dir(30.0, -45.0), angle_deg=2.5, strength=4.0),
    spp=dict(OWN_SPP),
)

# The shared `contact` scene under a spot instead of its sphere key (issue 52): the same position, power
# and radius (0.4 m), a 50-degree cone with blend 0.3 aimed at the camera's target, so that the cone's
# soft edge crosses the floor in frame (about 2.4 m from the target) while the three blockers' shadows lie
# inside it. Cycles 3.4 emits a spot from a disk facing the shading point (as its point light), not from
# one facing the axis as the contract's `spot`: over this scene the two differ by the cosine of the angle
# between the axis and the direction to a receiver (at most 25 degrees inside the cone), the reference
# holding Cycles' own.
SCENES["spot"] = dict(
    copy.deepcopy(SCENES["contact"]),
    about=("The shared `contact` scene (a sphere resting on the floor, a box floating 0.8 m above it, a thin pole) "
           "with its sphere key replaced by a spot light of the same position, power and radius (0.4 m): a "
           "50-degree cone, blend 0.3, aimed at the camera's target, so its soft edge crosses the floor in frame "
           "while the blockers' shadows lie inside it. The scene file's light is a `spot` (its axis `normal`, "
           "`spot_angle_deg`, `spot_blend`); its shadow map is perspective, looking down the axis."),
    spp=dict(OWN_SPP),
)
SCENES["spot"]["key"].update(spot_angle_deg=50.0, spot_blend=0.3)

OWN = [k for k in SCENES if k not in _shared.SCENES]
