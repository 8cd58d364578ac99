"""BVH motion files: reader (joint positions per frame) and writer (the dancer's motion, for Blender).

Axes: BVH files are Y-up. HDVR's world is x forward, y to the dancer's left, z up (metres). For a BVH character
that faces +Z with its left along +X (the CMU files), ``(x, y, z)_hdvr = (z, x, y)_bvh`` (:data:`BVH_TO_HDVR`).

Rotations: each joint's channels are applied in the listed order as intrinsic rotations (``Zrotation Xrotation
Yrotation`` means R = Rz Rx Ry, degrees); a child's position is ``p_parent + R_parent_world @ offset``. Euler angles
are turned into matrices with scipy (batched), never differenced as raw angles.

Units: :meth:`BVHMotion.positions` scales file units to metres either by a known factor or, by default, by
normalising the subject's stature: stature = (eye height in the file's rest pose) / 0.936 (eye height is 93.6 % of
stature in Drillis & Contini's segment proportions), scaled to ``height_m`` (1.70 m by default). The CMU salsa
files are rescaled by their distributor (eye-to-foot about 1.16 units), so their unit is not the metre.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from hdvr.errors import HDVRError
from hdvr.io.atomic import write_text_atomic
from hdvr.layouts import BODY25_NAMES

#: Permutation taking BVH (X left, Y up, Z forward) vectors to HDVR (x forward, y left, z up).
BVH_TO_HDVR = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
EYE_HEIGHT_FRACTION = 0.936
DEFAULT_STATURE_M = 1.70


@dataclass
class BVHJoint:
    name: str
    parent: int  # -1 for the root
    offset: np.ndarray  # (3,) file units, BVH axes
    channels: tuple[str, ...]  # e.g. ("Xposition", ..., "Zrotation"); () for an end site
    is_end_site: bool = False


@dataclass
class BVHMotion:
    """A parsed BVH file: the hierarchy (joints incl. end sites, parents before children) and channel data."""

    joints: list[BVHJoint]
    frame_time: float  # seconds
    motion: np.ndarray  # (T, total channels) file units / degrees
    source: str = ""
    _channel_start: list[int] = field(default_factory=list)

    def __post_init__(self) -> None:
        start, starts = 0, []
        for j in self.joints:
            starts.append(start)
            start += len(j.channels)
        self._channel_start = starts
        if self.motion.ndim != 2 or self.motion.shape[1] != start:
            raise HDVRError(f"BVH {self.source}: motion rows have {self.motion.shape[-1]} values, "
                            f"the hierarchy declares {start} channels")

    @property
    def fps(self) -> float:
        return 1.0 / self.frame_time

    @property
    def num_frames(self) -> int:
        return int(self.motion.shape[0])

    @property
    def names(self) -> list[str]:
        return [j.name for j in self.joints]

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise HDVRError(f"BVH {self.source} has no joint {name!r}") from None

    def raw_positions(self, rest: bool = False) -> np.ndarray:
        """(T, J, 3) joint positions in file units and BVH axes; ``rest``: one frame of offsets only."""
        return self.raw_pose(rest)[0]

    def raw_pose(self, rest: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Joint positions (T, J, 3) in file units and world rotations (T, J, 3, 3), BVH axes."""
        motion = np.zeros((1, self.motion.shape[1])) if rest else self.motion
        t = motion.shape[0]
        pos = np.zeros((t, len(self.joints), 3))
        rot = np.zeros((t, len(self.joints), 3, 3))
        for j, joint in enumerate(self.joints):
            local_t = np.broadcast_to(joint.offset, (t, 3)).copy()
            local_r = np.broadcast_to(np.eye(3), (t, 3, 3))
            if joint.channels:
                c0 = self._channel_start[j]
                values = motion[:, c0:c0 + len(joint.channels)]
                rot_axes, rot_cols = "", []
                for k, ch in enumerate(joint.channels):
                    axis = ch[0].upper()
                    if ch.lower().endswith("position"):
                        local_t[:, "XYZ".index(axis)] += values[:, k] if not rest else 0.0
                    else:
                        rot_axes += axis
                        rot_cols.append(k)
                if rot_axes:
                    local_r = Rotation.from_euler(rot_axes, values[:, rot_cols], degrees=True).as_matrix()
            if joint.parent < 0:
                pos[:, j] = local_t
                rot[:, j] = local_r
            else:
                p = joint.parent
                pos[:, j] = pos[:, p] + np.einsum("tij,tj->ti", rot[:, p], local_t)
                rot[:, j] = rot[:, p] @ local_r
        return pos, rot

    def stature_units(self) -> float:
        """Estimated standing height in file units from the rest pose (eye height / 0.936, see module doc)."""
        rest = self.raw_positions(rest=True)[0]
        eyes = [i for i, n in enumerate(self.names) if "eye" in n.lower() and not self.joints[i].is_end_site]
        floor = rest[:, 1].min()
        if eyes:
            return float((rest[eyes, 1].mean() - floor) / EYE_HEIGHT_FRACTION)
        return float(rest[:, 1].max() - floor)  # no eyes: top of the hierarchy

    def positions(self, unit_scale: float | None = None, height_m: float = DEFAULT_STATURE_M) -> np.ndarray:
        """(T, J, 3) joint positions in metres, HDVR axes (x forward, y left, z up).

        ``unit_scale``: metres per file unit; None normalises the stature to ``height_m``.
        """
        return self.pose(unit_scale, height_m)[0]

    def pose(self, unit_scale: float | None = None, height_m: float = DEFAULT_STATURE_M
             ) -> tuple[np.ndarray, np.ndarray]:
        """Joint positions (T, J, 3) metres and world rotations (T, J, 3, 3), HDVR axes (see :meth:`positions`)."""
        scale = unit_scale if unit_scale is not None else height_m / self.stature_units()
        pos, rot = self.raw_pose()
        return scale * pos @ BVH_TO_HDVR.T, BVH_TO_HDVR @ rot @ BVH_TO_HDVR.T

    def rest_positions(self, unit_scale: float | None = None, height_m: float = DEFAULT_STATURE_M) -> np.ndarray:
        """(J, 3) joint positions of the file's rest pose (all rotations zero), metres, HDVR axes."""
        scale = unit_scale if unit_scale is not None else height_m / self.stature_units()
        return scale * self.raw_positions(rest=True)[0] @ BVH_TO_HDVR.T


