"""The digital dancer at run time: a MuJoCo model with named, typed accessors.

Frames and units: world x forward (the dancer faces +x at identity root), y to the dancer's left, z up; metres,
radians. ``qpos`` layout (nq = 41): ``[0:3]`` pelvis position, ``[3:7]`` pelvis orientation quaternion (w, x, y, z),
``[7:41]`` the 34 hinges in DH-row order (:data:`hdvr.dh.JOINT_NAMES`). Keypoints are the 25 BODY_25 sites, always
returned in BODY_25 order.

Example::

    sk = Skeleton()
    sk.set_height(1.62)                       # or sk.set_bone_lengths(bones_m)
    q = sk.rest_qpos()
    kp = sk.keypoints(q)                      # (25, 3) world metres
    kps = sk.keypoints(np.stack([q, q]))      # (2, 25, 3)
    jac = sk.keypoint_jacobians(q)            # (25, 3, nv)
"""

from __future__ import annotations

import os
from pathlib import Path

import mujoco
import numpy as np

from hdvr import dh
from hdvr.dancer_model import body_specs, rest_pelvis_height
from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES

MODEL_PATH = Path(__file__).resolve().parent / "models" / "dancer.xml"
NUM_HINGES = dh.NUM_HINGES
ROOT_QPOS = 7  # free joint: 3 position + 4 quaternion
NQ = ROOT_QPOS + NUM_HINGES


