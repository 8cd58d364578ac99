"""``hdvr model info``: the digital dancer's DOF, joint ranges, masses and keypoint sites."""

from __future__ import annotations

import json

import numpy as np

from hdvr import dh


def register(subparsers) -> None:
    parser = subparsers.add_parser("model", help="inspect the digital dancer model")
    sub = parser.add_subparsers(dest="model_command", metavar="ACTION")
    info = sub.add_parser("info", help="DOF, joint-range table, masses, keypoint sites")
    info.add_argument("--height", type=float, default=dh.DEFAULT_HEIGHT_M, help="dancer height h in metres")
    info.add_argument("--json", action="store_true", help="print JSON instead of tables")
    info.set_defaults(func=run_info)
    parser.set_defaults(func=lambda args: parser.print_help())


def model_summary(height_m: float = dh.DEFAULT_HEIGHT_M) -> dict:
    """Everything ``hdvr model info`` prints, as a dict."""
    import mujoco

    from hdvr.layouts import BODY25_NAMES
    from hdvr.skeleton import MODEL_PATH, Skeleton

    sk = Skeleton(height_m=height_m)
    m = sk.model
    q = sk.rest_qpos()
    kp = sk.keypoints(q)
    joints = [{"row": j.row, "name": j.name, "theta": f"theta_{j.theta_index}",
               "min_deg": round(float(np.rad2deg(j.lower)), 2), "max_deg": round(float(np.rad2deg(j.upper)), 2),
               "rest_deg": round(float(np.rad2deg(j.rest)), 2), "bound_source": j.bound_source,
               "positive": j.meaning} for j in dh.JOINTS]
    bodies = [{"body": m.body(b).name, "mass_kg": round(float(m.body_mass[b]), 3)} for b in range(1, m.nbody)]
    sites = [{"keypoint": n, "body": m.body(int(m.site(n).bodyid[0])).name,
              "rest_world_m": [round(float(v), 4) for v in kp[i]]} for i, n in enumerate(BODY25_NAMES)]
    return {
        "model_file": str(MODEL_PATH),
        "dof": {"nq": int(m.nq), "nv": int(m.nv), "hinges": len(dh.JOINTS), "free_root": 1},
        "height_m": height_m,
        "bones_m": {n: round(float(v), 4) for n, v in zip(dh.BONE_NAMES, sk.bone_lengths)},
        "total_mass_kg": round(float(m.body_mass.sum()), 3),
        "mujoco_version": mujoco.__version__,
        "joints": joints, "bodies": bodies, "keypoint_sites": sites,
    }


def run_info(args) -> int:
    s = model_summary(args.height)
    if args.json:
        print(json.dumps(s, indent=2))
        return 0
    d = s["dof"]
    print(f"HDVR digital dancer ({s['model_file']}, MuJoCo {s['mujoco_version']})")
    print(f"DOF: {d['hinges']} hinges + free root (nq={d['nq']}, nv={d['nv']}); height {s['height_m']:.2f} m; "
          f"mass {s['total_mass_kg']:.1f} kg")
    print("bones (m): " + ", ".join(f"{k} {v:.3f}" for k, v in s["bones_m"].items()))
    print()
    print(f"{'row':>3} {'joint':<24} {'theta':<9} {'min':>8} {'max':>8} {'rest':>7}  bound")
    for j in s["joints"]:
        print(f"{j['row']:>3} {j['name']:<24} {j['theta']:<9} {j['min_deg']:>8.1f} {j['max_deg']:>8.1f} "
              f"{j['rest_deg']:>7.1f}  {j['bound_source']}")
    print()
    print(f"{'body':<18} {'mass kg':>8}")
    for b in s["bodies"]:
        print(f"{b['body']:<18} {b['mass_kg']:>8.3f}")
    print()
    print(f"{'#':>2} {'keypoint site':<16} {'body':<16} rest position (m, world)")
    for i, k in enumerate(s["keypoint_sites"]):
        x, y, z = k["rest_world_m"]
        print(f"{i:>2} {k['keypoint']:<16} {k['body']:<16} ({x:+.3f}, {y:+.3f}, {z:+.3f})")
    return 0
