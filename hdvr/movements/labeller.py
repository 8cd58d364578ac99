"""Reference movement labeller: BODY_25 3D keypoints (T, 25, 3) -> one label per body part per frame + segments.

Works on any 3D source (mocap, fitted results, synthetic data), any stature, world or camera frame (give the
``up`` direction of that frame: world (0, 0, 1), HDVR camera frame roughly (0, -1, 0)).

Measures (all from keypoints; angles in radians, positions in metres):

- head: yaw / pitch of (nose - ear midpoint) in a neck frame (z = ear midpoint - neck, y = torso's left).
- neck: lateral / forward lean of (ear midpoint - neck) in the torso frame.
- shoulders: roll of the shoulder line in the pelvis frame (left shoulder height = +roll, right = -roll) and its
  twist (used only for circling).
- upper/lower arm: unit direction of the segment in the torso frame (x front, y left, z along the trunk).
- torso: flex / lean of the trunk axis in the pelvis frame, twist of the shoulder line against the hip line; the
  trunk's pitch in the world's vertical plane for somersaults.
- hips: mid-hip velocity in the pelvis heading frame (lateral, forward, up) integrated to a path; heading rate.
- upper/lower leg: unit direction of the segment in the pelvis frame; foot: ankle angle and roll.

Decision per part and frame (thresholds in ``movements.json``): speed of the motion components with hysteresis,
short gaps filled and short runs dropped -> moving; moving frames get the dominant velocity component's direction
label (or fast / turning / somersault), runs shorter than ``min_run_s`` merge into their neighbour; windowed
shape analysis turns moving runs into patterns (circle, oscillation, figure 8) or jitter (Unknown); still frames
get a hold / state / keeping-still label; frames with missing keypoints of the part are Unknown.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES
from hdvr.movements.taxonomy import Part, Taxonomy, load_taxonomy

J = {n: i for i, n in enumerate(BODY25_NAMES)}

#: Keypoints each part's measure reads (a NaN in one of them makes the part Unknown in that frame).
PART_KEYPOINTS = {
    "head": ("nose", "left_ear", "right_ear", "neck", "left_shoulder", "right_shoulder"),
    "neck": ("left_ear", "right_ear", "neck", "mid_hip", "left_shoulder", "right_shoulder"),
    "shoulders": ("left_shoulder", "right_shoulder", "left_hip", "right_hip"),
    "torso": ("neck", "mid_hip", "left_shoulder", "right_shoulder", "left_hip", "right_hip"),
    "hips": ("mid_hip", "left_hip", "right_hip"),
    "left_upper_arm": ("left_shoulder", "left_elbow", "neck", "mid_hip", "right_shoulder"),
    "right_upper_arm": ("right_shoulder", "right_elbow", "neck", "mid_hip", "left_shoulder"),
    "left_lower_arm": ("left_elbow", "left_wrist", "neck", "mid_hip", "left_shoulder", "right_shoulder"),
    "right_lower_arm": ("right_elbow", "right_wrist", "neck", "mid_hip", "left_shoulder", "right_shoulder"),
    "left_upper_leg": ("left_hip", "left_knee", "right_hip"),
    "right_upper_leg": ("right_hip", "right_knee", "left_hip"),
    "left_lower_leg": ("left_knee", "left_ankle", "left_hip", "right_hip"),
    "right_lower_leg": ("right_knee", "right_ankle", "left_hip", "right_hip"),
    "left_foot": ("left_heel", "left_big_toe", "left_small_toe", "left_ankle", "left_knee"),
    "right_foot": ("right_heel", "right_big_toe", "right_small_toe", "right_ankle", "right_knee"),
}


def _unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-9)


def _ortho(v, axis):
    """Unit part of ``v`` orthogonal to the unit ``axis``."""
    return _unit(v - (v * axis).sum(-1, keepdims=True) * axis)


def _dot(a, b):
    return (a * b).sum(-1)


def _in_frame(v, frame):
    x, y, z = frame
    return np.stack([_dot(v, x), _dot(v, y), _dot(v, z)], axis=-1)


@dataclass
class PartSignals:
    """What the labeller reads for one part: ``components`` (T, k) signals, ``names`` (k,), which are motion
    components, plus ``extra`` arrays (hold direction, foot angle, heading rate, somersault pitch)."""

    components: np.ndarray
    names: tuple[str, ...]
    motion: tuple[int, ...]
    extra: dict


def _head_angles(g: dict, y_t: np.ndarray):
    ear_mid = 0.5 * (g["left_ear"] + g["right_ear"])
    n = _unit(ear_mid - g["neck"])
    y_n = _ortho(y_t, n)
    f = _in_frame(g["nose"] - ear_mid, (np.cross(y_n, n), y_n, n))
    yaw = np.unwrap(np.arctan2(f[:, 1], f[:, 0]))
    pitch = np.arctan2(f[:, 2], np.hypot(f[:, 0], f[:, 1]))
    return yaw, pitch, n


def head_yaw(kp: np.ndarray) -> np.ndarray:
    """(T,) the head's yaw (rad) as the labeller measures it: nose - ear midpoint in the neck frame."""
    g = {n: kp[:, J[n]] for n in ("left_ear", "right_ear", "neck", "nose", "mid_hip", "left_shoulder",
                                  "right_shoulder")}
    z_t = _unit(g["neck"] - g["mid_hip"])
    return _head_angles(g, _ortho(g["left_shoulder"] - g["right_shoulder"], z_t))[0]


