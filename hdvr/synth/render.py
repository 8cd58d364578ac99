"""Offscreen rendering of a scene (MuJoCo, ``MUJOCO_GL=egl`` on CPU) with per-keypoint visibility.

Per frame: an RGB image (``width`` x ``height``) from the scene camera ``cam``, and, when dancers' boxes overlap
(only then can one occlude another), a segmentation image at half resolution from which each projected
keypoint's visibility is read: 2 = visible, 1 = occluded by another dancer,
0 = outside the image or behind the camera. The half-resolution pixel under the projection decides: the own
dancer -> visible; another dancer -> occluded; scenery (a limb thinner than a pixel) -> visible unless the 3x3
neighbourhood shows another dancer and not this one. Keypoints are joint centres inside the body, so
self-occlusion is not occlusion (as in COCO / OpenPose annotation practice).

Cameras (:func:`random_camera_path`): pinhole with the principal point at the image centre (MuJoCo's camera
model), horizontal field of view 40-70 deg, placed at 3-8 m from the dancers' centre at 0.6-2.4 m height, any
azimuth, looking at the group; a hand-held shake (smooth random offsets of position and aim, ~1-3 cm, ~0.5 deg)
moves it per frame. World-to-camera ``P_cam = R (P_world - C)`` (:class:`hdvr.camera.Extrinsics`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from hdvr.camera import Extrinsics, Intrinsics, project  # noqa: E402

VISIBLE, OCCLUDED, OUTSIDE = 2, 1, 0


@dataclass
class CameraPath:
    """Per-frame camera: ``rotation`` (T, 3, 3), ``centre`` (T, 3) world metres, ``intrinsics`` (fixed)."""

    rotation: np.ndarray
    centre: np.ndarray
    intrinsics: Intrinsics

    def extrinsics(self, t: int) -> Extrinsics:
        return Extrinsics(self.rotation[t], self.centre[t])

    def to_camera(self, points_world: np.ndarray) -> np.ndarray:
        """(T, ..., 3) world -> camera frame, per frame."""
        p = np.asarray(points_world, dtype=np.float64)
        shape = p.shape
        flat = p.reshape(shape[0], -1, 3)
        out = np.einsum("tij,tnj->tni", self.rotation, flat - self.centre[:, None, :])
        return out.reshape(shape)


def _smooth_noise(rng, n, dims, scale, fps, hz=0.8):
    """Band-limited noise (T, dims): sum of a few random sinusoids below ``hz``."""
    t = np.arange(n) / fps
    out = np.zeros((n, dims))
    for _ in range(3):
        f = rng.uniform(0.15, hz, dims)
        out += np.sin(2 * np.pi * f * t[:, None] + rng.uniform(0, 2 * np.pi, dims))
    return out * scale / 3


def random_camera_path(rng: np.random.Generator, dancer_world_xy: np.ndarray, n_frames: int, fps: float,
                       size=(640, 480)) -> CameraPath:
    """A random camera for dancers whose horizontal positions are ``dancer_world_xy`` (T, N, 2)."""
    w, h = size
    intr = Intrinsics.default_for(w, h, fov_deg=float(rng.uniform(40, 70)))
    pts = dancer_world_xy.reshape(-1, 2)
    centre_xy = pts.mean(0)
    spread = float(np.max(np.linalg.norm(pts - centre_xy, axis=1))) if len(pts) else 0.5
    hfov = 2 * np.arctan(w / 2 / intr.focal)
    vfov = 2 * np.arctan(h / 2 / intr.focal)
    need = max((spread + 0.6) / np.tan(hfov / 2), 1.2 / np.tan(vfov / 2))  # fit the group and a 2.4 m height
    dist = float(np.clip(need * rng.uniform(1.0, 1.35), 3.0, 9.0))
    az = rng.uniform(0, 2 * np.pi)
    height = rng.uniform(0.6, 2.4)
    cam = np.array([centre_xy[0] + dist * np.cos(az), centre_xy[1] + dist * np.sin(az), height])
    target = np.array([centre_xy[0], centre_xy[1], rng.uniform(0.8, 1.1)])
    shake = rng.uniform(0.005, 0.03)
    pos_noise = _smooth_noise(rng, n_frames, 3, shake, fps, hz=1.5)
    aim_noise = _smooth_noise(rng, n_frames, 3, shake * dist * 0.3, fps, hz=1.0)
    cen = cam + pos_noise
    forward = target + aim_noise - cen
    forward /= np.linalg.norm(forward, axis=1, keepdims=True)
    right = np.cross(forward, np.array([0.0, 0.0, 1.0]))
    right /= np.linalg.norm(right, axis=1, keepdims=True)
    down = np.cross(forward, right)
    rot = np.stack([right, down, forward], axis=1)  # as hdvr.camera.look_at, batched
    return CameraPath(rot, cen, intr)


def _mj_cam_quat(rotation: np.ndarray) -> np.ndarray:
    """MuJoCo camera quaternion (looks along its -z, y up) for HDVR's world-to-camera ``rotation`` (x right,
    y down, z forward)."""
    right, down, forward = rotation
    mat = np.stack([right, -down, -forward], axis=1)  # columns: camera x, y, z axes in the world
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, mat.ravel())
    return q


class SceneRenderer:
    """Renders a compiled scene model; ``render(qpos, t_camera)`` -> (rgb (H, W, 3) uint8, dancer id map at half
    resolution (H/2, W/2) int16: dancer index or -1)."""

    def __init__(self, model: mujoco.MjModel, n_dancers: int, size=(640, 480)):
        self.model = model
        self.data = mujoco.MjData(model)
        self.width, self.height = size
        self.rgb = mujoco.Renderer(model, self.height, self.width)
        self.seg = mujoco.Renderer(model, self.height // 2, self.width // 2)
        self.seg.enable_segmentation_rendering()
        self.cam_id = model.camera("cam").id
        # geom id -> dancer index (-1 for scenery)
        self.geom_dancer = np.full(model.ngeom, -1, dtype=np.int16)
        for g in range(model.ngeom):
            name = model.geom(g).name
            if name.startswith("d") and "_" in name and name[1:name.index("_")].isdigit():
                self.geom_dancer[g] = int(name[1:name.index("_")])
        self.n_dancers = n_dancers

    def set_camera(self, rotation: np.ndarray, centre: np.ndarray, intr: Intrinsics) -> None:
        self.model.cam_pos[self.cam_id] = centre
        self.model.cam_quat[self.cam_id] = _mj_cam_quat(rotation)
        self.model.cam_fovy[self.cam_id] = np.degrees(2 * np.arctan(self.height / 2 / intr.focal))

    def render(self, qpos: np.ndarray, segmentation: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """RGB image and (when ``segmentation``) the half-resolution dancer id map."""
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)  # the moved camera's pose (cam_pos / cam_quat) into data
        self.rgb.update_scene(self.data, camera=self.cam_id)
        image = self.rgb.render()
        if not segmentation:
            return image, None
        self.seg.update_scene(self.data, camera=self.cam_id)
        s = self.seg.render()
        ids = np.where(s[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM), s[..., 0], -1)
        dancer = np.where(ids >= 0, self.geom_dancer[np.clip(ids, 0, None)], -1).astype(np.int16)
        return image, dancer

    def close(self) -> None:
        self.rgb.close()
        self.seg.close()


def boxes_overlap(boxes: np.ndarray) -> np.ndarray:
    """(N,) bool: whether each dancer's box (N, 4: x, y, w, h; NaN = none) overlaps another dancer's box. Only
    then can another dancer occlude its keypoints, so only then is the segmentation rendered."""
    n = boxes.shape[0]
    out = np.zeros(n, dtype=bool)
    for i in range(n):
        for j in range(i + 1, n):
            a, b = boxes[i], boxes[j]
            if not (np.isfinite(a).all() and np.isfinite(b).all()):
                continue
            if a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]:
                out[i] = out[j] = True
    return out


def keypoint_visibility(kp_cam: np.ndarray, dancer_map: np.ndarray | None, dancer: int, intr: Intrinsics,
                        size=(640, 480), radius: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """(uv (25, 2) pixels, visibility (25,) int8 in {0, 1, 2}) of one dancer's camera-frame keypoints."""
    w, h = size
    uv = project(kp_cam, intr.focal, intr.principal_point)
    vis = np.full(kp_cam.shape[0], OUTSIDE, dtype=np.int8)
    inside = np.isfinite(uv).all(1) & (uv[:, 0] >= 0) & (uv[:, 0] < w) & (uv[:, 1] >= 0) & (uv[:, 1] < h)
    if dancer_map is None:  # no other dancer can be in front: every keypoint in the image is visible
        vis[inside] = VISIBLE
        return uv, vis
    sh, sw = dancer_map.shape
    scale = sw / w
    for k in np.flatnonzero(inside):
        cx, cy = min(int(uv[k, 0] * scale), sw - 1), min(int(uv[k, 1] * scale), sh - 1)
        centre = dancer_map[cy, cx]
        if centre == dancer:
            vis[k] = VISIBLE
        elif centre >= 0:  # another dancer's surface is in front of this joint
            vis[k] = OCCLUDED
        else:  # scenery at the centre pixel: a limb thinner than a pixel, unless another dancer surrounds it
            patch = dancer_map[max(cy - radius, 0):cy + radius + 1, max(cx - radius, 0):cx + radius + 1]
            vis[k] = VISIBLE if (patch == dancer).any() or not (patch >= 0).any() else OCCLUDED
    return uv, vis


