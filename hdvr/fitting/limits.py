"""Joint ranges used by the fit.

``"paper"``: the model's ranges as shipped (:mod:`hdvr.dh`: the paper's tab:bounds plus anatomical limits for the
thetas it leaves open). ``"anatomical"`` (default): the same, widened where the paper's bound is narrower than
normal human range of motion, which real dance reaches (measured on the CMU salsa mocap: elbows flexed beyond 90
degrees in most frames; without the widening a mocap pose cannot be reproduced, and the fit bends other joints in
depth to compensate). Limit violations are reported against the ranges the fit used, and also against the
paper's.
"""

from __future__ import annotations

import numpy as np

from hdvr import dh
from hdvr.errors import HDVRError
from hdvr.skeleton import Skeleton

#: name -> (lower, upper, reason), radians, sign conventions of :data:`hdvr.dh.JOINTS`.
ANATOMICAL_WIDENING: dict[str, tuple[float, float, str]] = {
    "left_elbow_flex": (-np.deg2rad(150), 0.0, "elbow flexion 0-150 deg (paper: 0-90 deg)"),
    "right_elbow_flex": (-np.deg2rad(150), 0.0, "elbow flexion 0-150 deg (paper: 0-90 deg)"),
    "lumbar_flex": (-np.deg2rad(30), np.deg2rad(80), "trunk flexion 80 deg, extension 30 deg (paper: +-22.5 deg)"),
}
JOINT_RANGES = ("anatomical", "paper")


def fitting_ranges(kind: str = "anatomical") -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) (34,) radians for ``kind`` ("anatomical" or "paper")."""
    if kind not in JOINT_RANGES:
        raise HDVRError(f"joint ranges must be one of {JOINT_RANGES}, got {kind!r}")
    lower, upper = dh.LOWER.copy(), dh.UPPER.copy()
    if kind == "anatomical":
        for name, (lo, hi, _) in ANATOMICAL_WIDENING.items():
            j = dh.JOINT_NAMES.index(name)
            lower[j], upper[j] = min(lo, lower[j]), max(hi, upper[j])
    return lower, upper


def apply_ranges(skeleton: Skeleton, kind: str) -> None:
    """Set ``skeleton.lower/upper`` and the MuJoCo model's joint ranges to ``kind`` (this instance only)."""
    lower, upper = fitting_ranges(kind)
    skeleton.lower, skeleton.upper = lower, upper
    skeleton.model.jnt_range[skeleton.hinge_joint_ids, 0] = lower
    skeleton.model.jnt_range[skeleton.hinge_joint_ids, 1] = upper