def body_signals(kp: np.ndarray, up=(0.0, 0.0, 1.0), flipping: np.ndarray | None = None) -> dict[str, PartSignals]:
    """Per-part signals from BODY_25 keypoints (T, 25, 3), NaN-free; ``up`` is the frame's vertical.

    The pelvis frame takes its z from ``up`` (three collinear hip points do not fix the pelvis' pitch); in the
    frames where ``flipping`` (T,) is True (a somersault) it takes it from the trunk instead, so that limbs are
    measured against the body while the body turns over."""
    T = kp.shape[0]
    up = np.broadcast_to(_unit(np.asarray(up, dtype=np.float64)), (T, 3))
    g = {n: kp[:, i] for n, i in J.items()}
    y_p = _unit(g["left_hip"] - g["right_hip"])
    z_t = _unit(g["neck"] - g["mid_hip"])
    z_p = _ortho(up, y_p)
    if flipping is not None and flipping.any():
        z_p = np.where(flipping[:, None], _ortho(z_t, y_p), z_p)
    pelvis = (np.cross(y_p, z_p), y_p, z_p)
    y_t = _ortho(g["left_shoulder"] - g["right_shoulder"], z_t)
    torso = (np.cross(y_t, z_t), y_t, z_t)
    out: dict[str, PartSignals] = {}

    yaw, pitch, n = _head_angles(g, y_t)
    out["head"] = PartSignals(np.stack([yaw, pitch], 1), ("yaw", "pitch"), (0, 1), {})
    nt = _in_frame(n, torso)
    out["neck"] = PartSignals(np.stack([np.arctan2(nt[:, 1], nt[:, 2]), np.arctan2(nt[:, 0], nt[:, 2])], 1),
                              ("lateral", "forward"), (0, 1), {})

    s = _in_frame(_unit(g["left_shoulder"] - g["right_shoulder"]), pelvis)
    roll = np.arcsin(np.clip(s[:, 2], -1, 1))
    twist = np.unwrap(np.arctan2(-s[:, 0], s[:, 1]))
    out["left_shoulder"] = PartSignals(np.stack([roll, twist], 1), ("height", "twist"), (0,), {})
    out["right_shoulder"] = PartSignals(np.stack([-roll, twist], 1), ("height", "twist"), (0,), {})

    t = _in_frame(z_t, pelvis)
    yt = _in_frame(y_t, pelvis)
    torso_twist = np.unwrap(np.arctan2(-yt[:, 0], yt[:, 1]))
    heading_y = _ortho(y_p, up)
    heading_x = np.cross(heading_y, up)
    trunk_pitch = np.unwrap(np.arctan2(_dot(z_t, heading_x), _dot(z_t, up)))
    out["torso"] = PartSignals(np.stack([np.arctan2(t[:, 0], t[:, 2]), np.arctan2(t[:, 1], t[:, 2]), torso_twist],
                                        1), ("flex", "lean", "twist"), (0, 1, 2), {"trunk_pitch": trunk_pitch})

    # hips: path of the mid-hip in the heading frame (integrated velocity), heading angle about up
    v = np.gradient(g["mid_hip"], axis=0) if T > 1 else np.zeros((T, 3))
    step = np.stack([_dot(v, heading_y), _dot(v, heading_x), _dot(v, up)], 1)
    path = np.cumsum(step, axis=0)
    ref = _ortho(np.broadcast_to(np.array([1.0, 0.0, 0.0]) if abs(up[0, 0]) < 0.9 else np.array([0.0, 1.0, 0.0]),
                                 (T, 3)), up)
    heading = np.unwrap(np.arctan2(_dot(np.cross(ref, heading_x), up), _dot(ref, heading_x)))
    out["hips"] = PartSignals(path, ("lateral", "forward", "up"), (0, 1, 2), {"heading": heading})

    for side in ("left", "right"):
        for seg, (a, b), frame in (("upper_arm", ("shoulder", "elbow"), torso), ("lower_arm", ("elbow", "wrist"), torso),
                                   ("upper_leg", ("hip", "knee"), pelvis), ("lower_leg", ("knee", "ankle"), pelvis)):
            d = _in_frame(_unit(g[f"{side}_{b}"] - g[f"{side}_{a}"]), frame)
            out[f"{side}_{seg}"] = PartSignals(d, ("x", "y", "z"), (0, 1, 2), {"direction": d})
        foot = _unit(g[f"{side}_big_toe"] - g[f"{side}_heel"])
        shank = _unit(g[f"{side}_knee"] - g[f"{side}_ankle"])
        angle = np.degrees(np.arccos(np.clip(_dot(foot, shank), -1, 1)))
        lateral = _ortho(g[f"{side}_small_toe"] - g[f"{side}_big_toe"], foot)  # across the sole
        # foot rolled on its edge: the line across the sole tilts against the shank (inversion / eversion); a
        # foot carried by a leg lifted sideways is not rolled, so the tilt is not measured against the vertical
        roll_deg = np.degrees(np.arcsin(np.clip(np.abs(_dot(lateral, shank)), 0, 1)))
        out[f"{side}_foot"] = PartSignals(np.zeros((T, 0)), (), (), {"angle_deg": angle, "roll_deg": roll_deg})
    return out


