"""The forward model G for fitting: MuJoCo FK, keypoint Jacobians (mj_jacSite) and bone-length Jacobians.

Fitting parameters of one frame (the *tangent* vector, 40 values): root translation (3, metres, in the fitting
frame), root rotation increment (3, radians, rotation vector in the pelvis' local frame, applied on the right of
a reference quaternion: ``quat = quat_ref * exp(r)``), and the 34 hinge angles (radians, DH-row order).

The fitting frame is whatever frame the root pose is expressed in; :mod:`hdvr.fitting.sequence` fits directly
in the camera frame (x right, y down, z forward) and moves the result to the floor world at the end.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from hdvr.skeleton import NQ, ROOT_QPOS, Skeleton

NUM_TANGENT = 40  # 3 root translation + 3 root rotation + 34 hinges
NUM_BONES = 9


# ---------------------------------------------------------------------------------------------------------------
# Rotations (quaternions w, x, y, z).

def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions (..., 4)."""
    aw, ax, ay, az = np.moveaxis(np.asarray(a, dtype=np.float64), -1, 0)
    bw, bx, by, bz = np.moveaxis(np.asarray(b, dtype=np.float64), -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def quat_from_rotvec(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (..., 4) of rotation vector(s) ``r`` (..., 3) radians."""
    r = np.asarray(r, dtype=np.float64)
    angle = np.linalg.norm(r, axis=-1, keepdims=True)
    half = 0.5 * angle
    small = angle < 1e-8
    scale = np.where(small, 0.5 - angle ** 2 / 48.0, np.sin(half) / np.where(small, 1.0, angle))
    return np.concatenate([np.cos(half), scale * r], axis=-1)


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix (..., 3, 3) of unit quaternion(s) (..., 4)."""
    q = np.asarray(q, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)], axis=-2)


def quat_from_matrix(m: np.ndarray) -> np.ndarray:
    """Unit quaternion (4,) (w >= 0) of a rotation matrix (3, 3)."""
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(m, dtype=np.float64).reshape(9))
    return q if q[0] >= 0 else -q


def skew(v: np.ndarray) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def right_jacobian_so3(r: np.ndarray) -> np.ndarray:
    """Right Jacobian of SO(3) at rotation vector ``r`` (3,): body angular velocity = J_r(r) dr/dt."""
    angle = math.sqrt(float(r[0]) ** 2 + float(r[1]) ** 2 + float(r[2]) ** 2)
    k = skew(r)
    if angle < 1e-6:
        return np.eye(3) - 0.5 * k + k @ k / 6.0
    return (np.eye(3) - (1 - math.cos(angle)) / angle ** 2 * k
            + (angle - math.sin(angle)) / angle ** 3 * k @ k)


def qpos_from_tangent(x: np.ndarray, quat_ref: np.ndarray) -> np.ndarray:
    """(41,) qpos from a tangent vector ``x`` (40,) and the reference root quaternion (4,).

    The root quaternion is ``quat_ref * exp(r)`` with r = x[3:6] in the pelvis' local frame (``mju_quatIntegrate``).
    """
    q = np.empty(NQ)
    q[:3] = x[:3]
    quat = np.array(quat_ref, dtype=np.float64)
    r = np.ascontiguousarray(x[3:6], dtype=np.float64)
    if r.any():
        mujoco.mju_quatIntegrate(quat, r, 1.0)
    q[3:7] = quat
    q[ROOT_QPOS:] = x[6:]
    return q


