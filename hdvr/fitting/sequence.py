"""The whole clip: calibration, windowed fit, sequence-level refinement, floor and camera pose, Result3D.

Pipeline of :func:`fit_keypoints`:

1. 2D keypoints to BODY_25; weights = detector confidence (0 below ``min_confidence``) x joint weight; tracks
   smoothed in time when the clip's estimated jitter exceeds ``smooth_2d_min_px`` (:mod:`hdvr.fitting.smoothing`).
2. Intrinsics: given, or a field-of-view guess refined in step 3.
3. Per-dancer calibration (``calibrate``, :func:`calibrate_dancer`): a quick one-seed track of the first
   ``CALIBRATION_SPAN`` frames with the table's mean bones scaled to the stature gives one bone-length set (and
   focal) shared by the clip (:mod:`hdvr.fitting.calibration`); a second quick track with those bones gives the
   clip's vertical for the trunk tilt prior (:func:`clip_vertical`).
4. The windowed fit of :mod:`hdvr.fitting.window` (Algorithm 3* or HDVR's schedule); then (``limb_depth``) each
   arm's depth branch chosen for the whole clip (:mod:`hdvr.fitting.limb_depth`), changed frames re-solved; the
   choice is made again before the last refinement sweep, on the refined poses.
5. Refinement (``refine_sweeps``): Gauss-Seidel sweeps over the clip, each frame re-solved against its fixed
   neighbours with second differences on both sides (so windows leave no seams) and, with ``physics``, floor
   penetration and foot-skating terms for the floor estimated from the unrefined fit.
   Steps 4-5 run per chunk of ``chunk_frames`` frames, chunks in parallel worker processes, stitched where
   neighbouring chunks agree and re-refined around each seam (:mod:`hdvr.fitting.chunks`).
6. Floor plane and camera pose (:mod:`hdvr.fitting.floor`); qpos re-expressed in the floor world.

Memory: per-frame arrays only (qpos, keypoints, focal), O(T) with ~1 kB per frame; every solve is one frame.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from hdvr.errors import HDVRError
from hdvr.fitting.blas import single_threaded_blas
from hdvr.fitting.chunks import chunk_spans, run_chunks, seam_frame
from hdvr.fitting.calibration import bones_from_projections, calibrate_from_poses, stature_scaled_bones
from hdvr.fitting.floor import Floor, camera_pose_in_world, estimate_floor, qpos_to_world
from hdvr.fitting.intrinsics import initial_intrinsics
from hdvr.fitting.kinematics import DancerKinematics
from hdvr.fitting.limb_depth import BranchCosts, arm_targets
from hdvr.fitting.limits import apply_ranges
from hdvr.fitting.presets import FitSettings, default_joint_weights
from hdvr.fitting.residuals import FOOT_KEYPOINTS, FloorTerms, LinearTerm
from hdvr.fitting.seeds import TARGET_WEIGHT
from hdvr.fitting.smoothing import adaptive_smooth
from hdvr.fitting.window import Track, WindowFitter
from hdvr.io.keypoints2d import Keypoints2D
from hdvr.io.result3d import Result3D
from hdvr.layouts import BODY25_NAMES
from hdvr.progress import progress
from hdvr.skeleton import Skeleton

CALIBRATION_SPAN = 300  # frames of the quick calibration track (10 s at 30 fps)
SEAM_REFINE = 6  # frames each side of a chunk seam that are re-solved after stitching


@dataclass
class FitReport:
    """What a fit produced besides the poses: timings (s), calibration, floor, diagnostics."""

    frames: int = 0
    seconds: dict[str, float] = field(default_factory=dict)
    bone_lengths: np.ndarray | None = None
    focal: float | None = None
    focal_estimated: bool = False
    floor_contact_fraction: float = 0.0
    reinitialisations: int = 0
    arm_depth_frames: int = 0  # frame changes by the clip-level arm-depth choice, both rounds (hdvr.fitting.limb_depth)
    keypoint_noise_px: float = float("nan")  # estimated jitter of the 2D keypoints (hdvr.fitting.smoothing)
    smoothed_2d: bool = False  # whether the 2D tracks were smoothed before the fit

    @property
    def frames_per_second(self) -> float:
        total = sum(self.seconds.values())
        return float(self.frames / total) if total else 0.0


def observation_weights(kp: Keypoints2D, settings: FitSettings) -> tuple[np.ndarray, np.ndarray]:
    """(observed (T, 25, 2) pixels with NaN where missing, weights (T, 25)) from BODY_25 keypoints."""
    body = kp.to_body25()
    xy = body.keypoints[..., :2].astype(np.float64)
    conf = body.keypoints[..., 2].astype(np.float64)
    ok = (conf >= settings.min_confidence) & np.isfinite(xy).all(axis=-1)
    weights = np.where(ok, conf, 0.0) * default_joint_weights(settings.face_weight, settings.foot_weight)
    xy[~ok] = np.nan
    if not ok.any():
        raise HDVRError("no keypoint is visible (all missing or below the confidence threshold)")
    return xy, weights


def refine(fitter: WindowFitter, track: Track, settings: FitSettings, floor: Floor | None, desc: str = "refine",
           frames: range | None = None, sweeps: int | None = None, tick: Callable[[int], None] | None = None
           ) -> Track:
    """Gauss-Seidel sweeps: each frame re-solved with two-sided second differences (and floor terms).

    ``frames``: the frames to re-solve (default all; the others stay fixed and act as neighbours); ``sweeps``:
    default ``settings.refine_sweeps``; ``tick(k)``: progress callback (frames done)."""
    n = len(track.qpos)
    frames = range(n) if frames is None else range(max(0, frames.start), min(n, frames.stop))
    sweeps = settings.refine_sweeps if sweeps is None else sweeps
    for sweep in range(sweeps):
        with progress(total=len(frames), desc=f"{desc} {sweep + 1}/{sweeps}") as bar:
            for t in frames:
                prev = [j for j in (t - 1, t - 2) if j >= 0]
                nxt = [j for j in (t + 1, t + 2) if j < n]
                floor_terms = None
                if floor is not None and settings.physics:
                    floor_terms = FloorTerms(floor.normal, floor.offset, settings.penetration_weight,
                                             settings.skate_weight,
                                             track.keypoints[t - 1][FOOT_KEYPOINTS] if t > 0 else None)
                problem = fitter.problem(t, None, track.focal[t], [track.keypoints[j] for j in prev],
                                         [track.qpos[j] for j in prev], [track.keypoints[j] for j in nxt],
                                         [track.qpos[j] for j in nxt], floor=floor_terms)
                q, _, cost = fitter.solve(problem, track.qpos[t], track.focal[t], settings.refine_iter)
                track.qpos[t] = q
                track.keypoints[t] = fitter.kin.keypoints(q)
                track.cost[t] = cost
                bar.update(1)
                if tick is not None:
                    tick(1)
    return track


def repair_limb_depth(fitter: WindowFitter, track: Track, iterations: int = 6,
                      target_weight: float = TARGET_WEIGHT) -> int:
    """Move each arm to the depth branch chosen for the whole clip (:mod:`hdvr.fitting.limb_depth`): every frame
    whose branch changes is re-solved on its 2D keypoints plus 3D targets (``target_weight`` per metre) on the
    moved elbow / wrist and on their shoulder where it was, from its fitted pose; the refinement that follows
    settles them with their neighbours. Returns the number of frames re-solved."""
    targets, pinned = arm_targets(track.keypoints, BranchCosts())
    frames = np.flatnonzero(pinned.any(axis=1))
    for t in frames:
        problem = fitter.problem(t, None, track.focal[t], [], [])
        problem.terms3d = [LinearTerm(1.0, -targets[t], target_weight, pinned[t].astype(np.float64))]
        q, _, _ = fitter.solve(problem, track.qpos[t], track.focal[t], iterations)
        track.qpos[t] = q
        track.keypoints[t] = fitter.kin.keypoints(q)
    return len(frames)


def fit_chunked(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, focal: float, pp: np.ndarray,
                settings: FitSettings, estimate_focal: bool, vertical: np.ndarray | None = None
                ) -> tuple[Track, int, int]:
    """Windows + refinement over the whole clip, chunk by chunk (:mod:`hdvr.fitting.chunks`), stitched.

    Returns the track (camera frame), the number of re-initialised windows and the number of frames whose arm
    depth the clip-level choice changed (counted per chunk, overlaps included)."""
    n = len(obs)
    spans = chunk_spans(n, settings.chunk_frames)
    per_frame = 1 + max(settings.refine_sweeps, 0)

    def work(i: int, tick: Callable[[int], None]):
        c = spans[i]
        chunk_settings = replace(settings, random_seed=settings.random_seed + 7919 * i)
        fitter = WindowFitter(kin, obs[c.start:c.stop], weights[c.start:c.stop], focal, pp, chunk_settings,
                              estimate_focal, vertical)
        track = fitter.fit(tick=tick)
        changed = repair_limb_depth(fitter, track) if settings.limb_depth else 0
        if settings.refine_sweeps > 0:
            floor = estimate_floor(track.keypoints)
            # the arm depth is chosen again before the last sweep, on refined poses (same number of sweeps)
            again = int(settings.limb_depth and settings.refine_sweeps > 1)
            track = refine(fitter, track, settings, floor, sweeps=settings.refine_sweeps - again, tick=tick)
            if again:
                changed += repair_limb_depth(fitter, track)
                track = refine(fitter, track, settings, floor, desc="refine (after the second arm-depth choice)",
                               sweeps=1, tick=tick)
        return track, fitter.reinit_count, changed

    with progress(total=n * per_frame + sum(c.nominal_start - c.start for c in spans) * per_frame,
                  desc="fit3d") as bar:
        results = run_chunks(work, len(spans), resolve_workers(settings.workers), on_progress=bar.update)
    reinit = sum(r[1] for r in results)
    changed = sum(r[2] for r in results)
    if len(spans) == 1:
        return results[0][0], reinit, changed
    full = Track(np.zeros((n, 41)), np.zeros((n, 25, 3)), np.zeros(n), np.zeros(n), np.zeros((n, 9)))
    seams = []
    for c, (part, *_) in zip(spans, results):
        if c.start == 0:
            first = 0
        else:
            shared = slice(c.start, c.nominal_start)
            first = seam_frame(full.keypoints[shared], part.keypoints[:c.nominal_start - c.start], c.start)
            seams.append(first)
        for name in ("qpos", "keypoints", "focal", "cost", "bones"):
            getattr(full, name)[first:c.stop] = getattr(part, name)[first - c.start:]
    if settings.refine_sweeps > 0:  # smooth what is left of the step at each seam
        fitter = WindowFitter(kin, obs, weights, focal, pp, settings, estimate_focal, vertical)
        floor = estimate_floor(full.keypoints)
        for s in seams:
            refine(fitter, full, settings, floor, desc="seam", frames=range(s - SEAM_REFINE, s + SEAM_REFINE),
                   sweeps=settings.refine_sweeps + 1)
    return full, reinit, changed


def clip_vertical(keypoints_cam: np.ndarray, within_deg: float = 25.0, rounds: int = 3) -> np.ndarray:
    """The clip's up direction (3,) in the camera frame from a fitted track (T, 25, 3) metres: the mean
    mid-hip-to-neck direction, re-averaged ``rounds`` times over the frames within ``within_deg`` of it (dancers
    are upright most of the time; bows and leans do not pull the estimate)."""
    trunk = keypoints_cam[:, BODY25_NAMES.index("neck")] - keypoints_cam[:, BODY25_NAMES.index("mid_hip")]
    trunk = trunk / np.maximum(np.linalg.norm(trunk, axis=1, keepdims=True), 1e-9)
    trunk = trunk[np.isfinite(trunk).all(axis=1)]
    up = trunk.mean(axis=0)
    up /= np.linalg.norm(up)
    for _ in range(rounds):
        near = trunk @ up > np.cos(np.radians(within_deg))
        if near.sum() < 3:
            break
        up = trunk[near].mean(axis=0)
        up /= np.linalg.norm(up)
    return up


@dataclass
class Calibration:
    """One dancer's clip-level constants: focal (pixels), bone lengths (9,) metres (set on the kinematics), and
    the clip's up direction (3,) unit vector in the camera frame."""

    focal: float
    bone_lengths: np.ndarray
    vertical: np.ndarray