def _hysteresis(x: np.ndarray, on: float, off: float) -> np.ndarray:
    """True from where ``x > on`` until ``x <= off`` (state starts False); vectorised."""
    event = np.where(x > on, 1, np.where(x <= off, -1, 0))
    idx = np.where(event != 0, np.arange(x.shape[0]), -1)
    last = np.maximum.accumulate(idx)
    return np.where(last >= 0, event[np.clip(last, 0, None)] > 0, False)


def _runs(mask_or_labels: np.ndarray):
    """(start, end_exclusive, value) runs of equal values."""
    a = np.asarray(mask_or_labels)
    if a.size == 0:
        return []
    edges = np.flatnonzero(a[1:] != a[:-1]) + 1
    starts = np.r_[0, edges]
    ends = np.r_[edges, a.size]
    return [(int(s), int(e), a[s]) for s, e in zip(starts, ends)]


def _clean_mask(mask: np.ndarray, gap: int, min_run: int) -> np.ndarray:
    m = mask.copy()
    runs = _runs(m)
    for k, (s, e, v) in enumerate(runs):  # fill short gaps between moving runs
        if not v and 0 < k < len(runs) - 1 and e - s <= gap:
            m[s:e] = True
    for s, e, v in _runs(m):  # drop short moving runs
        if v and e - s < min_run:
            m[s:e] = False
    return m


