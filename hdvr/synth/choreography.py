"""Choreography generator: composes basic movements into joint trajectories of the 34-DOF digital dancer.

Each motor group (head, neck, trunk, left arm, right arm, legs) gets its own sequence of primitives on the
genre's beat grid: ``hold``, ``move`` (to a new target, trapezoidal velocity, single or double joint), ``swing``
(oscillation), ``circle`` (two joints in quadrature), ``jitter`` (fast irregular shaking: Unknown), plus leg
phrases (gestures of one leg with the other as stance, plie / releve, turns, hip isolations with both feet
planted: shift, wave, circle, figure 8, shimmy) and a somersault. Every trajectory stays inside the joint ranges
shrunk by :data:`MARGIN_RAD`, is C1-smooth, and the root is placed afterwards: its height puts the lowest sole
point on the floor (z = 0), its horizontal position keeps the stance foot fixed (no skating); during a flip it
follows a ballistic arc.

Ground-truth labels are declared by the primitives themselves (:mod:`hdvr.synth.declare`): every primitive is
recorded as an :class:`~hdvr.synth.declare.Intent` (group, kind, frames) and shape primitives as
:class:`Declared` spans; the labels follow from those and the planned trajectories, not from the labeller.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.ndimage import maximum_filter1d, uniform_filter1d
from scipy.optimize import least_squares

from hdvr import dh
from hdvr.layouts import BODY25_NAMES
from hdvr.movements.labeller import _runs
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.skeleton import ROOT_QPOS, Skeleton
from hdvr.synth.declare import Intent, declared_labels, plan_kinematics
from hdvr.synth.genres import GenreStyle, genre_style

MARGIN_RAD = 0.05
JI = {n: i for i, n in enumerate(dh.JOINT_NAMES)}
LOWER = dh.LOWER + MARGIN_RAD
UPPER = dh.UPPER - MARGIN_RAD
#: The generator's rest pose: the dancer's rest pose moved inside the margins (knees and toes bend 0.05 rad).
REST = np.clip(dh.REST_Q, LOWER, UPPER)
SOLE_KEYPOINTS = {"left": (19, 20, 21), "right": (22, 23, 24)}  # big toe, small toe, heel (BODY_25 indices)


def _j(*names):
    return [JI[n] for n in names]


GROUP_JOINTS = {
    "head": _j("neck_twist", "head_nod"),
    "neck": _j("neck_bend", "neck_flex"),
    "trunk": _j("lumbar_flex", "lumbar_bend", "lumbar_twist"),
    "left_arm": _j("left_shoulder_abduct", "left_shoulder_flex", "left_shoulder_rotate", "left_elbow_flex"),
    "right_arm": _j("right_shoulder_abduct", "right_shoulder_flex", "right_shoulder_rotate", "right_elbow_flex"),
}
# Body parts that see a shape made by a group's joints (declared pattern labels go to these parts).
FLEX_JOINTS = set(_j("left_shoulder_flex", "right_shoulder_flex"))
#: partners facing each other raise their arms forward at most this far (rad of shoulder flexion), so that
#: their hands do not meet (the arms are not choreographed into a hold)
PARTNER_REACH_CAP_RAD = 0.7
ARM_PARTS = {"shoulder": ("upper_arm", "lower_arm"), "forearm": ("lower_arm",)}


def leg_joints(side: str) -> dict[str, int]:
    return {k: JI[f"{side}_{k}"] for k in ("hip_adduct", "hip_extend", "hip_rotate", "knee_flex", "ankle_plantarflex",
                                            "ankle_invert", "toe_flex")}


def leg_ik(x, z, l1: float, l2: float, knee_min: float):
    """Sagittal two-link leg: hip_extend and knee_flex (rad) that put the ankle ``x`` behind and ``z`` below the
    hip (metres; thigh ``l1``, shank ``l2``); the knee bends at least ``knee_min`` (targets out of reach are
    pulled in). Convention: segment angles from straight down, positive backward; shank = hip_extend + knee."""
    x, z = np.asarray(x, dtype=float), np.asarray(z, dtype=float)
    r_max = np.sqrt(l1 * l1 + l2 * l2 + 2 * l1 * l2 * np.cos(knee_min))
    r = np.minimum(np.hypot(x, z), r_max)
    knee = np.arccos(np.clip((r * r - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1, 1))
    theta = np.arctan2(x, z) - np.arctan2(l2 * np.sin(knee), l1 + l2 * np.cos(knee))
    return theta, knee


def leg_fk(theta, knee, l1: float, l2: float):
    """Ankle (x behind, z below the hip; metres) of the sagittal two-link leg (inverse of :func:`leg_ik`)."""
    return (l1 * np.sin(theta) + l2 * np.sin(theta + knee), l1 * np.cos(theta) + l2 * np.cos(theta + knee))


def _rest_hinges(sk: Skeleton) -> np.ndarray:
    """(41,) qpos of the generator's rest pose (:data:`REST`), pelvis upright at the origin's height."""
    q = sk.rest_qpos()
    q[ROOT_QPOS:] = REST
    return q


#: joint speed (rad/s of hip abduction) of a foot sliding out to second position or back: with the weight on the
#: other leg the working foot travels about 1.6 m per radian, so about 0.5 m/s
TENDU_SPEED_RAD_S = 0.3
TURNED_OUT_JOINTS = ("hip_adduct", "hip_extend", "hip_rotate", "knee_flex", "ankle_plantarflex", "ankle_invert")


def turned_out_leg(sk: Skeleton, side: str, turnout: float, thigh: float, abduction: float = 0.0) -> np.ndarray:
    """Hinges of a bent, turned-out leg, as in a plie or a passe: (hip_adduct, hip_extend, hip_rotate, knee_flex,
    ankle_plantarflex, ankle_invert) in radians.

    The knee bends ``2 * thigh`` rad more than at rest and points ``turnout`` rad out from straight ahead, over the
    toes; the ankle stays where it stands at rest (under the hip), or with ``abduction`` (rad; second position) as
    far out as the straight leg opened that far puts it, whatever the bend (the feet stay where they stand while
    the dancer sinks).
    The sole stays level and points as far out as the knee (so a straight leg, ``thigh`` 0, is turned out too:
    first position). The three hip hinges and the foot are solved on the dancer's own kinematics (MuJoCo
    forward kinematics of ``sk``, pelvis upright): the chain's hinge order (adduct, extend, rotate) has no simple
    closed form for this. Results are cached on ``sk`` per rounded angle and bone set."""
    key = (side, round(float(turnout), 3), round(float(thigh), 3), round(float(abduction), 3),
           np.asarray(sk.bone_lengths).round(4).tobytes())
    cache = sk.__dict__.setdefault("_turned_out_cache", {})
    if key in cache:
        return cache[key].copy()
    q0 = _rest_hinges(sk)  # the generator's rest pose and margins (LOWER, UPPER), not the model's
    G = leg_joints(side)
    free = [ROOT_QPOS + G[k] for k in ("hip_adduct", "hip_extend", "hip_rotate", "ankle_plantarflex", "ankle_invert")]
    names = [f"{side}_{n}" for n in ("hip", "knee", "ankle", "big_toe", "small_toe", "heel")]
    ids = [BODY25_NAMES.index(n) for n in names]
    rest = sk.keypoints(q0)[ids]
    knee_flex = float(np.clip(REST[G["knee_flex"]] + 2 * thigh, LOWER[G["knee_flex"]], UPPER[G["knee_flex"]]))
    q0[ROOT_QPOS + G["knee_flex"]] = knee_flex
    hip = rest[0]
    l1, l2 = np.linalg.norm(rest[1] - rest[0]), np.linalg.norm(rest[2] - rest[1])
    out = 1.0 if side == "left" else -1.0  # +y is the dancer's left
    ahead = np.array([np.cos(turnout), out * np.sin(turnout), 0.0])
    # the ankle stays where it stands at rest, or in second position (l1 + l2) sin(abduction) further out, and comes
    # as near the hip as the bent knee makes the leg; the knee points along ``ahead``, off the hip-ankle line. So a
    # straight parallel leg (thigh 0, turnout 0, abduction 0) is the rest pose itself.
    reach = np.sqrt(l1 * l1 + l2 * l2 + 2 * l1 * l2 * np.cos(knee_flex))
    stand = (rest[2] - hip)[:2] + np.array([0.0, out * (l1 + l2) * np.sin(abduction)])
    stand *= min(1.0, 0.95 * reach / max(np.linalg.norm(stand), 1e-9))
    axis = np.r_[stand, -np.sqrt(reach * reach - stand @ stand)] / reach
    along = (l1 * l1 - l2 * l2 + reach * reach) / (2 * reach)
    side_dir = ahead - (ahead @ axis) * axis
    side_dir /= np.linalg.norm(side_dir)
    knee = along * axis + np.sqrt(max(l1 * l1 - along * along, 0.0)) * side_dir
    targets = hip + np.stack([knee, reach * axis])
    sole_rest = rest[3:, 2] - rest[2, 2]  # sole points' heights below the ankle, standing
    foot_rest = (rest[3] - rest[5])[:2]  # heel to big toe, standing (metres, horizontal)
    c, s = np.cos(out * turnout), np.sin(out * turnout)
    foot_target = np.array([[c, -s], [s, c]]) @ foot_rest  # the foot turned out as far as the knee

    def residual(x):
        q = q0.copy()
        q[free] = x
        kp = sk.keypoints(q)[ids]
        return np.concatenate([(kp[1:3] - targets).ravel(), kp[3:, 2] - kp[2, 2] - sole_rest,
                               (kp[3] - kp[5])[:2] - foot_target])

    lo, hi = LOWER[[i - ROOT_QPOS for i in free]], UPPER[[i - ROOT_QPOS for i in free]]
    x = least_squares(residual, np.clip(np.zeros(5), lo, hi), bounds=(lo, hi)).x
    hinges = np.array([x[0], x[1], x[2], knee_flex, x[3], x[4]])
    if len(cache) >= 20000:  # long synthetic runs: keep the memory bounded (a solve costs a few milliseconds)
        cache.clear()
    cache[key] = hinges
    return hinges.copy()


def ramp_profile(n: int, ramp: float = 0.2) -> np.ndarray:
    """Progress 0 -> 1 over n frames with a trapezoidal velocity (ramps ``ramp`` of the duration each side)."""
    if n <= 1:
        return np.ones(max(n, 0))
    tau = (np.arange(n) + 1) / n
    v = np.minimum(1.0, np.minimum(tau / ramp, (1 - tau + 1.0 / n) / ramp))
    v = np.clip(v, 0, 1)
    # smooth the corners of the trapezoid (C1 progress)
    v = np.convolve(np.pad(v, 2, mode="edge"), np.ones(5) / 5, mode="valid")
    p = np.cumsum(v)
    return p / p[-1]


def envelope(n: int, fps: float, ramp_s: float = 0.2) -> np.ndarray:
    r = max(1, int(round(ramp_s * fps)))
    e = np.ones(n)
    k = min(r, n // 2)
    if k > 0:
        rise = 0.5 - 0.5 * np.cos(np.linspace(0, np.pi, k))
        e[:k] = rise
        e[n - k:] = rise[::-1]
    return e


@dataclass
class Declared:
    """A primitive's declared shape label: frames [start, end), parts it applies to, label kind or name."""

    start: int
    end: int
    parts: tuple[str, ...]
    label: str  # "circle" | "oscillation" | "figure8" | "jitter" (-> Unknown) | "somersault"