def _tokens(text: str):
    for line_no, line in enumerate(text.splitlines(), 1):
        for tok in line.split():
            yield line_no, tok


def read_bvh(path: str | os.PathLike, skip_frames: int = 0) -> BVHMotion:
    """Parse a BVH file. ``skip_frames`` drops leading frames (CMU Indian files start with a T-pose frame)."""
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"BVH file not found: {p}")
    try:
        text = p.read_text(errors="strict")
    except UnicodeDecodeError:
        raise HDVRError(f"BVH file {p} is not text") from None
    head, sep, tail = text.partition("MOTION")
    if not sep or "HIERARCHY" not in head:
        raise HDVRError(f"BVH file {p} lacks a HIERARCHY or MOTION section")
    joints: list[BVHJoint] = []
    stack: list[int] = []
    toks = list(_tokens(head))
    i = 0
    pending: BVHJoint | None = None
    try:
        while i < len(toks):
            _, tok = toks[i]
            if tok in ("ROOT", "JOINT"):
                pending = BVHJoint(toks[i + 1][1], stack[-1] if stack else -1, np.zeros(3), ())
                i += 2
            elif tok == "End":
                parent = stack[-1]
                pending = BVHJoint(f"{joints[parent].name}_end", parent, np.zeros(3), (), True)
                i += 2
            elif tok == "{":
                joints.append(pending)
                stack.append(len(joints) - 1)
                i += 1
            elif tok == "}":
                stack.pop()
                i += 1
            elif tok == "OFFSET":
                joints[stack[-1]].offset = np.array([float(toks[i + k][1]) for k in (1, 2, 3)])
                i += 4
            elif tok == "CHANNELS":
                n = int(toks[i + 1][1])
                joints[stack[-1]].channels = tuple(toks[i + 2 + k][1] for k in range(n))
                i += 2 + n
            else:
                i += 1
    except (IndexError, ValueError):
        line = toks[min(i, len(toks) - 1)][0] if toks else 0
        raise HDVRError(f"BVH file {p}: malformed hierarchy near line {line}") from None
    if not joints or stack:
        raise HDVRError(f"BVH file {p}: empty or unbalanced hierarchy")
    m_frames = re.search(r"Frames:\s*(\d+)", tail)
    m_time = re.search(r"Frame Time:\s*([0-9.eE+-]+)", tail)
    if not m_frames or not m_time:
        raise HDVRError(f"BVH file {p}: MOTION section lacks 'Frames:' or 'Frame Time:'")
    body = tail[m_time.end():]
    try:
        values = np.array(body.split(), dtype=np.float64)
    except ValueError:
        raise HDVRError(f"BVH file {p}: non-numeric motion data") from None
    n_channels = sum(len(j.channels) for j in joints)
    n_frames = int(m_frames.group(1))
    if n_frames == 0 or values.size < n_frames * n_channels:
        raise HDVRError(f"BVH file {p}: declares {n_frames} frames of {n_channels} channels, has {values.size} "
                        "values")
    motion = values[: n_frames * n_channels].reshape(n_frames, n_channels)[skip_frames:]
    if motion.shape[0] == 0:
        raise HDVRError(f"BVH file {p}: no frames left after skipping {skip_frames}")
    return BVHMotion(joints, float(m_time.group(1)), motion, str(p))