def _merge_short(labels: np.ndarray, active: np.ndarray, min_run: int) -> np.ndarray:
    """Inside active stretches, replace label runs shorter than ``min_run`` by the longer neighbouring run."""
    out = labels.copy()
    for _ in range(3):
        runs = _runs(out)
        changed = False
        for k, (s, e, v) in enumerate(runs):
            if e - s >= min_run or not active[s]:
                continue
            left = runs[k - 1] if k > 0 and active[runs[k - 1][0]] else None
            right = runs[k + 1] if k + 1 < len(runs) and active[runs[k + 1][0]] else None
            pick = max((r for r in (left, right) if r is not None), key=lambda r: r[1] - r[0], default=None)
            if pick is not None:
                out[s:e] = pick[2]
                changed = True
        if not changed:
            break
    return out


def _reversals(x: np.ndarray, eps: float) -> int:
    d = np.diff(x)
    d = d[np.abs(d) > eps]
    return int(np.count_nonzero(np.sign(d[1:]) != np.sign(d[:-1]))) if d.size > 1 else 0


def classify_window(points: np.ndarray, fps: float, th: dict, amplitude_min: float) -> str | None:
    """Shape of a short stretch of a part's signal (n, k): ``circle``, ``figure8``, ``oscillation``, ``jitter``
    or None (no periodic shape: directional motion)."""
    n = points.shape[0]
    if n < 6:
        return None
    x = points - points.mean(0)
    if x.shape[1] == 1:
        x = np.concatenate([x, np.zeros_like(x)], 1)
    _, sv, vt = np.linalg.svd(x, full_matrices=False)
    z = x @ vt[:2].T
    s1, s2 = z.std(0) + 1e-12
    seconds = n / fps
    eps = 1e-4 * max(s1, 1e-6)
    n1 = _reversals(z[:, 0], eps)
    if n1 >= max(4, th["jitter_reversals_per_s"] * seconds) and s1 * np.sqrt(2) >= 0.25 * amplitude_min:
        return "jitter"
    if s1 * np.sqrt(2) < amplitude_min:
        return None
    ratio = s2 / s1
    if ratio >= 0.35:
        ang = np.unwrap(np.arctan2(z[:, 1] / s2, z[:, 0] / s1))
        dang = np.diff(ang)
        turns = abs(ang[-1] - ang[0]) / (2 * np.pi)
        monotone = max((dang > 0).mean(), (dang < 0).mean())
        if turns >= max(0.9, th["circle_turns_per_s"] * seconds) and monotone >= 0.8:
            return "circle"
    lo, hi = th["oscillation_reversals_per_s"]
    n2 = _reversals(z[:, 1], 1e-4 * max(s2, 1e-6))
    if ratio >= 0.3 and n1 >= 1 and 1.5 <= n2 / n1 <= 2.8 and n2 >= 3:
        return "figure8"
    if ratio >= 0.3 and n2 >= 1 and 1.5 <= n1 / n2 <= 2.8 and n1 >= 3:
        return "figure8"
    if ratio < 0.5 and n1 >= 2 and n1 <= (hi + 1) * seconds:
        return "oscillation"
    return None


def direction_table(part: Part, component_names) -> np.ndarray:
    """(k, 2) part-local label index for a motion component moving negative (column 0) / positive (column 1);
    ``Unknown`` where the vocabulary has no label for that direction (e.g. the neck moving forward)."""
    unknown = part.label("unknown").index
    table = np.full((len(component_names), 2), unknown)
    for k, name in enumerate(component_names):
        for si, sign in enumerate((-1, 1)):
            lab = part.find("direction", component=name, sign=sign)
            if lab is not None:
                table[k, si] = lab.index
    return table


