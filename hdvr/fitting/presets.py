"""Fitting settings: one dataclass, the ``--paper`` preset (Algorithm 3* as published) and HDVR's defaults."""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES


FACE_NAMES = ("nose", "right_eye", "left_eye", "right_ear", "left_ear")


def default_joint_weights(face: float = 0.05, feet: float = 0.1) -> np.ndarray:
    """(25,) weight of each BODY_25 keypoint in the reprojection term: face ``face``, toes/heels ``feet``, rest 1.

    The model's face and foot sites are coarse (a sphere head, a capsule foot): fitting them as tightly as the
    limbs bends the body in depth to absorb their mismatch (measured on the mocap benchmark: from 22 to 35 mm
    per-frame error from the true pose), so they only steer the head and feet.
    """
    w = np.ones(len(BODY25_NAMES))
    for j, name in enumerate(BODY25_NAMES):
        if name in FACE_NAMES:
            w[j] = face
        elif "toe" in name or "heel" in name:
            w[j] = feet
    return w


@dataclass
class FitSettings:
    """How ``fit3d`` fits the dancer. Units: pixels for image quantities, metres for 3D, radians for angles."""

    delta: int = 3  # window half-width: windows of 2 delta + 1 frames
    seeds: int = 2  # K seeds per window; the one with the least window error wins
    stride: int | None = None  # frames between window starts; None = 2 delta + 1 (each frame solved once)
    focal: float | None = None  # pixels; None = estimated
    principal_point: tuple[float, float] | None = None  # pixels; None = image centre
    height_m: float = 1.70  # dancer stature (fixes the monocular scale)
    # -- what HDVR adds to the paper --------------------------------------------------------------------------
    calibrate: bool = True  # first pass: one bone-length set (and focal) per dancer from a frame subsample
    bone_method: str = "projection"  # "projection" (longest image lengths) or "least_squares" (joint fit)
    calibration_frames: int = 30
    calibration_rounds: int = 3
    seed_strategy: str = "mirror"  # "mirror": warm start + mirrored-limb seeds; "random": the paper's seeds
    focal_per_window: bool = False  # the paper: omega optimised per frame and averaged over the window
    reinit_px: float = 3.0  # re-initialise a window whose mean reprojection error exceeds this (px) ...
    reinit_factor: float = 1.3  # ... and this times the 25th percentile of the earlier windows
    fresh_iter: int = 10  # iterations per yaw and per mirror of a fresh start
    fresh_yaws: int = 8  # upright orientations a fresh start tries
    fresh_flips: bool = False  # a fresh start also tries every segment mirror (measured: no gain, 2x cost)
    limb_depth: bool = True  # each arm's depth branch chosen for the whole clip (hdvr.fitting.limb_depth)
    refine_sweeps: int = 3  # sequence-level refinement sweeps (second-difference smoothness, no seams)
    robust_px: float | None = 20.0  # Cauchy scale of the reprojection loss; None = plain least squares
    sigma_px: float = 1.0
    min_confidence: float = 0.05
    smooth_2d: str = "auto"  # 2D tracks smoothed in time: "auto" (jitter > smooth_2d_min_px), "on" or "off"
    smooth_2d_min_px: float = 2.5  # estimated keypoint jitter (px) above which "auto" smooths
    smooth_2d_window: int = 7  # frames of the Savitzky-Golay filter (local quadratic)
    face_weight: float = 0.05  # reprojection weight of nose, eyes, ears (limbs and trunk: 1)
    foot_weight: float = 0.1  # reprojection weight of toes and heels
    # -- constraints (ablation switches) ----------------------------------------------------------------------
    joint_limits: bool = True  # hard box bounds on the 34 hinges
    joint_ranges: str = "anatomical"  # "anatomical" (paper's, widened where too narrow) or "paper"
    bone_prior: bool = True  # one bone-length set per dancer, with the table's mean +- std prior
    temporal: bool = True  # temporal smoothness of 2D and 3D poses
    physics: bool = False  # floor penetration and foot skating residuals in the refinement
    # -- weights (residual = weight * quantity) --------------------------------------------------------------
    velocity_weight_3d: float = 0.0  # per metre of keypoint motion between frames (paper: beta alpha)
    velocity_weight_2d: float = 0.0  # per pixel (paper: alpha)
    acceleration_weight_3d: float = 20.0  # per metre of second difference
    hinge_velocity_weight: float = 2.0  # per radian between frames
    penetration_weight: float = 3000.0  # per metre below the floor
    skate_weight: float = 100.0  # per metre of sliding while in contact
    pose_prior_weight: float = 3.0  # learned hinge prior (hdvr.fitting.prior), per unit Mahalanobis; 0 = off
    pose_prior_path: str | None = None  # a shipped prior's name (hdvr.fitting.prior.NAMED_PRIORS) or an NPZ; None: all
    upright_weight: float = 64.0  # trunk tilt prior (residuals.UprightTerm), per unit sine of tilt; 0 = off
    upright_robust_deg: float | None = 30.0  # tilt (degrees) beyond which the tilt prior gives way (Cauchy)
    bone_prior_weight: float = 1.0  # multiplies (b - mean h) / (std h)
    focal_prior_sigma: float = 0.7  # std of log focal around the field-of-view guess
    max_iter: int = 8
    refine_iter: int = 3
    random_seed: int = 0
    # -- execution (results depend on chunk_frames, never on workers) -----------------------------------------
    chunk_frames: int = 900  # clips longer than 1.5 chunks are fitted in overlapping chunks (hdvr.fitting.chunks)
    workers: int | None = None  # processes fitting chunks at once; None = the CPU cores available

    def __post_init__(self) -> None:
        if self.delta < 0 or self.seeds < 1:
            raise HDVRError(f"delta must be >= 0 and seeds >= 1, got delta={self.delta}, seeds={self.seeds}")
        if self.stride is not None and self.stride < 1:
            raise HDVRError(f"stride must be >= 1, got {self.stride}")
        if self.focal is not None and not (np.isfinite(self.focal) and self.focal > 0):
            raise HDVRError(f"focal must be a positive number of pixels, got {self.focal}")
        if not (np.isfinite(self.height_m) and 0.5 < self.height_m < 2.6):
            raise HDVRError(f"height must be between 0.5 and 2.6 m, got {self.height_m}")
        if self.smooth_2d not in ("auto", "on", "off"):
            raise HDVRError(f"smooth_2d must be 'auto', 'on' or 'off', got {self.smooth_2d!r}")
        if self.smooth_2d_window < 3 or self.smooth_2d_window % 2 == 0:
            raise HDVRError(f"smooth_2d_window must be an odd number of frames >= 3, got {self.smooth_2d_window}")
        if self.seed_strategy not in ("mirror", "random"):
            raise HDVRError(f"seed strategy must be 'mirror' or 'random', got {self.seed_strategy!r}")

    @property
    def window(self) -> int:
        return 2 * self.delta + 1

    @property
    def window_stride(self) -> int:
        return self.stride if self.stride is not None else self.window

    def to_dict(self) -> dict:
        return asdict(self)


def paper_settings(**overrides) -> FitSettings:
    """Algorithm 3* as published: a window centred on every frame (Delta = 3), K = 2 random seeds of the joint
    angles (within bounds) and bone lengths (mean +- std), omega = {f, c} per frame averaged over the window,
    first-difference 2D/3D smoothness; no per-dancer calibration, no refinement, plain squared error.
    (The paper's optimiser, Adam for 50 epochs, is replaced by the box-bounded Levenberg-Marquardt solver.)"""
    base = FitSettings(stride=1, calibrate=False, joint_ranges="paper", reinit_px=1e9, seed_strategy="random",
                       focal_per_window=True, face_weight=1.0, foot_weight=1.0, refine_sweeps=0, robust_px=None,
                       bone_prior=False, acceleration_weight_3d=0.0, velocity_weight_3d=20.0, velocity_weight_2d=0.05,
                       hinge_velocity_weight=0.0, max_iter=10, pose_prior_weight=0.0, upright_weight=0.0,
                       limb_depth=False, smooth_2d="off")
    return replace(base, **overrides)


PRESETS = {"hdvr": FitSettings, "paper": paper_settings}