def calibrate_dancer(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, focal: float, pp: np.ndarray,
                     settings: FitSettings, estimate_focal: bool) -> Calibration:
    """Bone lengths (and the focal when estimated) from a quick one-seed track of the first ``CALIBRATION_SPAN``
    frames fitted with the stature-scaled table bones; then the clip's vertical from a second quick track fitted
    with the dancer's own bones. Sets the bones on ``kin``.

    The vertical is taken from the second track because the trunk's lean towards or away from the camera is
    what a monocular fit trades against the trunk's length: the first track, with table proportions, leans the
    trunk of a dancer whose trunk is shorter or longer than the table's (session 6, 14 salsa clips: vertical
    error 4.1 -> 3.2 deg on average, 17 -> 7 deg on the worst clip)."""
    span = min(len(obs), CALIBRATION_SPAN)
    quick = FitSettings(**{**settings.to_dict(), "seeds": 1, "refine_sweeps": 0, "focal_per_window": False})
    kin.set_bone_lengths(stature_scaled_bones(kin, settings.height_m))
    track0 = WindowFitter(kin, obs[:span], weights[:span], focal, pp, quick, False).fit(desc="calibrate")
    bones = bones_from_projections(kin, obs[:span], weights[:span], track0.keypoints, focal, settings.height_m)
    if estimate_focal or settings.bone_method == "least_squares":
        cal = calibrate_from_poses(kin, obs[:span], weights[:span], track0.qpos, focal, pp, estimate_focal,
                                   settings.height_m, frames=settings.calibration_frames,
                                   rounds=settings.calibration_rounds,
                                   bone_prior_weight=settings.bone_prior_weight,
                                   focal_prior_sigma=settings.focal_prior_sigma, robust_px=settings.robust_px,
                                   joint_limits=settings.joint_limits,
                                   fix_bones=settings.bone_method != "least_squares")
        focal = cal.focal
        bones = cal.bone_lengths
    kin.set_bone_lengths(bones)
    track1 = WindowFitter(kin, obs[:span], weights[:span], focal, pp, quick, False).fit(desc="calibrate (vertical)")
    return Calibration(float(focal), np.asarray(bones, dtype=np.float64), clip_vertical(track1.keypoints))