def keypoint_boxes(uv: np.ndarray, kp_cam: np.ndarray, present: np.ndarray, intr: Intrinsics, size=(640, 480),
                   margin_m: float = 0.12) -> np.ndarray:
    """Amodal boxes (..., 4) = x, y, w, h pixels around projected keypoints uv (..., 25, 2), grown by ``margin_m``
    at each keypoint's depth (body radius), clipped to the image; NaN where ``present`` (...,) is False or the
    box is empty."""
    ok = np.isfinite(uv).all(-1)
    pad = np.where(ok, intr.focal * margin_m / np.maximum(kp_cam[..., 2], 0.1), 0.0)
    big = np.where(ok[..., None], uv, np.nan)
    x0 = np.nanmin(np.where(ok, big[..., 0] - pad, np.inf), axis=-1)
    x1 = np.nanmax(np.where(ok, big[..., 0] + pad, -np.inf), axis=-1)
    y0 = np.nanmin(np.where(ok, big[..., 1] - pad, np.inf), axis=-1)
    y1 = np.nanmax(np.where(ok, big[..., 1] + pad, -np.inf), axis=-1)
    w, h = size
    x0, x1 = np.clip(x0, 0, w), np.clip(x1, 0, w)
    y0, y1 = np.clip(y0, 0, h), np.clip(y1, 0, h)
    boxes = np.stack([x0, y0, x1 - x0, y1 - y0], axis=-1)
    valid = present & ok.any(-1) & (boxes[..., 2] >= 1) & (boxes[..., 3] >= 1)
    return np.where(valid[..., None], boxes, np.nan)