@dataclass
class Choreography:
    """One dancer's motion. ``qpos`` (T, 41) world; ``keypoints`` (T, 25, 3) world metres; ``labels`` (T, 16) global
    label ids declared by the primitives; ``airborne`` (T,) bool (flip frames); ``primitives`` list of
    :class:`~hdvr.synth.declare.Intent`; ``declared`` list of :class:`Declared` shape spans."""

    genre: str
    fps: float
    qpos: np.ndarray
    keypoints: np.ndarray
    labels: np.ndarray
    airborne: np.ndarray
    primitives: list = field(default_factory=list)
    declared: list = field(default_factory=list)
    stance: np.ndarray | None = None  # (T,) 0 both / automatic, 1 left foot, 2 right foot carries the weight
    walks: list = field(default_factory=list)  # (start, end) frames of travelling phrases
    bones: np.ndarray | None = None  # (9,) bone lengths (metres) of the dancer
    between_m: float | None = None  # deepest penetration into other dancers of its clip (m), once checked


class _Track:
    """One motor group's joint trajectories being written frame by frame."""

    def __init__(self, hinges: np.ndarray, joints: list[int]):
        self.h = hinges
        self.joints = joints
        self.t = 0

    def current(self):
        return self.h[max(self.t - 1, 0), self.joints].copy() if self.t > 0 else self.h[0, self.joints].copy()


