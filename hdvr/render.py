"""Offscreen rendering of the single dancer model (headless: ``MUJOCO_GL=egl``), for the demo and docs pictures.

Multi-dancer scenes with ground truth are built by :mod:`hdvr.synth`; this module renders one
:class:`hdvr.skeleton.Skeleton` from an orbiting free camera. Images are uint8 RGB (H, W, 3).
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from hdvr.errors import HDVRError  # noqa: E402


class DancerRenderer:
    """Renders a skeleton's model at ``width`` x ``height`` pixels from an orbit camera (degrees, metres)."""

    def __init__(self, skeleton, width: int = 640, height: int = 480, shadows: bool = True):
        self.skeleton = skeleton
        model = skeleton.model
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        try:
            self.renderer = mujoco.Renderer(model, height=height, width=width)
        except Exception as exc:  # no GL context: missing EGL/OSMesa libraries
            raise HDVRError(f"cannot create an offscreen renderer ({exc}); set MUJOCO_GL=egl or osmesa") from None
        self.data = mujoco.MjData(model)
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.distance, self.camera.azimuth, self.camera.elevation = 3.2, 160.0, -12.0
        self.camera.lookat[:] = (0.0, 0.0, 0.7)
        self.options = mujoco.MjvOption()
        self.shadows = shadows

    def set_camera(self, distance: float | None = None, azimuth: float | None = None,
                   elevation: float | None = None, lookat=None) -> None:
        if distance is not None:
            self.camera.distance = distance
        if azimuth is not None:
            self.camera.azimuth = azimuth
        if elevation is not None:
            self.camera.elevation = elevation
        if lookat is not None:
            self.camera.lookat[:] = lookat

    def render(self, qpos: np.ndarray, show_keypoints: bool = False) -> np.ndarray:
        """RGB image (H, W, 3) uint8 of the dancer at ``qpos`` (41,)."""
        self.data.qpos[:] = qpos
        mujoco.mj_forward(self.skeleton.model, self.data)
        self.options.sitegroup[3] = 1 if show_keypoints else 0
        self.renderer.update_scene(self.data, camera=self.camera, scene_option=self.options)
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.shadows
        return self.renderer.render().copy()

    def close(self) -> None:
        self.renderer.close()


def joint_sweep(skeleton, seconds_per_group: float = 1.0, fps: float = 30.0) -> tuple[np.ndarray, list[str]]:
    """A motion that moves each hinge (left/right pairs together) from rest to its minimum, maximum and back.

    Returns qpos (T, 41) and, per frame, the name of the joint group moving.
    """
    from hdvr import dh

    groups: list[list[int]] = []
    seen = set()
    for j in dh.JOINTS:
        if j.row in seen:
            continue
        twin = j.name.replace("left_", "right_") if j.name.startswith("left_") else \
            j.name.replace("right_", "left_") if j.name.startswith("right_") else None
        rows = [j.row] + ([dh.JOINT_NAMES.index(twin)] if twin in dh.JOINT_NAMES else [])
        seen.update(rows)
        groups.append(rows)
    n = max(int(round(seconds_per_group * fps)), 4)
    s = np.linspace(0.0, 1.0, n)
    # rest -> min -> max -> rest, smooth (cosine) in each quarter
    frames, labels = [], []
    rest = skeleton.rest_qpos()
    for rows in groups:
        lo, hi, r0 = skeleton.lower[rows], skeleton.upper[rows], rest[7 + np.array(rows)]
        keys = np.stack([r0, lo, hi, r0])
        for u in s:
            seg = min(int(u * 3), 2)
            w = 0.5 - 0.5 * np.cos(np.pi * (u * 3 - seg))
            q = rest.copy()
            q[7 + np.array(rows)] = (1 - w) * keys[seg] + w * keys[seg + 1]
            frames.append(q)
            labels.append(dh.JOINT_NAMES[rows[0]].replace("left_", "").replace("right_", ""))
    return np.stack(frames), labels