def tangent_from_qpos(qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(tangent (40,), quat_ref (4,)) with zero rotation increment: the inverse of :func:`qpos_from_tangent`."""
    x = np.zeros(NUM_TANGENT)
    x[:3] = qpos[:3]
    x[6:] = qpos[ROOT_QPOS:]
    quat = np.asarray(qpos[3:7], dtype=np.float64)
    return x, quat / np.linalg.norm(quat)


# ---------------------------------------------------------------------------------------------------------------


class DancerKinematics:
    """Keypoints and their derivatives for a :class:`Skeleton` (BODY_25 sites, fitting-frame metres)."""

    def __init__(self, skeleton: Skeleton):
        self.skeleton = skeleton
        self.model = skeleton.model
        self.data = mujoco.MjData(self.model)
        self.site_ids = skeleton.keypoint_site_ids
        self._jac = np.empty((len(self.site_ids), 3, self.model.nv))
        self._build_bone_maps()

    # bones ------------------------------------------------------------------------------------------------------
    @property
    def bone_lengths(self) -> np.ndarray:
        return self.skeleton.bone_lengths

    def set_bone_lengths(self, bones_m: np.ndarray) -> None:
        self.skeleton.set_bone_lengths(bones_m)

    def _build_bone_maps(self) -> None:
        """Body and site offsets are linear in the bone lengths (checked in tests): store d(offset)/d(bone)."""
        m = self.model
        base = self.skeleton.bone_lengths
        m0_body, m0_site = m.body_pos.copy(), m.site_pos.copy()
        self._dbody = np.zeros((NUM_BONES, m.nbody, 3))
        self._dsite = np.zeros((NUM_BONES, len(self.site_ids), 3))
        for k in range(NUM_BONES):
            bumped = base.copy()
            bumped[k] += 1.0
            self.skeleton.set_bone_lengths(bumped)
            self._dbody[k] = m.body_pos - m0_body
            self._dsite[k] = (m.site_pos - m0_site)[self.site_ids]
        self.skeleton.set_bone_lengths(base)
        self._dbody[:, 1] = 0.0  # the pelvis position is the free joint's, not an offset
        # ancestors[s, b] = 1 if body b (not the pelvis) lies on the path from keypoint s's body to the root
        parent = m.body_parentid
        self._parent = parent
        self._ancestors = np.zeros((len(self.site_ids), m.nbody))
        for s, sid in enumerate(self.site_ids):
            b = m.site_bodyid[sid]
            while b > 1:
                self._ancestors[s, b] = 1.0
                b = parent[b]
        self._site_body = m.site_bodyid[self.site_ids]

    # evaluation -------------------------------------------------------------------------------------------------
    def keypoints(self, qpos: np.ndarray) -> np.ndarray:
        """(25, 3) keypoints (fitting-frame metres) for one qpos (41,)."""
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        return self.data.site_xpos[self.site_ids].copy()

    def keypoints_batch(self, qpos: np.ndarray) -> np.ndarray:
        """(T, 25, 3) keypoints for qpos (T, 41)."""
        out = np.empty((qpos.shape[0], len(self.site_ids), 3))
        for t in range(qpos.shape[0]):
            out[t] = self.keypoints(qpos[t])
        return out

    def keypoints_and_jacobian(self, qpos: np.ndarray, quat_increment: np.ndarray | None = None
                               ) -> tuple[np.ndarray, np.ndarray]:
        """Keypoints (25, 3) and d(keypoints)/d(tangent) (25, 3, 40) at ``qpos`` (41,).

        ``quat_increment``: the rotation vector r of the tangent (default 0); the root-rotation columns are
        chained with the right Jacobian of SO(3) so that they are exact derivatives with respect to r.
        """
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)
        jac = self._jac
        for k, sid in enumerate(self.site_ids):
            mujoco.mj_jacSite(self.model, self.data, jac[k], None, sid)
        out = jac.copy()
        if quat_increment is not None and np.any(quat_increment):
            out[:, :, 3:6] = out[:, :, 3:6] @ right_jacobian_so3(quat_increment)
        return self.data.site_xpos[self.site_ids].copy(), out

    def bone_jacobian(self) -> np.ndarray:
        """d(keypoints)/d(bone lengths) (25, 3, 9) at the configuration of the last evaluation."""
        xmat = self.data.xmat.reshape(-1, 3, 3)
        # moving body b's offset moves b and its subtree by R_parent(b) @ d offset
        body_term = np.einsum("bij,kbj->kbi", xmat[self._parent], self._dbody)  # (9, nbody, 3)
        through_bodies = np.einsum("sb,kbi->ski", self._ancestors, body_term)  # (25, 9, 3)
        site_term = np.einsum("sij,ksj->ski", xmat[self._site_body], self._dsite)  # (25, 9, 3)
        return np.transpose(through_bodies + site_term, (0, 2, 1))