class ChoreographyGenerator:
    """Builds one dancer's choreography for a genre. Deterministic for a given ``rng`` state."""

    def __init__(self, skeleton: Skeleton | None = None, fps: float = 30.0):
        self.sk = skeleton or Skeleton()
        self.fps = float(fps)
        self.tax = load_taxonomy()
        self.reach_cap = None

    # ---- helpers ---------------------------------------------------------------------------------------------
    def _beat_frames(self, style: GenreStyle, bpm: float) -> float:
        return self.fps * 60.0 / bpm

    def _speed(self, style, rng):
        return rng.uniform(*style.speed)

    def _target(self, joints, current, style, rng, min_delta=0.3):
        """A new target for one or two of ``joints`` that moves at least ``min_delta`` rad."""
        target = current.copy()
        k = rng.choice(len(joints), size=1 if rng.random() < 0.7 else min(2, len(joints)), replace=False)
        for i in k:
            j = joints[i]
            lo = REST[j] + style.amplitude * (LOWER[j] - REST[j])
            hi = REST[j] + style.amplitude * (UPPER[j] - REST[j])
            if j in FLEX_JOINTS and self.reach_cap is not None:
                hi = min(hi, self.reach_cap)
            for _ in range(8):
                v = rng.uniform(lo, hi)
                if abs(v - current[i]) >= min(min_delta, 0.45 * (hi - lo)):
                    break
            target[i] = v
        return target

    def _write_move(self, h, joints, t0, start, target, speed):
        delta = np.max(np.abs(target - start))
        n = max(int(round(self.fps * delta / max(speed * 0.8, 1e-3))), int(0.15 * self.fps), 2)
        full = n
        n = min(n, h.shape[0] - t0)
        if n <= 0:
            return 0
        p = ramp_profile(full)[:n, None]  # a move cut by the end of the clip keeps its speed
        h[t0:t0 + n][:, joints] = start + (target - start) * p
        return n

    def _hold(self, h, joints, t0, n, value):
        n = min(n, h.shape[0] - t0)
        if n > 0:
            h[t0:t0 + n][:, joints] = value
        return max(n, 0)

    def _oscillate(self, h, joints, t0, value, amps, phases, freq, periods, freq_mult=None):
        """value + env * amps * sin(2 pi f t + phase) on ``joints`` (amplitudes clipped to stay in range)."""
        n = min(int(round(self.fps * periods / freq)), h.shape[0] - t0)
        if n < int(0.6 * self.fps):
            return 0
        t = np.arange(n) / self.fps
        env = envelope(n, self.fps)
        mult = freq_mult or [1.0] * len(joints)
        for i, j in enumerate(joints):
            a = min(amps[i], value[i] - LOWER[j], UPPER[j] - value[i])
            h[t0:t0 + n, j] = value[i] + env * a * np.sin(2 * np.pi * freq * mult[i] * t + phases[i])
        return n

    def _jitter(self, h, joints, t0, value, amp, rng):
        n = min(int(round(self.fps * rng.uniform(0.8, 1.4))), h.shape[0] - t0)
        if n < int(0.5 * self.fps):
            return 0
        t = np.arange(n) / self.fps
        env = envelope(n, self.fps, 0.1)
        for i, j in enumerate(joints):
            a = min(amp, value[i] - LOWER[j], UPPER[j] - value[i])
            sig = sum(np.sin(2 * np.pi * rng.uniform(3.2, 4.2) * t + rng.uniform(0, 2 * np.pi)) for _ in range(2)) / 1.6
            h[t0:t0 + n, j] = value[i] + env * a * sig
        return n

    # ---- upper body groups -----------------------------------------------------------------------------------
    def _group(self, h, group, style, weights, beat, rng, declared, prims, parts_for_shape):
        joints = GROUP_JOINTS[group]
        T = h.shape[0]
        t = int(rng.integers(0, max(1, int(beat))))
        h[:t, joints] = h[0, joints]
        kinds = list(weights)
        w = np.array([weights[k] for k in kinds], dtype=float)
        while t < T:
            cur = h[t - 1, joints].copy() if t > 0 else h[0, joints].copy()
            h[t:, joints] = cur  # joints a primitive does not drive hold their value
            kind = kinds[rng.choice(len(kinds), p=w / w.sum())]
            n = 0
            if kind == "move":
                target = self._target(joints, cur, style, rng)
                if group.endswith("_arm") and rng.random() < 0.25:  # raise the arm above the horizontal
                    k = int(rng.integers(0, 2)) if self.reach_cap is None else 0  # partners: sideways / up
                    target[k] = rng.uniform(1.78, 1.9)
                    if abs(target[k] - cur[k]) < 0.3:
                        target[k] = rng.uniform(0.0, 0.6)
                n = self._write_move(h, joints, t, cur, target, self._speed(style, rng))
            elif kind in ("swing", "circle", "jitter", "forearm"):
                pre, m, shape_parts, label = self._shape(h, group, joints, t, cur, kind, style, rng)
                n = pre + m if m else 0
                if m:
                    declared.append(Declared(t + pre, t + pre + m, shape_parts, label))
            if n == 0:
                kind = "hold"
            if kind != "hold":
                prims.append((group, kind, t, t + n))
            t += n
            hold = int(round(beat * rng.choice([1, 1, 2, 3] if kind != "hold" else [1, 2, 4]))) if t < T else 0
            hold = max(hold, int(0.4 * self.fps))
            t += self._hold(h, joints, t, hold, h[t - 1, joints] if t > 0 else cur)

    def _settle(self, h, joints, t, cur, centre):
        """Move ``joints`` to ``centre`` and hold 0.3 s (so a shape starts from rest, as its own movement)."""
        n = self._write_move(h, joints, t, cur, centre, 2.0) if np.max(np.abs(centre - cur)) > 1e-6 else 0
        n += self._hold(h, joints, t + n, int(0.45 * self.fps), centre)
        h[t + n:, joints] = centre  # the shape then drives some of these joints; the others stay here
        return n

    def _shape(self, h, group, joints, t, cur, kind, style, rng):
        """A shaped primitive: returns (frames before the shape, shape frames, parts, declared label)."""
        freq = rng.uniform(*style.osc_hz)
        periods = rng.uniform(2.0, 3.5)
        prev = h[max(t - 1, 0)].copy()
        if kind == "jitter":
            if group == "trunk":
                sel = _j("lumbar_flex", "lumbar_twist") if rng.random() < 0.5 else _j("lumbar_bend", "lumbar_twist")
                parts = ("torso",) if JI["lumbar_bend"] not in sel else ("torso", "left_shoulder", "right_shoulder")
            else:
                sel = joints[:2]
                parts = self._parts_for_shape(group, kind)
            centre = np.clip(prev[sel], LOWER[sel] + 0.1, UPPER[sel] - 0.1)
            pre = self._settle(h, sel, t, prev[sel], centre)
            amp = 0.06 if group in ("head", "neck", "trunk") else 0.08
            return pre, self._jitter(h, sel, t + pre, centre, amp, rng), parts, "jitter"
        if group in ("left_arm", "right_arm"):
            side = group.split("_")[0]
            if kind == "forearm":
                sel = _j(f"{side}_shoulder_rotate", f"{side}_elbow_flex")
                centre = np.array([rng.uniform(-2.0, -1.1), -0.75])
                pre = self._settle(h, sel, t, prev[sel], centre)
                m = self._oscillate(h, sel, t + pre, centre, [0.5, 0.55], [0.0, np.pi / 2], freq, periods)
                return pre, m, (f"{side}_lower_arm",), "circle"
            sel = _j(f"{side}_shoulder_abduct", f"{side}_shoulder_flex")
            centre = np.r_[rng.uniform(0.3, 0.9), rng.uniform(0.2, 0.8), cur[2], rng.uniform(-0.3, 0.0)]
            if self.reach_cap is not None:  # partners: the arm's forward swing stays below the cap
                centre[1] = min(centre[1], self.reach_cap - (0.45 if kind == "circle" else 0.6))
            pre = self._settle(h, joints, t, cur, centre)
            if kind == "circle":
                m = self._oscillate(h, sel, t + pre, centre[:2], [0.45, 0.45], [0.0, np.pi / 2], freq, periods)
            else:
                m = self._oscillate(h, sel[1:], t + pre, centre[1:2], [0.6], [0.0], freq, periods)
            return pre, m, (f"{side}_upper_arm", f"{side}_lower_arm"), "circle" if kind == "circle" else "oscillation"
        if group == "trunk":
            if kind == "circle":  # side bend + twist in quadrature: shoulders circle, the trunk swings
                sel = _j("lumbar_bend", "lumbar_twist")
                centre = np.zeros(2)
                pre = self._settle(h, sel, t, prev[sel], centre)
                m = self._oscillate(h, sel, t + pre, centre, [0.2, 0.3], [0.0, np.pi / 2], freq, periods)
                return pre, m, ("torso", "left_shoulder", "right_shoulder"), "circle"
            j = int(rng.choice(_j("lumbar_flex", "lumbar_twist")))
            centre = np.zeros(1)
            pre = self._settle(h, [j], t, prev[[j]], centre)
            m = self._oscillate(h, [j], t + pre, centre, [0.25 if j != JI["lumbar_twist"] else 0.35], [0.0], freq,
                                periods)
            return pre, m, ("torso",), "oscillation"
        if group in ("head", "neck") and kind == "circle":
            sel = _j("neck_twist", "head_nod") if group == "head" else _j("neck_bend", "neck_flex")
            centre = np.zeros(2)
            pre = self._settle(h, sel, t, prev[sel], centre)
            amps = [0.35, 0.3] if group == "head" else [0.3, 0.3]
            m = self._oscillate(h, sel, t + pre, centre, amps, [0.0, np.pi / 2], freq, periods)
            return pre, m, (group,), "circle"
        return 0, 0, (), ""

    @staticmethod
    def _parts_for_shape(group, kind):
        if group in ("left_arm", "right_arm"):
            side = group.split("_")[0]
            return (f"{side}_upper_arm", f"{side}_lower_arm")
        if group == "trunk":
            return ("torso",)
        return (group,)

    # ---- legs ------------------------------------------------------------------------------------------------
    def _legs(self, h, yaw, pitch, style, beat, rng, declared, prims):
        T = h.shape[0]
        L, R = leg_joints("left"), leg_joints("right")
        allj = sorted(set(L.values()) | set(R.values()))
        kinds = list(style.legs) + (["walk"] if style.walk > 0 else [])
        w = np.array([style.legs[k] for k in kinds if k != "walk"] + ([style.walk] if style.walk > 0 else []),
                     dtype=float)
        t = 0
        while t < T:
            cur = h[t - 1, allj].copy() if t > 0 else h[0, allj].copy()
            h[t:, allj] = cur  # joints a phrase does not drive hold their value
            kind = kinds[rng.choice(len(kinds), p=w / w.sum())]
            n = 0
            # phrases other than gestures start from both feet flat on the floor
            neutral = REST[allj].copy()
            if kind != "gesture" and np.max(np.abs(cur - neutral)) > 1e-6:
                t += self._write_move(h, allj, t, cur, neutral, 2.0)
                t += self._hold(h, allj, t, int(0.4 * self.fps), neutral)
                continue
            if kind == "plie":
                n = self._plie(h, allj, t, neutral, style, beat, rng, L, R)
            elif kind == "relieve":
                target = neutral.copy()
                phi = rng.uniform(0.55, 0.9)
                for s in (L, R):
                    target[allj.index(s["ankle_plantarflex"])] = phi
                    target[allj.index(s["toe_flex"])] = -min(phi, 1.3)
                n = self._write_move(h, allj, t, cur, target, rng.uniform(1.2, 2.0))
                n += self._hold(h, allj, t + n, int(beat * rng.choice([1, 2])), target)
                n += self._write_move(h, allj, t + n, target, neutral, rng.uniform(1.2, 2.0))
            elif kind == "turn":
                side = rng.choice(["left", "right"])
                G = leg_joints(side)
                gj = [G["hip_adduct"], G["hip_extend"], G["hip_rotate"], G["knee_flex"]]
                phi = rng.uniform(0.65, 0.8)
                lifted = REST[gj] + np.array([0.0, -phi, 0.0, 2 * phi])  # thigh forward, shank back: foot rises
                passe = turned_out_leg(self.sk, side, rng.uniform(*style.turnout_rad), phi)[:4]  # knee out as the genre
                speed = self._speed(style, rng)
                up = self._write_move(h, gj, t, h[t - 1, gj] if t else h[0, gj], lifted, speed)
                up += self._write_move(h, gj, t + up, lifted, passe, speed)
                spin = self._turn(h, yaw, t + up, style, beat, rng)
                self._hold(h, gj, t + up, spin, passe)
                self.airtime[t + up:t + up + spin] = True
                down = self._write_move(h, gj, t + up + spin, passe, lifted, speed)
                down += self._write_move(h, gj, t + up + spin + down, lifted, REST[gj], speed)
                n = up + spin + down
                self.stance[t:t + n] = 2 if side == "left" else 1
            elif kind == "walk":
                n = self._walk(h, yaw, t, style, beat, rng)
                # the legs swing forward and back like pendulums: a swing of each leg segment when the steps
                # reverse the legs at least twice per pattern window (the vocabulary's swinging), else the steps
                # are directional moves
                if n and self.step_frames <= self.fps * self.tax.thresholds["pattern_window_s"] / 2:
                    declared.append(Declared(t, t + n, ("left_upper_leg", "left_lower_leg", "right_upper_leg",
                                                        "right_lower_leg"), "oscillation"))
            elif kind == "flip":
                n = self._flip(pitch, t, rng)
                if n:
                    declared.append(Declared(t, t + n, ("torso",), "somersault"))
                    h[t:t + n, allj] = neutral
            elif kind.startswith("hips_"):
                n = self._hips(h, t, kind, style, rng, L, R)
                if n and kind != "hips_shift":
                    lab = {"hips_circle": "circle", "hips_eight": "figure8", "hips_wave": "oscillation",
                           "hips_jitter": "jitter"}[kind]
                    declared.append(Declared(t, t + n, ("hips",), lab))
            elif kind == "gesture":
                n = self._gesture(h, t, style, beat, rng, declared, prims)
            if n == 0:
                kind = "hold"
                n = self._hold(h, allj, t, int(beat), cur)
            if kind != "hold":
                prims.append(("legs", kind, t, t + n))
            t += n
            t += self._hold(h, allj, t, max(int(beat * rng.choice([1, 2])), int(0.4 * self.fps)), h[t - 1, allj])

    def _plie(self, h, allj, t, neutral, style, beat, rng, L, R):
        """A plie as the genre dances it: the legs turn out (first position, the feet pivoting on the floor), one
        foot may slide out to second position (a tendu: the other leg carries the weight), the knees bend over the
        toes and straighten, and the legs close and turn in again. Returns the frames written."""
        phi = min(rng.uniform(0.3, 0.55) * style.amplitude / 0.8, 0.6)  # thigh lean (rad); knees bend 2 phi
        turnout = rng.uniform(*style.turnout_rad)
        turnout = turnout if turnout > 0.02 else 0.0  # a parallel plie starts and ends at the rest pose exactly
        opened = rng.uniform(0.12, 0.3) if rng.random() < style.second_position else 0.0

        def legs(lean, abduction):
            out = neutral.copy()
            for side, joints in (("left", L), ("right", R)):
                for name, v in zip(TURNED_OUT_JOINTS, turned_out_leg(self.sk, side, turnout, lean, abduction)):
                    out[allj.index(joints[name])] = v
            return out

        first, second = legs(0.0, 0.0), legs(0.0, opened)
        # bending: the knees stay over the toes all the way down (the turned-out leg is not linear in the hinges)
        path = np.stack([legs(phi * k / 8, opened) for k in range(9)])
        working = 1 if rng.random() < 0.5 else 2  # stance code of the leg that stays while the other slides out
        speed = rng.uniform(1.2, 2.0)
        n = self._turn_out(h, allj, t, neutral, first, speed, L, R) if turnout else 0
        slide = min(speed, TENDU_SPEED_RAD_S)  # the working foot slides about 1.6 m per radian of opening
        if opened:
            m = self._write_move(h, allj, t + n, first, second, slide)
            self.stance[t + n:t + n + m] = working
            n += m
        n += self._write_path(h, allj, t + n, path, speed)
        n += self._hold(h, allj, t + n, int(beat * rng.choice([1, 2])), path[-1])
        speed = rng.uniform(1.2, 2.0)
        n += self._write_path(h, allj, t + n, path[::-1], speed)
        if opened:
            m = self._write_move(h, allj, t + n, second, first, min(speed, TENDU_SPEED_RAD_S))
            self.stance[t + n:t + n + m] = working
            n += m
        if turnout:
            n += self._turn_out(h, allj, t + n, first, neutral, speed, L, R)
        return n

    def _turn_out(self, h, allj, t, start, end, speed, L, R):
        """Turn the legs out (or in) one at a time from ``start`` to ``end`` (both legs' hinges over ``allj``):
        each foot turns unweighted on the floor while the other leg carries the weight."""
        n = 0
        cur = start.copy()
        for code, joints in ((2, L), (1, R)):  # the left foot turns while the right leg stands (code 2), then
            nxt = cur.copy()
            cols = [allj.index(j) for j in joints.values()]
            nxt[cols] = end[cols]
            m = self._write_move(h, allj, t + n, cur, nxt, speed)
            self.stance[t + n:t + n + m] = code
            n += m
            cur = nxt
        return n

    def _write_path(self, h, joints, t0, keyframes, speed):
        """Like :meth:`_write_move`, along a cubic spline through ``keyframes`` (K, len(joints)) evenly spaced in
        progress; the duration comes from the largest joint change between the first and last keyframe."""
        delta = np.max(np.abs(keyframes[-1] - keyframes[0]))
        n = max(int(round(self.fps * delta / max(speed * 0.8, 1e-3))), int(0.15 * self.fps), 2)
        full = n
        n = min(n, h.shape[0] - t0)
        if n <= 0:
            return 0
        path = CubicSpline(np.linspace(0.0, 1.0, len(keyframes)), keyframes, axis=0)
        h[t0:t0 + n][:, joints] = path(ramp_profile(full)[:n])
        return n

    def _walk(self, h, yaw, t, style, beat, rng):
        """Travelling: 3-6 steps forward or backward (inverted pendulum: the stance leg swings from in front to
        behind while the other leg swings through with a bent knee and lands symmetrically, so both feet are on
        the floor at each change of weight). The stance foot stays flat and pinned (:meth:`place_root` moves the
        root over it), so the root travels 2 L sin(a) per step (L hip -> ankle, a = step angle, rad). Solo dancers
        curve their path by pivoting the stance foot (up to ``style.curve_rad`` per step); every path turns back
        toward the start when it would leave ``style.travel_radius_m``. Returns the frames written."""
        T = h.shape[0]
        legs = {"left": leg_joints("left"), "right": leg_joints("right")}
        bones = self.sk.bone_lengths
        leg_len = float(bones[6] + bones[7])
        a = rng.uniform(*style.step_rad)
        steps = int(rng.integers(3, 7))
        # frames of a step (the first and last: half steps): one per beat, two per beat in slow music
        full = max(int(round(beat if beat <= 0.6 * self.fps else beat / 2)), int(0.5 * self.fps))
        half = max(int(round(0.75 * full)), int(0.4 * self.fps))
        self.step_frames = full
        heading = self.start_yaw + yaw[t - 1 if t else 0]
        forward = np.array([np.cos(heading), np.sin(heading)])
        to_home = self.home - self.pos
        length = 2 * leg_len * np.sin(a) * steps
        if np.linalg.norm(to_home) + length > style.travel_radius_m:  # head back toward the start
            sign = 1.0 if forward @ to_home >= 0 else -1.0
            # about as many steps as bring the dancer home (the first and last are half steps)
            steps = int(np.clip(round(np.linalg.norm(to_home) / (2 * leg_len * np.sin(a))), 3, 6))
            want = np.arctan2(to_home[1], to_home[0]) - np.arctan2(sign * forward[1], sign * forward[0])
            want = (want + np.pi) % (2 * np.pi) - np.pi
            curve = 0.0 if style.couple else max(style.curve_rad, 0.25)  # partners keep their line
            delta = float(np.clip(want / steps, -curve, curve))
            if np.linalg.norm(to_home) < 0.3 and abs(forward @ to_home) < 0.1:
                sign = float(rng.choice([-1.0, 1.0]))
        else:
            sign = 1.0 if rng.random() < 0.7 else -1.0
            delta = float(rng.uniform(-style.curve_rad, style.curve_rad))
        l1, l2 = float(bones[6]), float(bones[7])
        k0 = float(REST[legs["left"]["knee_flex"]])
        r_max = np.sqrt(l1 * l1 + l2 * l2 + 2 * l1 * l2 * np.cos(k0))  # hip -> ankle with the rest knee bend
        G = legs["left"]
        x_c, z_rest = leg_fk(REST[G["hip_extend"]], REST[G["knee_flex"]], l1, l2)  # the rest pose's ankle
        r_walk = 0.985 * r_max  # knees never quite straight while walking (the IK stays well conditioned)
        X = r_walk * np.sin(a)  # ankle in front of / behind its rest place at a weight change (m)
        H = np.sqrt(r_walk ** 2 - (abs(x_c) + X) ** 2)  # hip height above the ankles while walking (m)
        # phases: (stance ankle's x behind its rest place at start, at end; hip height at start, at end; frames)
        phases = ([(0.0, X, z_rest, H, half)] + [(-X, X, H, H, full)] * (steps - 1) + [(-X, 0.0, H, z_rest, half)])
        if t + sum(ph[-1] for ph in phases) > T:
            return 0
        stance_side = str(rng.choice(["left", "right"]))
        lift = rng.uniform(0.05, 0.09)  # the swinging foot's clearance at mid-swing (m)
        t0 = t
        for k, (x0, x1, z0, z1, n) in enumerate(phases):
            swing_side = "right" if stance_side == "left" else "left"
            p = 0.5 - 0.5 * np.cos(np.pi * (np.arange(1, n + 1) / n))  # C1: zero speed at each weight change
            x = sign * (x0 + (x1 - x0) * p)  # stance ankle behind the hip (m); the swinging ankle mirrors it
            # the hip leaves / reaches its rest height with zero slope: near the straight rest knee the IK is
            # steep (knee ~ sqrt of the missing reach), so a linear approach would snap the knee
            z = z0 + (z1 - z0) * (p * p if k == 0 else 1 - (1 - p) ** 2 if k == len(phases) - 1 else p)
            # the swinging foot rises at once (sin, not sin^2: it does not brush the floor while it travels); its
            # speed is still zero at lift-off and touch-down, where p has zero slope
            for side, xs, zs in ((stance_side, x_c + x, z), (swing_side, x_c - x, z - lift * np.sin(np.pi * p))):
                G = legs[side]
                theta, knee = leg_ik(xs, zs, l1, l2, k0)
                flat = REST[G["hip_extend"]] + REST[G["knee_flex"]] + REST[G["ankle_plantarflex"]]
                h[t:t + n, G["hip_extend"]] = theta
                h[t:t + n, G["knee_flex"]] = knee
                h[t:t + n, G["ankle_plantarflex"]] = flat - theta - knee  # the sole stays level
                for j in ("hip_adduct", "hip_rotate", "ankle_invert", "toe_flex"):
                    h[t:t + n, G[j]] = REST[G[j]]
            self.stance[t:t + n] = 1 if stance_side == "left" else 2
            yaw[t:t + n] = yaw[t - 1 if t else 0] + delta * p
            yaw[t + n:] = yaw[t + n - 1]
            self.pos = self.pos + sign * (abs(x1) + abs(x0)) * np.array([np.cos(heading), np.sin(heading)])
            heading += delta
            t += n
            stance_side = swing_side
        self.walks.append((t0, t))
        return t - t0

    def _turn(self, h, yaw, t, style, beat, rng):
        T = h.shape[0]
        if style.couple:  # partners turn whole turns, so they face each other again afterwards
            angle = rng.choice([-1, 1]) * 2 * np.pi
        else:
            angle = rng.choice([-1, 1]) * rng.uniform(0.5, 1.0) * 2 * np.pi * (2 if style.name == "ballet" else 1)
        rate = rng.uniform(3.0, 6.0)
        full = max(int(round(self.fps * abs(angle) / rate)), 4)
        n = min(full, T - t)
        if n < 4:
            return 0
        yaw[t:t + n] = yaw[t - 1 if t else 0] + angle * ramp_profile(full, 0.15)[:n]
        yaw[t + n:] = yaw[t + n - 1]
        return n

    def _flip(self, pitch, t, rng):
        n = int(round(self.fps * rng.uniform(0.65, 0.8)))
        if t + n >= pitch.shape[0]:
            return 0
        pitch[t:t + n] = pitch[t] + 2 * np.pi * ramp_profile(n, 0.1) * rng.choice([-1, 1])
        pitch[t + n:] = pitch[t + n - 1]
        return n

    def _hips(self, h, t, kind, style, rng, L, R):
        """Hip isolations with both feet planted: the legs tilt as a parallelogram (lateral: hip ab/adduction with
        ankle inversion; sagittal: hip flexion with plantarflexion), small enough that the legs stay below the
        still threshold while the pelvis moves several centimetres."""
        T = h.shape[0]
        freq = rng.uniform(0.8, 1.05)
        if kind == "hips_shift":
            amp = rng.uniform(0.035, 0.045) * rng.choice([-1, 1])
            n = min(int(round(self.fps * rng.uniform(0.3, 0.45))), T - t)
            lat = amp * ramp_profile(n)
            sag = np.zeros(n)
            back_hold = int(round(self.fps * rng.uniform(0.4, 0.7)))
            lat = np.r_[lat, np.full(back_hold, amp), amp * (1 - ramp_profile(n))]
            sag = np.zeros(lat.shape[0])
        elif kind == "hips_jitter":
            n = int(round(self.fps * rng.uniform(0.8, 1.3)))
            tt = np.arange(n) / self.fps
            env = envelope(n, self.fps, 0.1)
            lat = 0.008 * env * sum(np.sin(2 * np.pi * rng.uniform(3.2, 4.2) * tt + rng.uniform(0, 6.3)) for _ in range(2))
            sag = np.zeros(n)
        else:
            periods = rng.uniform(2.2, 3.5)
            n = int(round(self.fps * periods / freq))
            tt = np.arange(n) / self.fps
            env = envelope(n, self.fps, 0.25)
            a = 0.04
            w = 2 * np.pi * freq
            if kind == "hips_circle":
                lat, sag = a * env * np.sin(w * tt), a * env * np.cos(w * tt) - a * env
            elif kind == "hips_eight":
                lat, sag = a * env * np.sin(w * tt), 0.6 * a * env * np.sin(2 * w * tt)
            else:  # wave: side-to-side sway
                lat, sag = a * env * np.sin(w * tt), np.zeros(n)
        n = min(lat.shape[0], T - t)
        lat, sag = lat[:n], sag[:n]
        for s, sign in ((L, 1.0), (R, -1.0)):
            h[t:t + n, s["hip_adduct"]] = sign * lat
            h[t:t + n, s["ankle_invert"]] = -sign * lat
            h[t:t + n, s["hip_extend"]] = sag
            h[t:t + n, s["ankle_plantarflex"]] = -sag
        return n

    def _gesture(self, h, t, style, beat, rng, declared, prims):
        """One leg gestures (lift, 1-3 primitives, return) while the other stands still."""
        T = h.shape[0]
        side = rng.choice(["left", "right"])
        G = leg_joints(side)
        gj = [G["hip_adduct"], G["hip_extend"], G["hip_rotate"], G["knee_flex"], G["ankle_plantarflex"]]
        t0 = t
        gesture_side = side
        cur = h[t - 1, gj].copy() if t > 0 else h[0, gj].copy()
        amp = style.amplitude
        turnout = style.turnout_rad[0]  # the genre's least turnout: a ballet leg gestures turned out
        lift = np.array([rng.uniform(-0.35, 0.0) * amp, rng.uniform(-0.7, 0.3) * amp, rng.uniform(-0.4, 0.6) - turnout,
                         rng.uniform(0.35, 1.2), 0.0])  # the foot stays flexed until the leg is up
        phi = rng.uniform(0.3, 0.45)
        vertical = np.array([cur[0], -phi, cur[2], 2 * phi + REST[gj[3]], 0.0])  # the foot rises straight up
        t += self._write_move(h, gj, t, cur, vertical, self._speed(style, rng))
        t += self._hold(h, gj, t, int(0.35 * self.fps), vertical)
        h[t:, gj] = vertical
        lifted_from = t  # the foot is off the floor from here on: on its way to the lift it must clear the floor
        t += self._write_move(h, gj, t, vertical, lift, self._speed(style, rng))
        t += self._hold(h, gj, t, int(0.35 * self.fps), lift)
        h[t:, gj] = lift
        kinds = list(style.gesture)
        w = np.array([style.gesture[k] for k in kinds], dtype=float)
        for _ in range(int(rng.integers(1, 4))):
            if t >= T:
                break
            cur = h[t - 1, gj].copy()
            h[t:, gj + [G["ankle_invert"]]] = h[t - 1, gj + [G["ankle_invert"]]]
            kind = kinds[rng.choice(len(kinds), p=w / w.sum())]
            n = 0
            if kind == "move" and rng.random() < 0.5:  # a held leg position: front, side, back or high
                tgt = cur.copy()
                pos = rng.choice(["front", "side", "back", "back", "high"])
                tgt[:4] = {"front": [0.0, -rng.uniform(0.7, 1.0), cur[2], rng.uniform(0.0, 0.1)],
                           "side": [-rng.uniform(0.6, 0.85), -rng.uniform(0.0, 0.1), cur[2], 0.0],
                           "back": [0.0, rng.uniform(0.6, 0.85), cur[2], rng.uniform(0.0, 1.3)],
                           "high": [-rng.uniform(0.0, 0.3), -rng.uniform(1.6, 1.9), cur[2], rng.uniform(0.0, 0.2)]}[pos]
                n = self._write_move(h, gj, t, cur, tgt, self._speed(style, rng))
            elif kind == "move":
                tgt = cur.copy()
                j = rng.choice([0, 1, 3])
                lo, hi = {0: (-0.9 * amp, 0.1), 1: (-1.5 * amp, 0.5), 3: (0.2, 1.9)}[j]
                tgt[j] = rng.uniform(lo, hi)
                if abs(tgt[j] - cur[j]) < 0.35:
                    tgt[j] = np.clip(cur[j] + np.sign(rng.random() - 0.5) * 0.5, lo, hi)
                n = self._write_move(h, gj, t, cur, tgt, self._speed(style, rng))
            elif kind == "kick":
                tgt = cur.copy()
                tgt[1] = -rng.uniform(1.3, 1.8) * amp  # straight out and back: only the hip moves
                fast = rng.uniform(8.0, 10.0)
                n = self._write_move(h, gj, t, cur, tgt, fast)
                n += self._write_move(h, gj, t + n, tgt, cur, fast)
            elif kind in ("swing", "circle"):
                centre = cur.copy()
                centre[1] = rng.uniform(-0.9, -0.5) * amp
                centre[0] = rng.uniform(-0.5, -0.3) if kind == "circle" else cur[0]
                centre[3] = rng.uniform(0.0, 0.2)
                pre = self._settle(h, gj, t, cur, centre)
                freq = rng.uniform(*style.osc_hz)
                if kind == "circle":
                    sel = [G["hip_adduct"], G["hip_extend"]]
                    m = self._oscillate(h, sel, t + pre, centre[:2], [0.3, 0.35], [0.0, np.pi / 2], freq,
                                        rng.uniform(2, 3))
                    lab = "circle"
                else:
                    m = self._oscillate(h, [G["hip_extend"]], t + pre, centre[1:2], [0.45], [0.0], freq,
                                        rng.uniform(2, 3))
                    lab = "oscillation"
                if m:
                    declared.append(Declared(t + pre, t + pre + m, (f"{side}_upper_leg", f"{side}_lower_leg"), lab))
                n = pre + m
            elif kind == "knee":
                centre = cur.copy()
                centre[3] = rng.uniform(0.9, 1.3)
                centre[1] = min(cur[1], -0.3)
                pre = self._settle(h, gj, t, cur, centre)
                m = self._oscillate(h, [G["knee_flex"]], t + pre, centre[3:4], [0.55], [0.0],
                                    rng.uniform(*style.osc_hz), rng.uniform(2, 3))
                if m:
                    declared.append(Declared(t + pre, t + pre + m, (f"{side}_lower_leg",), "oscillation"))
                n = pre + m
            elif kind == "foot":
                tgt = cur.copy()
                tgt[4] = rng.choice([rng.uniform(0.8, 1.3), rng.uniform(-0.7, -0.5), 0.0])
                n = self._write_move(h, gj, t, cur, tgt, rng.uniform(3.0, 6.0))
                if rng.random() < 0.3:  # roll the foot on its edge: no label (Unknown)
                    inv = G["ankle_invert"]
                    m = self._write_move(h, [inv], t, h[t - 1, [inv]], np.array([rng.choice([-1, 1]) * 0.45]), 3.0)
                    m += self._hold(h, [inv], t + m, int(beat), h[t + m - 1, [inv]])
                    m += self._write_move(h, [inv], t + m, h[t + m - 1, [inv]], np.array([0.0]), 3.0)
                    h[t + n:t + m, gj] = h[t + n - 1, gj] if m > n else h[t + n:t + m, gj]
                    n = max(n, m)
            elif kind == "jitter":
                sel = [G["hip_extend"], G["hip_adduct"]]
                n = self._jitter(h, sel, t, h[t - 1, sel], 0.08, rng)
                if n:
                    declared.append(Declared(t, t + n, (f"{side}_upper_leg", f"{side}_lower_leg"), "jitter"))
            if kind != "hold" and n:
                prims.append((f"{side}_leg", kind, t, t + n))
            t += n
            t += self._hold(h, gj + [G["ankle_invert"]], t, max(int(beat), int(0.4 * self.fps)),
                            h[t - 1, gj + [G["ankle_invert"]]])
        self.airtime[lifted_from:t] = True  # the gesture foot must clear the floor here
        if t < T:  # relax the foot while the leg is still up, then put the leg down
            both = gj + [G["ankle_invert"]]
            cur = h[t - 1, both].copy()
            flat = cur.copy()
            flat[4:] = 0.0
            if np.max(np.abs(flat - cur)) > 1e-6:
                t += self._write_move(h, both, t, cur, flat, self._speed(style, rng))
                t += self._hold(h, both, t, int(0.35 * self.fps), flat)
                h[t:, both] = flat
            vertical = np.r_[0.0, -0.35, 0.0, 0.7, 0.0, 0.0] + REST[both]  # and lands straight down
            t += self._write_move(h, both, t, flat, vertical, self._speed(style, rng))
            t += self._hold(h, both, t, int(0.35 * self.fps), vertical)
            h[t:, both] = vertical
            t += self._write_move(h, both, t, vertical, REST[both], self._speed(style, rng))
        self.stance[t0:t] = 2 if gesture_side == "left" else 1
        return t - t0

    # ---- root placement --------------------------------------------------------------------------------------
    def _steady_head(self, h, prims, iterations=2):
        """Neck moves, circles and shakes tilt the neck as an Euler sequence (bend, then flex), which also turns
        the head a little about the neck (the twist of a combined tilt). Cancel that with the neck twist, so the head
        keeps the direction its own primitives give it, as the neck primitive intends."""
        from hdvr.movements.labeller import head_yaw as measured_yaw

        j = JI["neck_twist"]
        tilt = _j("neck_bend", "neck_flex")
        for g, _, s, e in prims:
            if g != "neck":
                continue
            e = min(e, h.shape[0])
            if e - s < 3:
                continue
            s = max(s - 1, 0)

            def head_yaw(hinges):
                q = np.zeros((e - s, 41))
                q[:, 3] = 1.0
                q[:, ROOT_QPOS:] = hinges
                return measured_yaw(self.sk.keypoints(q))

            still_neck = h[s:e].copy()
            still_neck[:, tilt] = h[s, tilt]  # the same head motion without the neck's shape
            reference = head_yaw(still_neck)
            before = h[s:e, j].copy()
            for _ in range(iterations):
                h[s:e, j] = np.clip(h[s:e, j] - (head_yaw(h[s:e]) - reference), LOWER[j], UPPER[j])
            # a move ends on a new tilt: its correction stays while the neck holds it (shapes end at rest: ~0)
            h[e:, j] = np.clip(h[e:, j] + (h[e - 1, j] - before[-1]), LOWER[j], UPPER[j])
        return h

    def _clear_gesture_foot(self, h, stance, clearance=0.02, iterations=6):
        """Raise a gesturing foot that would come closer to the floor than the standing foot + ``clearance``
        (m) by bending its knee more, while the leg is up (``self.airtime``: between the straight-up lift and the
        straight-down landing of each phrase). Keeps the weight on the standing leg."""
        if not (stance > 0).any():
            return h
        rows = np.flatnonzero(stance > 0)
        taper = uniform_filter1d(self.airtime.astype(float), 5, mode="nearest")
        want = clearance * taper
        shank = float(self.sk.bone_lengths[7])
        for _ in range(iterations):
            q = np.zeros((rows.size, 41))
            q[:, 3] = 1.0
            q[:, ROOT_QPOS:] = h[rows]
            kp = self.sk.keypoints(q)
            low = {s: kp[:, list(ix), 2].min(1) for s, ix in SOLE_KEYPOINTS.items()}
            changed = False
            for code, stand, gest in ((1, "left", "right"), (2, "right", "left")):
                sel = stance[rows] == code
                deficit = np.where(sel, low[stand] + want[rows] - low[gest], 0.0)
                if not (deficit > 1e-4).any():
                    continue
                changed = True
                j = JI[f"{gest}_knee_flex"]
                raw = np.zeros(h.shape[0])
                raw[rows] = np.arccos(np.clip(1 - np.maximum(deficit, 0) / shank, -1, 1))
                # a smooth upper envelope: widen the peaks, then average (slope <= peak / 9 per frame)
                extra = uniform_filter1d(maximum_filter1d(raw, 9, mode="nearest"), 9, mode="nearest")
                h[:, j] = np.clip(h[:, j] + extra * taper * (stance == code), LOWER[j], UPPER[j])
            if not changed:
                break
            # only frames near a remaining deficit need another look (the correction spreads over +-8 frames)
            near = np.zeros(h.shape[0], dtype=bool)
            for code, stand, gest in ((1, "left", "right"), (2, "right", "left")):
                d = np.zeros(h.shape[0])
                d[rows] = np.where(stance[rows] == code, low[stand] + want[rows] - low[gest], 0.0)
                near |= maximum_filter1d((d > 1e-4).astype(np.uint8), 17) > 0
            rows = np.flatnonzero(near & (stance > 0))
            if rows.size == 0:
                break
        return h

    def place_root(self, hinges, yaw, pitch, start_xy, start_yaw, stance=None):
        """qpos (T, 41) and keypoints (T, 25, 3): lowest sole point on the floor, stance foot pinned, flips airborne."""
        T = hinges.shape[0]
        q = np.zeros((T, 41))
        q[:, ROOT_QPOS:] = hinges
        ang = start_yaw + yaw
        half_y, half_p = ang / 2, pitch / 2
        qz = np.stack([np.cos(half_y), np.zeros(T), np.zeros(T), np.sin(half_y)], 1)
        qy = np.stack([np.cos(half_p), np.zeros(T), np.sin(half_p), np.zeros(T)], 1)
        q[:, 3:7] = _quat_mul(qz, qy)
        kin = plan_kinematics(self.sk, q)  # root at the origin: keypoints and body rotations of the plan
        rel = kin["keypoints"]
        airborne = np.abs(np.gradient(pitch)) > 1e-9
        airborne = np.convolve(airborne, np.ones(3), mode="same") > 0
        soles = {s: rel[:, list(ix)] for s, ix in SOLE_KEYPOINTS.items()}
        lowest = {s: soles[s][..., 2].min(1) for s in soles}
        root = np.zeros((T, 3))
        root[:, 2] = -np.minimum(lowest["left"], lowest["right"])  # no sole point below the floor
        # flips: a ballistic arc high enough that no keypoint goes below the floor
        for s, e, v in _runs(airborne):
            if not v:
                continue
            n = e - s
            tt = np.linspace(0, 1, n)
            need = -rel[s:e, :, 2].min(1) + 0.05
            base = np.linspace(root[max(s - 1, 0), 2], root[min(e, T - 1), 2], n)
            apex = max(0.0, float(np.max(need - base)) / 1.0)
            root[s:e, 2] = np.maximum(base + 4 * apex * tt * (1 - tt) * 1.1, need)
        # horizontal: pin the stance foot
        centres = {side: soles[side][..., :2].mean(1) for side in soles}
        low_l, low_r = lowest["left"].tolist(), lowest["right"].tolist()
        left_stance = np.empty(T, dtype=bool)
        stance_left = True
        forced = np.zeros(T, dtype=np.int8) if stance is None else stance
        for t in range(T):
            if forced[t]:
                stance_left = forced[t] == 1
            elif stance_left and low_r[t] < low_l[t] - 0.004:
                stance_left = False
            elif not stance_left and low_l[t] < low_r[t] - 0.004:
                stance_left = True
            left_stance[t] = stance_left
        stance_centre = np.where(left_stance[:, None], centres["left"], centres["right"])
        prev_centre = np.where(left_stance[1:, None], centres["left"][:-1], centres["right"][:-1])
        step = prev_centre - stance_centre[1:]  # move the root so the stance foot stays where it was
        step[airborne[1:] | airborne[:-1]] = 0.0
        root[:, :2] = np.asarray(start_xy, dtype=float) + np.r_[np.zeros((1, 2)), np.cumsum(step, axis=0)]
        q[:, :3] = root
        self.kinematics = {**kin, "keypoints": rel + root[:, None, :]}  # rotations do not depend on the root position
        return q, rel + root[:, None, :], airborne

    # ---- top level -------------------------------------------------------------------------------------------
    def generate(self, genre: str, seconds: float, rng: np.random.Generator, start_xy=(0.0, 0.0),
                 start_yaw: float = 0.0, mirror_of: "Choreography | None" = None) -> Choreography:
        style = genre_style(genre)
        T = max(int(round(seconds * self.fps)), 3)
        bpm = rng.uniform(*style.bpm)
        beat = self._beat_frames(style, bpm)
        if mirror_of is not None:
            return self._mirror(mirror_of, start_xy, start_yaw)
        self.reach_cap = PARTNER_REACH_CAP_RAD if style.couple else None
        h = np.tile(REST, (T, 1))
        yaw = np.zeros(T)
        pitch = np.zeros(T)
        declared: list[Declared] = []
        prims: list = []
        for group in ("head", "neck", "trunk"):
            self._group(h, group, style, getattr(style, group), beat, rng, declared, prims, self._parts_for_shape)
        symmetric = rng.random() < style.symmetric_arms
        if symmetric:
            self._group(h, "left_arm", style, style.arm, beat, rng, declared, prims, self._parts_for_shape)
            _mirror_arm(h)
            declared += [Declared(d.start, d.end, tuple(p.replace("left", "right") for p in d.parts), d.label)
                         for d in declared if any(p.startswith("left_") and "arm" in p for p in d.parts)]
        else:
            for group in ("left_arm", "right_arm"):
                self._group(h, group, style, style.arm, beat, rng, declared, prims, self._parts_for_shape)
        self.stance = np.zeros(T, dtype=np.int8)
        self.airtime = np.zeros(T, dtype=bool)
        self.home = np.asarray(start_xy, dtype=float)
        self.pos = self.home.copy()
        self.start_yaw = float(start_yaw)
        self.walks = []
        self._legs(h, yaw, pitch, style, beat, rng, declared, prims)
        h = np.clip(h, LOWER, UPPER)
        h = self._steady_head(h, prims)
        h = self._clear_gesture_foot(h, self.stance)
        q, kp, airborne = self.place_root(h, yaw, pitch, start_xy, start_yaw, self.stance)
        intents = [Intent("legs" if g.endswith("_leg") else g, k, s, e) for g, k, s, e in prims]
        if symmetric:  # the right arm performs the left arm's primitives
            intents += [Intent("right_arm", it.kind, it.start, it.end) for it in intents if it.group == "left_arm"]
        labels = declared_labels(self.tax, self.sk, q, start_yaw + yaw, pitch, intents, declared, self.fps,
                                 self.kinematics)
        return Choreography(style.name, self.fps, q, kp, labels, airborne, intents, declared, self.stance.copy(),
                            list(self.walks), self.sk.bone_lengths)

    def _mirror(self, lead: Choreography, start_xy, start_yaw) -> Choreography:
        """The partner: the lead's motion mirrored left/right (a couple facing each other moves as mirror images)."""
        h = _mirror_hinges(lead.qpos[:, ROOT_QPOS:])
        bones_l = lead.bones if lead.bones is not None else self.sk.bone_lengths
        bones_f = self.sk.bone_lengths
        k0 = float(REST[JI["left_knee_flex"]])
        scale = (bones_f[6] + bones_f[7]) / (bones_l[6] + bones_l[7])
        for s, e in lead.walks:  # the lead walks forward, the partner facing it backward, the same distance
            for side in ("left", "right"):
                G = leg_joints(side)
                flat = REST[G["hip_extend"]] + REST[G["knee_flex"]] + REST[G["ankle_plantarflex"]]
                x, z = leg_fk(h[s:e, G["hip_extend"]], h[s:e, G["knee_flex"]], bones_l[6], bones_l[7])
                theta, knee = leg_ik(-x, z * scale, bones_f[6], bones_f[7], k0)
                h[s:e, G["hip_extend"]] = theta
                h[s:e, G["knee_flex"]] = knee
                h[s:e, G["ankle_plantarflex"]] = flat - theta - knee
        yaw = -_unwrapped_yaw(lead.qpos)
        yaw = yaw - yaw[0]
        pitch = _unwrapped_pitch(lead.qpos)
        stance = np.where(lead.stance == 1, 2, np.where(lead.stance == 2, 1, 0)).astype(np.int8)
        q, kp, airborne = self.place_root(h, yaw, pitch, start_xy, start_yaw, stance)
        declared = [Declared(d.start, d.end, tuple(_swap_side(p) for p in d.parts), d.label) for d in lead.declared]
        intents = [Intent(_swap_side(it.group), it.kind, it.start, it.end) for it in lead.primitives]
        labels = declared_labels(self.tax, self.sk, q, start_yaw + yaw, pitch, intents, declared, self.fps,
                                 self.kinematics)
        return Choreography(lead.genre, self.fps, q, kp, labels, airborne, intents, declared, stance,
                            list(lead.walks), self.sk.bone_lengths)