def resolve_workers(workers: int | None) -> int:
    """Worker processes for :func:`fit_chunked`: ``workers``, or the CPU cores this process may use."""
    if workers is not None:
        return max(1, int(workers))
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def fit_keypoints(kp: Keypoints2D, settings: FitSettings | None = None, skeleton: Skeleton | None = None
                  ) -> tuple[Result3D, FitReport]:
    """Fit the digital dancer to one dancer's 2D keypoints; returns the 3D result and a report."""
    with single_threaded_blas():
        return _fit_keypoints(kp, settings, skeleton)


def _fit_keypoints(kp: Keypoints2D, settings: FitSettings | None, skeleton: Skeleton | None
                   ) -> tuple[Result3D, FitReport]:
    settings = settings or FitSettings()
    report = FitReport()
    clock = time.perf_counter()
    raw_obs, weights = observation_weights(kp, settings)
    obs, report.keypoint_noise_px, report.smoothed_2d = adaptive_smooth(
        raw_obs, weights > 0, settings.smooth_2d_min_px, settings.smooth_2d_window, mode=settings.smooth_2d)
    n = len(obs)
    intr = initial_intrinsics(kp.image_size, settings.focal, settings.principal_point)
    estimate_focal = settings.focal is None
    skeleton = skeleton or Skeleton()
    apply_ranges(skeleton, settings.joint_ranges)
    kin = DancerKinematics(skeleton)
    kin.set_bone_lengths(stature_scaled_bones(kin, settings.height_m))
    focal = intr.focal
    pp = np.asarray(intr.principal_point)

    vertical = None
    if settings.calibrate:
        cal = calibrate_dancer(kin, obs, weights, focal, pp, settings, estimate_focal)
        focal, vertical = cal.focal, cal.vertical
    report.seconds["calibration"] = time.perf_counter() - clock

    clock = time.perf_counter()
    track, report.reinitialisations, report.arm_depth_frames = fit_chunked(kin, obs, weights, focal, pp, settings,
                                                                           estimate_focal, vertical)
    fitter = WindowFitter(kin, raw_obs, weights, focal, pp, settings, estimate_focal)  # errors vs the input
    floor = estimate_floor(track.keypoints)
    report.seconds["windows_and_refinement"] = time.perf_counter() - clock

    rotation, centre = camera_pose_in_world(floor, track.keypoints[0][BODY25_NAMES.index("mid_hip")])
    qpos_world = qpos_to_world(track.qpos, rotation, centre)
    errors = np.array([fitter.reprojection_px(range(t, t + 1), track.keypoints[t:t + 1], track.focal[t:t + 1])
                       for t in range(n)])
    report.frames = n
    report.bone_lengths = kin.bone_lengths
    report.focal = float(np.median(track.focal))
    report.focal_estimated = estimate_focal
    report.floor_contact_fraction = floor.contact_fraction
    meta = {"settings": settings.to_dict(), "focal_estimated": estimate_focal,
            "floor_contact_fraction": floor.contact_fraction, "reinitialisations": report.reinitialisations,
            "arm_depth_frames": report.arm_depth_frames,
            "keypoint_noise_px": report.keypoint_noise_px, "smoothed_2d": report.smoothed_2d,
            "seconds": dict(report.seconds)}
    result = Result3D(keypoints3d=track.keypoints, qpos=qpos_world, focal=track.focal,
                      principal_point=np.tile(pp, (n, 1)), bone_lengths=kin.bone_lengths,
                      reprojection_error_px=errors, fps=kp.fps, camera_rotation=rotation, camera_centre=centre,
                      meta=meta)
    return result, report