# ---------------------------------------------------------------------------------------------------------------
# CMU skeleton (salsa, Indian dance) -> BODY_25.

#: BODY_25 joints read directly from CMU BVH joints (joint positions = the named BVH joint's origin).
CMU_BVH_TO_BODY25: dict[str, str] = {
    "right_shoulder": "rShldr", "right_elbow": "rForeArm", "right_wrist": "rHand",
    "left_shoulder": "lShldr", "left_elbow": "lForeArm", "left_wrist": "lHand",
    "right_hip": "rThigh", "right_knee": "rShin", "right_ankle": "rFoot",
    "left_hip": "lThigh", "left_knee": "lShin", "left_ankle": "lFoot",
    "right_eye": "rightEye", "left_eye": "leftEye",
    "right_big_toe": "rFoot_end", "left_big_toe": "lFoot_end",
}


def body25_from_bvh(motion: BVHMotion, positions: np.ndarray, rotations: np.ndarray | None = None,
                    rest: np.ndarray | None = None) -> np.ndarray:
    """BODY_25 (T, 25, 3) from CMU-skeleton joint positions (T, J, 3), metres, HDVR axes.

    Direct joints: :data:`CMU_BVH_TO_BODY25`. Derived (documented approximations):
    neck = midpoint of the shoulders; mid_hip = midpoint of the hips; nose = midpoint of the eyes;
    ears = head joint + 1.5 x (eye - mid-eyes) (lateral of the eyes, at the head joint's depth).
    Heel and small toe ride rigidly on the foot: in the file's rest pose (standing) the heel lies at the toe's
    height, 0.3 x the horizontal ankle-to-toe length behind the ankle, and the small toe 0.35 x that length
    outward of the big toe; with the foot joints' world ``rotations`` (T, J, 3, 3) and the ``rest`` positions
    (J, 3) these offsets follow the foot (a raised heel rises). Without rotations, the rest-pose rule is applied
    per frame (heel at toe height).
    """
    idx = {n: motion.index(b) for n, b in CMU_BVH_TO_BODY25.items()}
    out = np.full(positions.shape[:1] + (25, 3), np.nan)
    for name, i in idx.items():
        out[:, BODY25_NAMES.index(name)] = positions[:, i]

    def get(name):
        return out[:, BODY25_NAMES.index(name)]

    def put(name, value):
        out[:, BODY25_NAMES.index(name)] = value

    put("neck", (get("left_shoulder") + get("right_shoulder")) / 2)
    put("mid_hip", (get("left_hip") + get("right_hip")) / 2)
    mid_eyes = (get("left_eye") + get("right_eye")) / 2
    put("nose", mid_eyes)
    head = positions[:, motion.index("head")]

    def foot_points(ankle, toe, hip, mid_hip):
        """Heel and small toe for ankle/toe/hip/mid-hip arrays (..., 3) with the rest-pose rule."""
        horiz = (toe - ankle) * np.array([1.0, 1.0, 0.0])
        heel = ankle - 0.3 * horiz
        heel[..., 2] = toe[..., 2]
        length = np.linalg.norm(horiz, axis=-1, keepdims=True)
        outward = (hip - mid_hip) * np.array([1.0, 1.0, 0.0])
        outward /= np.maximum(np.linalg.norm(outward, axis=-1, keepdims=True), 1e-9)
        return heel, toe + 0.35 * length * outward

    for side, prefix in (("left", "l"), ("right", "r")):
        put(f"{side}_ear", head + 1.5 * (get(f"{side}_eye") - mid_eyes))
        if rotations is not None and rest is not None:
            r = {k: rest[motion.index(b)] for k, b in (("ankle", f"{prefix}Foot"), ("toe", f"{prefix}Foot_end"),
                                                        ("hip", f"{prefix}Thigh"))}
            rest_mid = (rest[motion.index("lThigh")] + rest[motion.index("rThigh")]) / 2
            heel0, small0 = foot_points(r["ankle"], r["toe"], r["hip"], rest_mid)
            foot_rot = rotations[:, motion.index(f"{prefix}Foot")]
            ankle = get(f"{side}_ankle")
            put(f"{side}_heel", ankle + foot_rot @ (heel0 - r["ankle"]))
            put(f"{side}_small_toe", ankle + foot_rot @ (small0 - r["ankle"]))
        else:
            heel, small = foot_points(get(f"{side}_ankle"), get(f"{side}_big_toe"), get(f"{side}_hip"),
                                      get("mid_hip"))
            put(f"{side}_heel", heel)
            put(f"{side}_small_toe", small)
    return out