class Skeleton:
    """A loaded dancer model with per-subject bone lengths.

    Attributes: ``model`` (mujoco.MjModel), ``data`` (mujoco.MjData, scratch for kinematics),
    ``keypoint_site_ids`` (25,) site ids in BODY_25 order, ``lower``/``upper`` (34,) hinge limits (rad).
    """

    def __init__(self, model_path: str | os.PathLike | None = None, height_m: float = dh.DEFAULT_HEIGHT_M):
        path = Path(model_path) if model_path is not None else MODEL_PATH
        if not path.is_file():
            raise HDVRError(f"dancer model not found: {path}")
        self.model = mujoco.MjModel.from_xml_path(str(path))
        self.data = mujoco.MjData(self.model)
        if self.model.nq != NQ:
            raise HDVRError(f"{path} has nq={self.model.nq}, expected {NQ} (free root + 34 hinges)")
        self.hinge_joint_ids = np.array([self.model.joint(n).id for n in dh.JOINT_NAMES])
        self.hinge_qpos_adr = self.model.jnt_qposadr[self.hinge_joint_ids]
        if not np.array_equal(self.hinge_qpos_adr, np.arange(ROOT_QPOS, NQ)):
            raise HDVRError(f"{path}: hinges are not stored in DH-row order after the root")
        self.keypoint_site_ids = np.array([self.model.site(n).id for n in BODY25_NAMES])
        self.lower = self.model.jnt_range[self.hinge_joint_ids, 0].copy()
        self.upper = self.model.jnt_range[self.hinge_joint_ids, 1].copy()
        self.height_m = float(height_m)
        self._bones = dh.bone_lengths_m(dh.DEFAULT_HEIGHT_M)
        if abs(height_m - dh.DEFAULT_HEIGHT_M) > 1e-12:
            self.set_height(height_m)

    # -- bones -------------------------------------------------------------------------------------------------
    @property
    def bone_lengths(self) -> np.ndarray:
        """(9,) metres, order :data:`hdvr.dh.BONE_NAMES`."""
        return self._bones.copy()

    def set_height(self, height_m: float, ratios: np.ndarray | None = None) -> None:
        """Set bone lengths to ``ratios`` (default: the table's averages) times ``height_m``."""
        if not np.isfinite(height_m) or height_m <= 0:
            raise HDVRError(f"height must be a positive number of metres, got {height_m}")
        self.height_m = float(height_m)
        self.set_bone_lengths(dh.bone_lengths_m(height_m, ratios))

    def set_bone_lengths(self, bones_m) -> None:
        """Move bodies, sites and geoms for bone lengths ``bones_m`` (9,) metres, without re-parsing the XML.

        Masses and inertias keep their compiled values (kinematics is exact; dynamics is approximate for
        subjects far from the default build).
        """
        bones = np.asarray(bones_m, dtype=np.float64)
        if bones.shape != (9,) or not np.isfinite(bones).all() or (bones <= 0).any():
            raise HDVRError(f"bone lengths must be 9 positive numbers of metres, got shape {bones.shape}")
        specs = body_specs(bones, self.height_m)
        m = self.model
        for name, spec in specs.items():
            if name != "pelvis":  # the pelvis position is the free joint's
                m.body_pos[m.body(name).id] = spec.pos
            for g in spec.geoms:
                gid = m.geom(g.name).id
                if g.kind == "capsule":
                    axis = g.end - g.start
                    length = np.linalg.norm(axis)
                    m.geom_pos[gid] = (g.start + g.end) / 2
                    m.geom_size[gid, 0] = g.radius
                    m.geom_size[gid, 1] = length / 2
                    quat = np.zeros(4)
                    mujoco.mju_quatZ2Vec(quat, axis / max(length, 1e-12))
                    m.geom_quat[gid] = quat
                else:
                    m.geom_pos[gid] = g.start
                    m.geom_size[gid, 0] = g.radius
                m.geom_rbound[gid] = m.geom_size[gid, 0] + (m.geom_size[gid, 1] if g.kind == "capsule" else 0)
            for sname, spos in spec.sites.items():
                m.site_pos[m.site(sname).id] = spos
        self._bones = bones.copy()

    # -- poses -------------------------------------------------------------------------------------------------
    def rest_qpos(self) -> np.ndarray:
        """(41,) standing rest pose, pelvis at its rest height above the origin, facing +x."""
        q = np.zeros(NQ)
        q[2] = rest_pelvis_height(self._bones)
        q[3] = 1.0
        q[ROOT_QPOS:] = dh.REST_Q
        return q

    def clamp(self, qpos: np.ndarray) -> np.ndarray:
        """Copy of ``qpos`` (..., 41) with hinges clamped into their ranges and the root quaternion normalised."""
        q = np.array(qpos, dtype=np.float64, copy=True)
        q[..., ROOT_QPOS:] = np.clip(q[..., ROOT_QPOS:], self.lower, self.upper)
        norm = np.linalg.norm(q[..., 3:7], axis=-1, keepdims=True)
        q[..., 3:7] = q[..., 3:7] / np.where(norm > 0, norm, 1.0)
        return q

    def limit_violation(self, qpos: np.ndarray) -> np.ndarray:
        """(..., 34) radians by which each hinge lies outside its range (0 inside)."""
        h = np.asarray(qpos)[..., ROOT_QPOS:]
        return np.maximum(self.lower - h, 0) + np.maximum(h - self.upper, 0)

    def _check_qpos(self, qpos: np.ndarray) -> np.ndarray:
        q = np.asarray(qpos, dtype=np.float64)
        if q.shape[-1] != NQ:
            raise HDVRError(f"qpos must end with {NQ} values (free root + 34 hinges), got shape {q.shape}")
        return q

    def kinematics(self, qpos: np.ndarray) -> None:
        """Run ``mj_kinematics`` for one ``qpos`` (41,) into ``self.data``."""
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)

    def keypoints(self, qpos: np.ndarray) -> np.ndarray:
        """BODY_25 keypoints (world metres) for ``qpos`` (41,) -> (25, 3) or (T, 41) -> (T, 25, 3)."""
        q = self._check_qpos(qpos)
        flat = q.reshape(-1, NQ)
        out = np.empty((flat.shape[0], len(BODY25_NAMES), 3))
        for t in range(flat.shape[0]):
            self.kinematics(flat[t])
            out[t] = self.data.site_xpos[self.keypoint_site_ids]
        return out.reshape(q.shape[:-1] + (len(BODY25_NAMES), 3))

    def site_positions(self, qpos: np.ndarray, site_names) -> np.ndarray:
        """World positions (metres) of named sites, (len(names), 3), for one ``qpos``."""
        self.kinematics(self._check_qpos(qpos))
        return np.array([self.data.site(n).xpos for n in site_names])

    def keypoint_jacobians(self, qpos: np.ndarray) -> np.ndarray:
        """d(keypoint world position)/d(qvel) (25, 3, nv=40) at ``qpos`` (41,), from ``mj_jacSite``.

        Columns 0-2 are root translation, 3-5 root rotation (angular velocity in the world frame), 6-39 hinges.
        """
        self.kinematics(self._check_qpos(qpos))
        mujoco.mj_comPos(self.model, self.data)
        jac = np.empty((len(self.keypoint_site_ids), 3, self.model.nv))
        for k, sid in enumerate(self.keypoint_site_ids):
            mujoco.mj_jacSite(self.model, self.data, jac[k], None, sid)
        return jac

    def hinge_anchors_and_axes(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World anchor (34, 3) and unit axis (34, 3) of each hinge, in DH-row order."""
        self.kinematics(self._check_qpos(qpos))
        return (self.data.xanchor[self.hinge_joint_ids].copy(), self.data.xaxis[self.hinge_joint_ids].copy())

    def random_qpos(self, rng: np.random.Generator, margin: float = 0.0) -> np.ndarray:
        """A qpos with hinges uniform within their ranges (shrunk by ``margin`` rad) and the rest root."""
        q = self.rest_qpos()
        q[ROOT_QPOS:] = rng.uniform(self.lower + margin, self.upper - margin)
        return q


def qpos_from_hinges(hinges: np.ndarray, root_pos=(0.0, 0.0, 0.0), root_quat=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """Assemble a (41,) qpos from 34 hinge angles and a root pose."""
    q = np.zeros(NQ)
    q[:3] = root_pos
    q[3:7] = root_quat
    q[ROOT_QPOS:] = hinges
    return q