def _swap_side(name: str) -> str:
    if name.startswith("left_"):
        return "right_" + name[5:]
    if name.startswith("right_"):
        return "left_" + name[6:]
    return name


_MIRROR_NEGATE = _j("lumbar_bend", "lumbar_twist", "neck_bend", "neck_twist", "head_roll")
_MIRROR_PERM = [JI[_swap_side(n)] for n in dh.JOINT_NAMES]


def _mirror_hinges(h):
    out = h[:, _MIRROR_PERM].copy()
    out[:, _MIRROR_NEGATE] *= -1
    return out


def _mirror_arm(h):
    for k in ("shoulder_abduct", "shoulder_flex", "shoulder_rotate", "elbow_flex"):
        h[:, JI[f"right_{k}"]] = h[:, JI[f"left_{k}"]]


def _quat_mul(a, b):
    w1, x1, y1, z1 = a.T
    w2, x2, y2, z2 = b.T
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], 1)


def _unwrapped_yaw(q):
    w, x, y, z = q[:, 3:7].T
    return np.unwrap(np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))


def _unwrapped_pitch(q):
    """Pitch of the generator's yaw * pitch composition (the angle about the body's y axis), unwrapped."""
    yaw = _unwrapped_yaw(q)
    half = yaw / 2
    qz_inv = np.stack([np.cos(half), np.zeros_like(half), np.zeros_like(half), -np.sin(half)], 1)
    qy = _quat_mul(qz_inv, q[:, 3:7])
    return np.unwrap(2 * np.arctan2(qy[:, 2], qy[:, 0]))