def still_labels(part: Part, direction: np.ndarray | None, th: dict, frames: int = 1) -> np.ndarray:
    """Part-local label of a part that does not move, per frame: ``Holding ...`` by the segment's unit direction
    (T, 3) in its body frame (x front, y left, z up; arms: torso frame, legs: pelvis frame) when it is held away
    from hanging (more than ``hold_away_from_down_deg``; High: arms above the horizontal, legs more than 60 deg
    from straight down), else ``Keeping Still``. ``direction`` None (parts without a segment): Keeping Still in
    each of ``frames`` frames."""
    T = frames if direction is None else direction.shape[0]
    out = np.full(T, part.label("still").index)
    if direction is None:
        return out
    d = direction
    away = np.degrees(np.arccos(np.clip(-d[:, 2], -1, 1))) > th["hold_away_from_down_deg"]
    conds = {"high": d[:, 2] > (0.2 if part.measure == "limb" and "arm" in part.name else -0.5)}
    fwd_dom = np.abs(d[:, 0]) >= np.abs(d[:, 1])
    conds["forward"] = away & fwd_dom & (d[:, 0] > 0)
    conds["backward"] = away & fwd_dom & (d[:, 0] <= 0)
    conds["side"] = away & ~fwd_dom
    for cond in ("side", "backward", "forward", "high"):  # later ones take precedence
        lab = part.find("hold", condition=cond)
        if lab is not None:
            out[conds[cond]] = lab.index
    return out


def foot_state_labels(part: Part, extension: np.ndarray, flexion: np.ndarray, rolled: np.ndarray) -> np.ndarray:
    """Part-local foot labels from (T,) masks: Extension / Flexion / Relaxed, Unknown where rolled on its edge."""
    out = np.full(extension.shape[0], part.find("state", condition="relaxed").index)
    out[extension] = part.find("state", condition="extension").index
    out[flexion] = part.find("state", condition="flexion").index
    out[rolled] = part.label("unknown").index
    return out


@dataclass
class Labels:
    """Per-frame labels: ``ids`` (T, 16) int16 global label ids (taxonomy order of parts), ``fps``."""

    ids: np.ndarray
    fps: float
    taxonomy: Taxonomy

    def names(self, part: str) -> list[str]:
        p = self.taxonomy.part(part)
        return [self.taxonomy.labels[i].name for i in self.ids[:, p.index]]

    def segments(self) -> list[dict]:
        """Runs of equal labels: dicts with fixed keys part, label, label_id, start, end (frames, end exclusive),
        start_s, end_s (seconds)."""
        out = []
        for p in self.taxonomy.parts:
            for s, e, v in _runs(self.ids[:, p.index]):
                out.append({"part": p.name, "label": self.taxonomy.labels[int(v)].name, "label_id": int(v),
                            "start": s, "end": e, "start_s": s / self.fps, "end_s": e / self.fps})
        return out

    def multi_hot(self) -> np.ndarray:
        """(T, 154) bool."""
        out = np.zeros((self.ids.shape[0], len(self.taxonomy.labels)), dtype=bool)
        np.put_along_axis(out, self.ids.astype(np.int64), True, axis=1)
        return out


