"""The generator's declared movement labels: what its primitives perform, per body part and frame.

The reference for the labeller check (:mod:`hdvr.synth.evaluate`) must not come from the labeller. Each primitive
of :mod:`hdvr.synth.choreography` is recorded as an :class:`Intent` (motor group, kind, frames [start, end)); the
declared labels follow from the intents and the planned trajectories they write, with the vocabulary's
definitions (``movements.json``) applied to the plan itself:

- A part can move only inside an intent of the group that drives it (head: head group; neck: neck; torso and
  shoulders: trunk; arms: their arm; legs, hips and feet: leg phrases). Outside, it holds: Keeping Still or
  Holding ... by its planned posture.
- Inside an intent, the part moves where its planned speed exceeds ``still_speed_rad_s`` (hips:
  ``hips_still_speed_m_s``): the intent starts / stops moving the part when its ramp passes the threshold.
  Direction = the dominant component of the planned velocity: for head, neck, torso and shoulders the hinge that
  drives the component (``JOINT_EFFECTS``: neck_twist -> head yaw, head_nod -> head pitch, neck_bend -> neck
  lateral, lumbar_flex / lumbar_bend / lumbar_twist -> torso flex / lean / twist, lumbar_bend -> shoulder height),
  rates in rad/s straight from the joint plan; for arm and leg segments the unit direction of the segment in its
  parent body's frame (the model's torso / pelvis body, forward kinematics of the plan), rad/s; for the hips the
  planned root velocity in the planned heading frame (m/s). Legs faster than ``kick_speed_rad_s``: Kicking.
- Hips Turning where the planned yaw rate exceeds ``turn_speed_rad_s`` (turns, pivots); Torso Somersault where
  the planned pitch rate exceeds ``somersault_speed_rad_s`` (flips).
- Shape primitives (circle, swing / oscillation, figure 8, jitter -> Unknown) label the frames of their span
  where the part moves.
- Feet: states from the planned ankle / toe angles (foot angle between heel -> big toe and the shank of the
  model at the planned pose, thresholds ``foot_extension_deg`` / ``foot_flexion_deg``), rolled on its edge
  (Unknown) where the planned ankle inversion exceeds ``foot_roll_deg``.

None of the labeller's estimation machinery is used: no keypoint-built body frames, no smoothing, hysteresis, gap
filling, run merging or windowed shape analysis. The labeller check then measures how well that machinery
recovers the plan from keypoints alone (any stature, any camera frame, optionally noise).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr import dh
from hdvr.layouts import BODY25_NAMES
from hdvr.movements.labeller import direction_table, foot_state_labels, still_labels
from hdvr.movements.taxonomy import Taxonomy
from hdvr.skeleton import ROOT_QPOS, Skeleton

KP = {n: i for i, n in enumerate(BODY25_NAMES)}
JI = {n: i for i, n in enumerate(dh.JOINT_NAMES)}

#: part -> ((hinge, measured component, sign), ...): the hinge that moves the component, and in which direction
#: (checked against forward kinematics in tests/test_synth_declare.py).
JOINT_EFFECTS = {
    "head": (("neck_twist", "yaw", 1), ("head_nod", "pitch", -1)),
    "neck": (("neck_bend", "lateral", -1), ("neck_flex", "forward", 1)),
    "left_shoulder": (("lumbar_bend", "height", 1),),
    "right_shoulder": (("lumbar_bend", "height", -1),),
    "torso": (("lumbar_flex", "flex", 1), ("lumbar_bend", "lean", -1), ("lumbar_twist", "twist", 1)),
}
#: limb part -> (proximal keypoint, distal keypoint, parent body)
LIMB_SEGMENTS = {f"{s}_{seg}": (f"{s}_{a}", f"{s}_{b}", body)
                 for s in ("left", "right")
                 for seg, a, b, body in (("upper_arm", "shoulder", "elbow", "torso"),
                                         ("lower_arm", "elbow", "wrist", "torso"),
                                         ("upper_leg", "hip", "knee", "pelvis"),
                                         ("lower_leg", "knee", "ankle", "pelvis"))}


@dataclass(frozen=True)
class Intent:
    """A primitive as performed: motor ``group`` (head, neck, trunk, left_arm, right_arm, legs), ``kind`` and
    frames [start, end)."""

    group: str
    kind: str
    start: int
    end: int


def driving_group(part: str) -> str:
    """The motor group whose intents can move ``part``."""
    if part in ("head", "neck"):
        return part
    if part in ("torso", "left_shoulder", "right_shoulder"):
        return "trunk"
    if part.endswith("_arm"):
        return part.split("_")[0] + "_arm"
    return "legs"


def _body_rest_rotation(sk: Skeleton, body: str) -> np.ndarray:
    sk.kinematics(sk.rest_qpos())
    return sk.data.body(body).xmat.reshape(3, 3).copy()


def plan_kinematics(sk: Skeleton, qpos: np.ndarray) -> dict:
    """Forward kinematics of the planned qpos (T, 41): keypoints (T, 25, 3) and the torso / pelvis body rotations
    (T, 3, 3) re-based so that they are x front, y left, z up in the rest pose."""
    T = qpos.shape[0]
    kp = np.empty((T, 25, 3))
    rot = {b: np.empty((T, 3, 3)) for b in ("torso", "pelvis")}
    rest = {b: _body_rest_rotation(sk, b) for b in rot}
    ids = sk.keypoint_site_ids
    body_ids = [sk.model.body(b).id for b in rot]
    xmat = np.empty((T, len(body_ids), 9))
    data = sk.data
    for t in range(T):
        sk.kinematics(qpos[t])
        kp[t] = data.site_xpos[ids]
        xmat[t] = data.xmat[body_ids]
    for k, b in enumerate(rot):
        rot[b] = xmat[:, k].reshape(T, 3, 3) @ rest[b].T
    return {"keypoints": kp, **rot}


def _intent_mask(intents, group: str, T: int) -> np.ndarray:
    m = np.zeros(T, dtype=bool)
    for it in intents:
        if it.group == group:
            m[max(it.start, 0):min(it.end, T)] = True
    return m


def declared_labels(tax: Taxonomy, sk: Skeleton, qpos: np.ndarray, heading: np.ndarray, pitch: np.ndarray,
                    intents, shapes, fps: float, kinematics: dict | None = None) -> np.ndarray:
    """(T, 16) global label ids declared by the plan: ``qpos`` (T, 41) planned motion, ``heading`` / ``pitch`` (T,)
    planned root heading (world yaw) / somersault angles (rad), ``intents`` list of :class:`Intent`, ``shapes`` list of
    :class:`hdvr.synth.choreography.Declared` (shape spans), ``fps`` frames per second; ``kinematics``: the
    result of :func:`plan_kinematics` for ``qpos`` when the caller has it."""
    th = tax.thresholds
    T = qpos.shape[0]
    kin = kinematics if kinematics is not None else plan_kinematics(sk, qpos)
    kp = kin["keypoints"]
    h = qpos[:, ROOT_QPOS:]
    ids = np.zeros((T, len(tax.parts)), dtype=np.int16)
    yaw_rate = np.abs(np.gradient(heading) * fps) if T > 1 else np.zeros(T)
    pitch_rate = np.abs(np.gradient(pitch) * fps) if T > 1 else np.zeros(T)
    for part in tax.parts:
        unknown = part.label("unknown").index
        direction = None
        if part.measure == "foot":
            side = part.name.split("_")[0]
            toe = kp[:, KP[f"{side}_big_toe"]] - kp[:, KP[f"{side}_heel"]]
            shank = kp[:, KP[f"{side}_knee"]] - kp[:, KP[f"{side}_ankle"]]
            cos = (toe * shank).sum(-1) / np.linalg.norm(toe, axis=-1) / np.linalg.norm(shank, axis=-1)
            angle = np.degrees(np.arccos(np.clip(cos, -1, 1)))
            rolled = np.degrees(np.abs(h[:, JI[f"{side}_ankle_invert"]])) > th["foot_roll_deg"]
            local = foot_state_labels(part, angle > th["foot_extension_deg"], angle < th["foot_flexion_deg"], rolled)
            ids[:, part.index] = [part.labels[i].id for i in local]
            continue
        if part.name in JOINT_EFFECTS:
            effects = JOINT_EFFECTS[part.name]
            comps = [c for _, c, _ in effects]
            vel = np.stack([sign * np.gradient(h[:, JI[j]]) * fps for j, _, sign in effects], 1)
            thr = th["still_speed_rad_s"]
        elif part.name in LIMB_SEGMENTS:
            a, b, body = LIMB_SEGMENTS[part.name]
            seg = kp[:, KP[b]] - kp[:, KP[a]]
            seg /= np.linalg.norm(seg, axis=-1, keepdims=True)
            direction = np.einsum("tji,tj->ti", kin[body], seg)  # R^T seg: in the body's frame
            comps = ["x", "y", "z"]
            vel = np.gradient(direction, axis=0) * fps
            thr = th["still_speed_rad_s"]
        else:  # hips: planned root velocity in the planned heading frame
            v = np.gradient(qpos[:, :3], axis=0) * fps
            fwd = np.stack([np.cos(heading), np.sin(heading)], 1)
            left = np.stack([-np.sin(heading), np.cos(heading)], 1)
            vel = np.stack([(v[:, :2] * left).sum(1), (v[:, :2] * fwd).sum(1), v[:, 2]], 1)
            comps = ["lateral", "forward", "up"]
            thr = th["hips_still_speed_m_s"]
        speed = np.linalg.norm(vel, axis=1)
        active = _intent_mask(intents, driving_group(part.name), T)
        moving = active & (speed > thr)
        table = direction_table(part, comps)
        dom = np.argmax(np.abs(vel), axis=1)
        dom_vel = np.take_along_axis(vel, dom[:, None], 1)[:, 0]
        local = np.where(moving, table[dom, (dom_vel > 0).astype(int)], still_labels(part, direction, th, T))
        fast = part.find("fast")
        if fast is not None:
            local = np.where(moving & (speed > th["kick_speed_rad_s"]), fast.index, local)
        special = np.zeros(T, dtype=bool)
        if part.name == "hips":
            special = yaw_rate > th["turn_speed_rad_s"]
            local = np.where(special, part.label("turning").index, local)
        if part.name == "torso":
            special = pitch_rate > th["somersault_speed_rad_s"]
            local = np.where(special, part.label("somersault").index, local)
        for d in shapes:
            if part.name not in d.parts or d.label == "somersault":
                continue
            lab = part.label("unknown") if d.label == "jitter" else part.find("pattern", pattern=d.label)
            if lab is None:
                continue
            span = np.zeros(T, dtype=bool)
            span[max(d.start, 0):min(d.end, T)] = True
            local = np.where(span & moving & ~special, lab.index, local)
        local = np.where(local < 0, unknown, local)
        ids[:, part.index] = np.asarray([lab.id for lab in part.labels], dtype=np.int16)[local]
    return ids