def foot_metrics(keypoints: np.ndarray, airborne: np.ndarray, fps: float, contact_m: float = 0.005,
                 stance: np.ndarray | None = None) -> dict:
    """Penetration (m: deepest sole keypoint below z = 0) and skating (m/s) of a motion (T, 25, 3).

    A foot is planted in a frame when its lowest sole point (big toe, small toe, heel) is below ``contact_m``
    in that frame and the frames before and after (lift-off and touch-down frames are not planted; flips are
    excluded). Its skating speed between two planted frames is the horizontal speed of the point that moves
    least among the sole points in contact and the sole centre: zero when the foot pivots about its centre or
    peels off over its toes, the sliding speed when the whole foot slides. With ``stance`` (T,) (0 both feet,
    1 left, 2 right carries the weight) only weight-bearing feet count: a gesturing foot that brushes the floor
    (tendu, lift-off) is not skating."""
    penetration = float(max(0.0, -keypoints[:, [19, 20, 21, 22, 23, 24], 2].min()))
    speeds = []
    for code, ix in ((1, SOLE_KEYPOINTS["left"]), (2, SOLE_KEYPOINTS["right"])):
        sole = keypoints[:, list(ix)]
        contact = (sole[..., 2].min(1) < contact_m) & ~airborne
        if stance is not None:
            contact &= (stance == 0) | (stance == code)
        planted = contact & np.r_[False, contact[:-1]] & np.r_[contact[1:], False]
        both = planted[1:] & planted[:-1]
        points = np.concatenate([sole, sole.mean(1, keepdims=True)], axis=1)  # (T, 4, 3)
        v = np.linalg.norm(np.diff(points[..., :2], axis=0), axis=-1) * fps  # (T-1, 4)
        touching = np.concatenate([sole[..., 2] < contact_m, np.ones((sole.shape[0], 1), bool)], axis=1)
        v = np.where(touching[1:] & touching[:-1], v, np.inf).min(1)
        speeds.append(v[both])
    skate = np.concatenate(speeds)
    return {"penetration_m": penetration, "skate_max_m_s": float(skate.max()) if skate.size else 0.0,
            "skate_p99_m_s": float(np.percentile(skate, 99)) if skate.size else 0.0,
            "skate_mean_m_s": float(skate.mean()) if skate.size else 0.0}