def load_mocap_body25(path: str | os.PathLike, fps: float | None = None, height_m: float = DEFAULT_STATURE_M,
                      skip_frames: int | None = None) -> tuple[np.ndarray, float]:
    """Read a CMU-skeleton BVH as BODY_25 (T, 25, 3) metres (HDVR world), stature normalised to ``height_m``.

    ``fps`` resamples by linear interpolation (e.g. 120 -> 30). ``skip_frames`` defaults to 1 for files whose
    first frame is the converter's reference pose (detected: root rotation exactly zero there and not in the next
    frame, as in the CMU Indian files), else 0. Returns (positions, fps).
    """
    motion = read_bvh(path)
    if skip_frames is None:  # the converter's reference frame has an exactly zero root rotation
        root_rot = [k for k, ch in enumerate(motion.joints[0].channels) if ch.endswith("rotation")]
        first, second = motion.motion[0, root_rot], motion.motion[min(1, motion.num_frames - 1), root_rot]
        skip_frames = 1 if motion.num_frames > 1 and np.all(first == 0) and np.any(second != 0) else 0
    if skip_frames:
        motion = BVHMotion(motion.joints, motion.frame_time, motion.motion[skip_frames:], motion.source)
    positions, rotations = motion.pose(height_m=height_m)
    pos = body25_from_bvh(motion, positions, rotations, motion.rest_positions(height_m=height_m))
    src_fps = motion.fps
    if fps is None or abs(fps - src_fps) < 1e-9:
        return pos, src_fps
    t_src = np.arange(pos.shape[0]) / src_fps
    t_dst = np.arange(0.0, t_src[-1] + 1e-9, 1.0 / fps)
    flat = pos.reshape(pos.shape[0], -1)
    res = np.stack([np.interp(t_dst, t_src, flat[:, k]) for k in range(flat.shape[1])], axis=1)
    return res.reshape(-1, 25, 3), float(fps)


