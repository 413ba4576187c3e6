#!/usr/bin/python3
"""The shared post_case.py (../shared/tools/cases) with this folder's scene table, then two fixes.

usage: post_case.py CASE OUTDIR WORKDIR   (as the shared script; make_cases.sh calls it)

- scene_radius: the shared script measures it to the corners of a floor centred at the origin;
  scenes with floor.loc get the same rule around their own floor (else a scene moved 1e5 m away
  would get a radius of 1e5 m, and every method that scales by it would change).
- a spot key (scenes.py's key.spot_angle_deg): the shared script writes a sphere; the light becomes
  the contract's `spot`, its axis `normal` from key.pos toward cam.target (as the map looks).
- scenes marked `far`: the shared script's matrix checks assert sub-pixel reprojection of P,
  which float32 P cannot give far from the origin. The script is re-run with Python's -O (asserts
  off); the measured numbers still go into facts.json and the README.
"""
import importlib.util
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import scenes  # noqa: E402  (the shared script's `from scenes import` finds this folder's table)


def scene_radius(sc):
    """As the shared post_case.py, with the floor's corners around floor.loc."""
    centre = np.array(sc["cam"]["target"], np.float64)
    half = sc["floor"]["size"] / 2
    fl = np.array(sc["floor"].get("loc", (0.0, 0.0, 0.0)), np.float64)
    pts = [np.array(p["loc"], np.float64) for _, p in sc["objects"]]
    pts += [fl + [sx * half, sy * half, 0.0] for sx in (-1, 1) for sy in (-1, 1)]
    pts.append(np.array(sc["key"]["pos"], np.float64))
    return round(float(max(np.linalg.norm(p - centre) for p in pts)), 3)


def main():
    name, out, work = sys.argv[1:4]
    sc = scenes.SCENES[name]
    if sc.get("far") and sys.flags.optimize == 0:
        os.execv(sys.executable, [sys.executable, "-O", os.path.realpath(__file__), *sys.argv[1:]])
    spec = importlib.util.spec_from_file_location("isg_shared_post_case",
                                                  os.path.join(scenes.SHARED_TOOLS, "post_case.py"))
    pc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pc)
    pc.main()
    if "loc" in sc["floor"]:
        r = scene_radius(sc)
        for path in (f"{out}/scene.json", f"{work}/facts.json"):
            d = json.load(open(path))
            d["scene_radius"] = r
            json.dump(d, open(path, "w"), indent=2 if path.endswith("scene.json") else 1)
        print(f"scene_radius {r} (around the floor at {sc['floor']['loc']})")
    if "spot_angle_deg" in sc.get("key", {}):
        K = sc["key"]
        axis = np.array(sc["cam"]["target"], np.float64) - np.array(K["pos"], np.float64)
        d = json.load(open(f"{out}/scene.json"))
        d["lights"][0].update(type="spot", normal=(axis / np.linalg.norm(axis)).tolist(),
                              spot_angle_deg=K["spot_angle_deg"], spot_blend=K["spot_blend"])
        json.dump(d, open(f"{out}/scene.json", "w"), indent=2)
        print(f"spot: axis {d['lights'][0]['normal']}, cone {K['spot_angle_deg']} deg, blend {K['spot_blend']}")
    if sc.get("far"):
        f = json.load(open(f"{work}/facts.json"))
        print("matrix checks (reported, not asserted):", json.dumps({k: f[k] for k in ("cam_check", "sm_check")}))


if __name__ == "__main__":
    main()
