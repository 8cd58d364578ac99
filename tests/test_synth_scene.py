import os

import mujoco
import numpy as np

from hdvr.skeleton import Skeleton
from hdvr.synth.scene import build_scene_xml, place_dancers, random_looks, random_stage

os.environ.setdefault("MUJOCO_GL", "egl")


def test_scene_holds_n_dancers_whose_sites_match_the_skeleton():
    rng = np.random.default_rng(0)
    heights = [1.62, 1.80, 1.70]
    model = mujoco.MjModel.from_xml_string(build_scene_xml(heights, random_looks(rng, 3), random_stage(rng)))
    assert model.nq == 3 * 41
    data = mujoco.MjData(model)
    qs = []
    for k, h in enumerate(heights):
        sk = Skeleton(height_m=h)
        q = sk.random_qpos(rng, margin=0.1)
        q[:2] = [k * 1.5, -k]
        qs.append((sk, q))
    data.qpos[:] = np.concatenate([q for _, q in qs])
    mujoco.mj_kinematics(model, data)
    from hdvr.layouts import BODY25_NAMES
    for k, (sk, q) in enumerate(qs):
        sites = np.array([data.site(f"d{k}_{n}").xpos for n in BODY25_NAMES])
        assert np.allclose(sites, sk.keypoints(q), atol=1e-9)
    # dancers do not collide with each other (the scene is kinematic)
    assert (model.geom_contype == 0).all()


def test_distinct_clothing_and_placement():
    rng = np.random.default_rng(1)
    looks = random_looks(rng, 4)
    tops = np.array([lk.top_rgb for lk in looks])
    assert min(np.linalg.norm(tops[i] - tops[j]) for i in range(4) for j in range(i + 1, 4)) > 0.1
    pos, yaws = place_dancers(rng, 4, couple=True)
    assert abs(np.linalg.norm(pos[0] - pos[1]) - 0.75) < 1e-9  # partners 0.75 m apart, facing each other
    assert abs(abs(yaws[1] - yaws[0]) - np.pi) < 1e-9