# ---------------------------------------------------------------------------------------------------------------
# Writer: the dancer's motion.


def write_dancer_bvh(path: str | os.PathLike, skeleton, qpos: np.ndarray, fps: float,
                     units_per_metre: float = 100.0) -> None:
    """Write the dancer's motion ``qpos`` (T, 41) as BVH (Y up, centimetres by default), atomically.

    One BVH joint per dancer body (pelvis root with 6 channels, others 3 rotation channels Z X Y), End Sites at
    the nose, hand tips and toe tips. The rest pose (all rotations zero) is the dancer's rest pose, so the file
    opens in Blender as a standing figure. Joint positions read back with :func:`read_bvh` equal the dancer's
    body origins (tested).
    """

    qpos = np.asarray(qpos, dtype=np.float64)
    if qpos.ndim != 2 or qpos.shape[1] != skeleton.model.nq or qpos.shape[0] == 0:
        raise HDVRError(f"qpos must be (T>0, {skeleton.model.nq}), got {qpos.shape}")
    m = skeleton.model
    bodies = list(range(1, m.nbody))  # depth-first order, parents first
    end_sites = {int(m.site(s).bodyid[0]): s for s in ("nose", "left_hand_tip", "right_hand_tip",
                                                           "left_toe_tip", "right_toe_tip")}
    hdvr_to_bvh = BVH_TO_HDVR.T

    def world_state(q):
        skeleton.kinematics(q)
        d = skeleton.data
        return d.xpos.copy(), d.xmat.reshape(-1, 3, 3).copy(), d.site_xpos.copy()

    rest_pos, rest_rot, rest_sites = world_state(skeleton.rest_qpos())
    lines = ["HIERARCHY"]

    def emit(b, depth):
        pad = "\t" * depth
        parent = m.body_parentid[b]
        name = m.body(b).name
        if parent == 0:
            lines.append(f"{pad}ROOT {name}")
            offset = np.zeros(3)  # the root's position channels carry its absolute position
            channels = "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
        else:
            lines.append(f"{pad}JOINT {name}")
            offset = rest_pos[b] - rest_pos[parent]
            channels = "CHANNELS 3 Zrotation Xrotation Yrotation"
        lines.append(f"{pad}{{")
        lines.append(f"{pad}\tOFFSET " + " ".join(f"{v:.6f}" for v in units_per_metre * hdvr_to_bvh @ offset))
        lines.append(f"{pad}\t{channels}")
        for child in (c for c in bodies if m.body_parentid[c] == b):
            emit(child, depth + 1)
        if b in end_sites:
            sid = m.site(end_sites[b]).id
            end = units_per_metre * hdvr_to_bvh @ (rest_sites[sid] - rest_pos[b])
            lines.extend([f"{pad}\tEnd Site", f"{pad}\t{{", f"{pad}\t\tOFFSET " + " ".join(f"{v:.6f}" for v in end),
                          f"{pad}\t}}"])
        lines.append(f"{pad}}}")

    emit(1, 0)
    lines += ["MOTION", f"Frames: {qpos.shape[0]}", f"Frame Time: {1.0 / fps:.8f}"]
    for q in qpos:
        pos, rot, _ = world_state(q)
        # rotation of each body relative to its rest orientation, in world axes, then local to the parent
        delta = rot @ np.transpose(rest_rot, (0, 2, 1))
        values = []
        for b in bodies:
            parent = m.body_parentid[b]
            local = delta[b] if parent == 0 else delta[parent].T @ delta[b]
            local_bvh = hdvr_to_bvh @ local @ hdvr_to_bvh.T
            euler = Rotation.from_matrix(local_bvh).as_euler("ZXY", degrees=True)
            if parent == 0:
                values += list(units_per_metre * hdvr_to_bvh @ pos[b])
            values += list(euler)
        lines.append(" ".join(f"{v:.6f}" for v in values))
    write_text_atomic(path, "\n".join(lines) + "\n")