class MovementLabeller:
    """Labels BODY_25 3D motion with the vocabulary of :mod:`hdvr.movements.taxonomy`.

    ``patterns=False`` skips the windowed shape analysis (circles, oscillations, figure 8, jitter); the synthetic
    generator uses that mode on its exact kinematics and adds the pattern labels its primitives declare.
    """

    def __init__(self, taxonomy: Taxonomy | None = None, patterns: bool = True, smooth: bool = True,
                 smoothing_s: float | None = None):
        self.tax = taxonomy or load_taxonomy()
        self.th = dict(self.tax.thresholds)
        if smoothing_s is not None:  # longer for noisy input (fitted 3D), at the cost of fast shakes (jitter)
            self.th["smoothing_s"] = float(smoothing_s)
        self.patterns = patterns
        self.smooth = smooth

    def label(self, keypoints: np.ndarray, fps: float, up=(0.0, 0.0, 1.0)) -> Labels:
        kp = np.asarray(keypoints, dtype=np.float64)
        if kp.ndim != 3 or kp.shape[1:] != (25, 3):
            raise HDVRError(f"keypoints must be BODY_25 (T, 25, 3) metres, got shape {kp.shape}")
        if not np.isfinite(fps) or fps <= 0:
            raise HDVRError(f"fps must be positive, got {fps}")
        T = kp.shape[0]
        if T < 3:
            raise HDVRError(f"need at least 3 frames to label movements, got {T}")
        missing = ~np.isfinite(kp).all(-1)  # (T, 25)
        if missing.all():
            raise HDVRError("every keypoint is missing (NaN); nothing to label")
        filled = kp.copy()
        t_idx = np.arange(T)
        for j in range(25):
            ok = ~missing[:, j]
            if ok.all():
                continue
            for c in range(3):
                filled[:, j, c] = np.interp(t_idx, t_idx[ok], kp[ok, j, c]) if ok.any() else 0.0
        win = max(1, int(round(self.th["smoothing_s"] * fps)) | 1)
        raw = None
        if self.smooth and win > 1:
            raw = filled
            filled = uniform_filter1d(filled, win, axis=0, mode="nearest")
        flipping = self._flipping(filled, fps, up)
        signals = body_signals(filled, up, flipping)
        # kicks last a few frames: smoothing would flatten their peak speed, so it is read unsmoothed
        raw_signals = body_signals(raw, up, flipping) if raw is not None else signals
        ids = np.zeros((T, len(self.tax.parts)), dtype=np.int16)
        for part in self.tax.parts:
            names = PART_KEYPOINTS.get(part.name) or PART_KEYPOINTS[part.measure]
            part_missing = missing[:, [J[n] for n in names]].any(1)
            local = self._label_part(part, signals[part.name], fps, raw_signals[part.name])
            local[part_missing] = part.label("unknown").index
            ids[:, part.index] = np.array([part.labels[i].id for i in local], dtype=np.int16)
        return Labels(ids, float(fps), self.tax)

    # ------------------------------------------------------------------------------------------------------------
    def _flipping(self, kp: np.ndarray, fps: float, up) -> np.ndarray:
        """Frames of a somersault: the trunk axis turns in the world's vertical plane faster than the threshold."""
        sig = body_signals(kp, up)["torso"].extra["trunk_pitch"]
        rate = np.abs(np.gradient(sig) * fps)
        thr = self.th["somersault_speed_rad_s"]
        return _hysteresis(rate, thr, thr * 0.6)

    def _label_part(self, part: Part, sig: PartSignals, fps: float, raw: PartSignals | None = None) -> np.ndarray:
        th = self.th
        T = sig.components.shape[0] if sig.components.size else sig.extra["angle_deg"].shape[0]
        unknown = part.label("unknown").index
        if part.measure == "foot":
            return self._label_foot(part, sig)
        vel = np.gradient(sig.components, axis=0) * fps
        is_hips = part.measure == "hips"
        thr = th["hips_still_speed_m_s"] if is_hips else th["still_speed_rad_s"]
        speed = np.linalg.norm(vel[:, list(sig.motion)], axis=1)
        special = np.full(T, -1)
        if is_hips:
            turn_rate = np.abs(np.gradient(sig.extra["heading"]) * fps)
            turning = _hysteresis(turn_rate, th["turn_speed_rad_s"], th["turn_speed_rad_s"] * th["still_exit_ratio"])
            special[turning] = part.label("turning").index
        if part.name == "torso":
            pitch_rate = np.abs(np.gradient(sig.extra["trunk_pitch"]) * fps)
            flip = _hysteresis(pitch_rate, th["somersault_speed_rad_s"], th["somersault_speed_rad_s"] * 0.6)
            special[flip] = part.label("somersault").index
        gap = int(round(th["gap_fill_s"] * fps))
        min_run = max(2, int(round(th["min_run_s"] * fps)))
        moving = _hysteresis(speed, thr, thr * th["still_exit_ratio"]) | (special >= 0)
        moving = _clean_mask(moving, gap, min_run)

        out = np.full(T, unknown)
        motion = list(sig.motion)
        dom = np.argmax(np.abs(vel[:, motion]), axis=1)
        fast = part.find("fast")
        table = direction_table(part, [sig.names[ci] for ci in motion])
        dom_vel = np.take_along_axis(vel[:, motion], dom[:, None], 1)[:, 0]
        direction = table[dom, (dom_vel > 0).astype(int)]
        if fast is not None:
            raw_speed = speed if raw is None else np.linalg.norm(
                np.gradient(raw.components[:, motion], axis=0) * fps, axis=1)
            direction = np.where(raw_speed > th["kick_speed_rad_s"], fast.index, direction)
        out[moving] = direction[moving]
        out[special >= 0] = special[special >= 0]
        out = _merge_short(out, moving, min_run)

        if self.patterns:
            out = self._apply_patterns(part, sig, fps, moving, out, special)

        still = ~moving
        out[still] = still_labels(part, sig.extra.get("direction"), th, T)[still]
        return out

    def _apply_patterns(self, part, sig, fps, moving, out, special):
        th = self.th
        half = int(round(th["pattern_window_s"] * fps / 2))
        amp = th["hips_pattern_min_amplitude_m"] if part.measure == "hips" else th["pattern_min_amplitude_rad"]
        labels = {}
        for kind in ("circle", "oscillation", "figure8"):
            lab = part.find("pattern", pattern=kind)
            if lab is not None:
                labels[kind] = lab.index
        labels["jitter"] = part.label("unknown").index
        res = out.copy()
        for s, e, v in _runs(moving):
            if not v:
                continue
            if e - s <= 2 * half + 1:
                kinds = [classify_window(sig.components[s:e], fps, th, amp)] * (e - s)
            else:
                stride = max(1, int(round(0.1 * fps)))  # classify every 0.1 s, hold in between
                centre = []
                for c in range(s + half, e - half):
                    if (c - s - half) % stride == 0:
                        kind = classify_window(sig.components[c - half:c + half + 1], fps, th, amp)
                    centre.append(kind)
                kinds = [centre[0]] * half + centre + [centre[-1]] * (e - s - half - len(centre))
            for k, kind in enumerate(kinds):
                t = s + k
                if kind in labels and special[t] < 0:
                    res[t] = labels[kind]
        return res

    def _label_foot(self, part: Part, sig: PartSignals) -> np.ndarray:
        th = self.th
        angle, roll = sig.extra["angle_deg"], sig.extra["roll_deg"]
        hyst = th["foot_hysteresis_deg"]
        ext, flx = th["foot_extension_deg"], th["foot_flexion_deg"]
        extension = _hysteresis(angle, ext + hyst, ext - hyst)
        flexion = _hysteresis(-angle, -(flx - hyst), -(flx + hyst))
        rolled = _hysteresis(roll, th["foot_roll_deg"] + hyst, th["foot_roll_deg"] - hyst)
        return foot_state_labels(part, extension, flexion, rolled)


def label_keypoints(keypoints: np.ndarray, fps: float, up=(0.0, 0.0, 1.0), patterns: bool = True) -> Labels:
    """Convenience: label BODY_25 3D keypoints (T, 25, 3) with the packaged vocabulary."""
    return MovementLabeller(patterns=patterns).label(keypoints, fps, up)
