"""Pinhole camera: the paper's perspective projection Psi(P; omega) with omega = {f, c}.

Camera frame: x right, y down, z forward (optical axis), metres; origin at the optical centre. Image: pixels,
origin at the top-left corner, u right, v down. A camera-frame point (X, Y, Z) with Z > 0 projects to
``u = f X / Z + c_x``, ``v = f Y / Z + c_y`` (square pixels, no skew, no distortion).

World-to-camera: ``P_cam = R (P_world - C)`` with ``R`` (3, 3) rotating world vectors into the camera frame and
``C`` the camera centre in the world (metres). :func:`look_at` builds one for HDVR's world (z up).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.errors import HDVRError

MIN_DEPTH_M = 1e-6


@dataclass
class Intrinsics:
    """omega = {f, c}: focal length (pixels) and principal point (pixels); image size (width, height) pixels."""

    focal: float
    principal_point: tuple[float, float]
    image_size: tuple[int, int] | None = None

    @classmethod
    def default_for(cls, width: int, height: int, fov_deg: float = 55.0) -> "Intrinsics":
        """A guess for an unknown camera: principal point at the centre, horizontal field of view ``fov_deg``."""
        focal = 0.5 * width / np.tan(np.deg2rad(fov_deg) / 2)
        return cls(float(focal), (width / 2.0, height / 2.0), (int(width), int(height)))

    def matrix(self) -> np.ndarray:
        """The 3x3 intrinsic matrix K."""
        cx, cy = self.principal_point
        return np.array([[self.focal, 0.0, cx], [0.0, self.focal, cy], [0.0, 0.0, 1.0]])


def project(points_cam: np.ndarray, focal, principal_point) -> np.ndarray:
    """Project camera-frame points (..., 3) metres to pixels (..., 2).

    ``focal`` is a scalar or broadcastable array (...,); ``principal_point`` (2,) or (..., 2). Points at or behind
    the camera (Z <= 1e-6 m) project to NaN.
    """
    p = np.asarray(points_cam, dtype=np.float64)
    if p.shape[-1] != 3:
        raise HDVRError(f"points must end with 3 coordinates (X, Y, Z metres), got shape {p.shape}")
    f = np.asarray(focal, dtype=np.float64)[..., None]
    c = np.asarray(principal_point, dtype=np.float64)
    z = p[..., 2:3]
    safe = np.where(z > MIN_DEPTH_M, z, np.nan)
    return f * p[..., :2] / safe + c


def projection_jacobian(points_cam: np.ndarray, focal) -> np.ndarray:
    """d(u, v)/d(X, Y, Z) for camera-frame points (..., 3) -> (..., 2, 3), pixels per metre."""
    p = np.asarray(points_cam, dtype=np.float64)
    f = np.asarray(focal, dtype=np.float64)
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    inv = 1.0 / z
    jac = np.zeros(p.shape[:-1] + (2, 3))
    jac[..., 0, 0] = f * inv
    jac[..., 0, 2] = -f * x * inv * inv
    jac[..., 1, 1] = f * inv
    jac[..., 1, 2] = -f * y * inv * inv
    return jac


@dataclass
class Extrinsics:
    """World-to-camera transform: ``P_cam = rotation @ (P_world - centre)``; metres."""

    rotation: np.ndarray  # (3, 3)
    centre: np.ndarray  # (3,) world metres

    def to_camera(self, points_world: np.ndarray) -> np.ndarray:
        return (np.asarray(points_world, dtype=np.float64) - self.centre) @ self.rotation.T

    def to_world(self, points_cam: np.ndarray) -> np.ndarray:
        return np.asarray(points_cam, dtype=np.float64) @ self.rotation + self.centre


def look_at(centre, target, world_up=(0.0, 0.0, 1.0)) -> Extrinsics:
    """A camera at ``centre`` (world metres) looking at ``target``, image 'up' along ``world_up`` (z up in HDVR)."""
    centre = np.asarray(centre, dtype=np.float64)
    forward = np.asarray(target, dtype=np.float64) - centre
    norm = np.linalg.norm(forward)
    if norm < 1e-9:
        raise HDVRError("camera centre and target coincide")
    forward /= norm
    right = np.cross(forward, np.asarray(world_up, dtype=np.float64))
    if np.linalg.norm(right) < 1e-9:
        raise HDVRError("camera looks straight along the up direction; choose another target")
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return Extrinsics(np.stack([right, down, forward]), centre)


def orbit_camera(distance_m: float, azimuth_deg: float, elevation_deg: float, target=(0.0, 0.0, 1.0)) -> Extrinsics:
    """A camera on a sphere around ``target``: azimuth 0 looks at a dancer facing +x from the front."""
    az, el = np.deg2rad(azimuth_deg), np.deg2rad(elevation_deg)
    target = np.asarray(target, dtype=np.float64)
    offset = distance_m * np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    return look_at(target + offset, target)
