"""Builds the MJCF of the digital dancer from the DH table (:mod:`hdvr.dh`).

One body per rigid segment; the hinges of consecutive DH rows that rotate about the same point share a body.
A body's frame is the DH frame before its first row; hinge i of the body turns about
``(G_first ... G_{i-1}) z`` where ``G_r = Rot_z(offset_r + rest_r) Rot_x(alpha_r)``, with ``ref = rest_r`` so that
``qpos0`` is the rest pose. The child body sits at the rest-pose product of the body's rows. This reproduces the
DH chain exactly for every q (tested against :func:`hdvr.dh.forward_kinematics`).

:func:`body_specs` is the single source of geometry: the XML writer uses it, and
:meth:`hdvr.skeleton.Skeleton.set_bone_lengths` re-runs it to move bodies, sites and geoms at run time.

Masses: segment fractions of body mass from Winter, D. A. (2009), "Biomechanics and Motor Control of Human
Movement", 4th ed., Table 4.1 (after Dempster 1955): hand 0.006, forearm 0.016, upper arm 0.028, foot 0.0145,
leg 0.0465, thigh 0.100, head and neck 0.081, thorax + abdomen 0.355, pelvis 0.142. Default 65 kg at 1.70 m.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import numpy as np

from hdvr import dh

DEFAULT_MASS_KG = 65.0

#: Winter (2009) segment mass fractions, split over our bodies (head+neck 0.081 = neck 0.016 + head 0.065;
#: foot 0.0145 = foot 0.0125 + toes 0.002).
MASS_FRACTIONS: dict[str, float] = {
    "pelvis": 0.142, "torso": 0.355, "neck": 0.016, "head": 0.065,
    "upper_arm": 0.028, "forearm": 0.016, "hand": 0.006,
    "thigh": 0.100, "shank": 0.0465, "foot": 0.0125, "toes": 0.002,
}

#: Capsule radii (metres) at the default height, scaled by height / 1.70 m.
RADII: dict[str, float] = {
    "pelvis": 0.075, "torso": 0.055, "neck": 0.035, "head": 0.085,
    "upper_arm": 0.038, "forearm": 0.032, "hand": 0.025,
    "thigh": 0.055, "shank": 0.042, "foot": 0.025, "toes": 0.02,
}

#: Bodies, their DH rows, and their parent body. Segment kind (for masses/radii) is the name minus its side.
BODY_ROWS: tuple[tuple[str, tuple[int, ...], str], ...] = (
    ("torso", (0, 1, 2), "pelvis"),
    ("neck", (3, 4, 5), "torso"),
    ("head", (6, 7), "neck"),
    ("left_upper_arm", (8, 9, 10), "torso"),
    ("left_forearm", (11, 12), "left_upper_arm"),
    ("left_hand", (13,), "left_forearm"),
    ("right_upper_arm", (14, 15, 16), "torso"),
    ("right_forearm", (17, 18), "right_upper_arm"),
    ("right_hand", (19,), "right_forearm"),
    ("right_thigh", (20, 21, 22), "pelvis"),
    ("right_shank", (23,), "right_thigh"),
    ("right_foot", (24, 25), "right_shank"),
    ("right_toes", (26,), "right_foot"),
    ("left_thigh", (27, 28, 29), "pelvis"),
    ("left_shank", (30,), "left_thigh"),
    ("left_foot", (31, 32), "left_shank"),
    ("left_toes", (33,), "left_foot"),
)


@dataclass
class GeomSpec:
    name: str
    kind: str  # "capsule" or "sphere"
    radius: float
    start: np.ndarray  # body frame, metres (capsule) or centre (sphere)
    end: np.ndarray | None
    mass: float


@dataclass
class BodySpec:
    name: str
    parent: str
    pos: np.ndarray  # in the parent body frame, metres
    rot: np.ndarray  # 3x3, parent body frame
    joints: list[tuple[str, np.ndarray, float, float, float]] = field(default_factory=list)  # name, axis, lo, hi, ref
    geoms: list[GeomSpec] = field(default_factory=list)
    sites: dict[str, np.ndarray] = field(default_factory=dict)
    world_rot_rest: np.ndarray = field(default_factory=lambda: np.eye(3))
    end_rest: np.ndarray | None = None  # body frame position of the segment's end (next joint)


def _kind(body: str) -> str:
    for prefix in ("left_", "right_"):
        if body.startswith(prefix):
            return body[len(prefix):]
    return body


def _rest_product(rows, bones) -> np.ndarray:
    out = np.eye(4)
    for r in rows:
        out = out @ dh.row_transform(r, dh.REST_Q[r], bones)
    return out


def _rows_before(row: int, rows: tuple[int, ...]) -> tuple[int, ...]:
    return rows[: rows.index(row)]


def body_specs(bones: np.ndarray | None = None, height_m: float = dh.DEFAULT_HEIGHT_M,
               mass_kg: float = DEFAULT_MASS_KG) -> dict[str, BodySpec]:
    """All bodies of the dancer for bone lengths ``bones`` (9,) metres (default: table averages x height)."""
    bones = dh.bone_lengths_m(height_m) if bones is None else np.asarray(bones, dtype=np.float64)
    scale = height_m / dh.DEFAULT_HEIGHT_M
    bases = dh.chain_base_transforms(bones)
    chain_of_row = {r: c for c in dh.CHAINS for r in c.rows}
    specs: dict[str, BodySpec] = {}
    world_rest: dict[str, np.ndarray] = {"pelvis": np.eye(4)}
    pelvis = BodySpec("pelvis", "world", np.zeros(3), np.eye(3))
    specs["pelvis"] = pelvis

    for name, rows, parent in BODY_ROWS:
        chain = chain_of_row[rows[0]]
        parent_spec = specs[parent]
        if rows[0] == chain.rows[0] and chain.name != "head":
            # first body of a chain: parent frame -> chain base (pelvis, or the neck base at the torso's end)
            attach = np.eye(4) if chain.parent == "pelvis" else _rest_product(BODY_ROWS[0][1], bones)
            local = attach @ bases[chain.name]
        else:
            local = _rest_product(dict((n, r) for n, r, _ in BODY_ROWS)[parent], bones)
        spec = BodySpec(name, parent, local[:3, 3].copy(), local[:3, :3].copy())
        world_rest[name] = world_rest[parent] @ local
        spec.world_rot_rest = world_rest[name][:3, :3]
        for r in rows:
            pre = _rest_product(_rows_before(r, rows), bones)
            axis = pre[:3, 2]
            joint = dh.JOINTS[r]
            spec.joints.append((joint.name, axis, joint.lower, joint.upper, joint.rest))
        spec.end_rest = _rest_product(rows, bones)[:3, 3]
        specs[name] = spec

    _add_geoms_and_sites(specs, bones, scale, mass_kg)
    return specs


def _local(spec: BodySpec, world_vec) -> np.ndarray:
    """A direction/offset given in the rest-pose world frame (x fwd, y left, z up), in the body's frame."""
    return spec.world_rot_rest.T @ np.asarray(world_vec, dtype=np.float64)


def _add_geoms_and_sites(specs: dict[str, BodySpec], bones: np.ndarray, scale: float, mass_kg: float) -> None:
    b = bones
    head_len, shoulder, hip, toe = b[1], b[2], b[5], b[8]

    def mass(body):
        return MASS_FRACTIONS[_kind(body)] * mass_kg

    def radius(body):
        return RADII[_kind(body)] * scale

    def capsule(body, start, end, name=None):
        specs[body].geoms.append(GeomSpec(name or f"{body}_geom", "capsule", radius(body),
                                          np.asarray(start, float), np.asarray(end, float), mass(body)))

    pelvis = specs["pelvis"]
    capsule("pelvis", [0, -hip, 0], [0, hip, 0])
    pelvis.sites["mid_hip"] = np.zeros(3)

    torso = specs["torso"]
    capsule("torso", _local(torso, [0, 0, 0.3 * b[0]]), torso.end_rest - _local(torso, [0, 0, 0.12 * b[0]]))
    neck = specs["neck"]
    neck.sites["neck"] = np.zeros(3)
    capsule("neck", np.zeros(3), neck.end_rest)
    head = specs["head"]
    specs["head"].geoms.append(GeomSpec("head_geom", "sphere", radius("head"),
                                        _local(head, [0.35 * head_len, 0, 0.35 * head_len]), None, mass("head")))
    head.sites["nose"] = head.end_rest.copy()  # end of DH row 7 (a = b_1 h forward of the head joint)
    for side, sign in (("right", -1.0), ("left", 1.0)):
        head.sites[f"{side}_eye"] = _local(head, [0.75 * head_len, sign * 0.25 * head_len, 0.3 * head_len])
        head.sites[f"{side}_ear"] = _local(head, [0.0, sign * 0.5 * head_len, 0.1 * head_len])

        upper, fore, hand = (specs[f"{side}_{k}"] for k in ("upper_arm", "forearm", "hand"))
        upper.sites[f"{side}_shoulder"] = np.zeros(3)
        capsule(upper.name, np.zeros(3), upper.end_rest)
        fore.sites[f"{side}_elbow"] = np.zeros(3)
        capsule(fore.name, np.zeros(3), fore.end_rest)
        hand.sites[f"{side}_wrist"] = np.zeros(3)
        hand.sites[f"{side}_hand_tip"] = hand.end_rest.copy()
        capsule(hand.name, np.zeros(3), hand.end_rest)

        thigh, shank, foot, toes = (specs[f"{side}_{k}"] for k in ("thigh", "shank", "foot", "toes"))
        thigh.sites[f"{side}_hip"] = np.zeros(3)
        capsule(thigh.name, np.zeros(3), thigh.end_rest)
        shank.sites[f"{side}_knee"] = np.zeros(3)
        capsule(shank.name, np.zeros(3), shank.end_rest)
        foot.sites[f"{side}_ankle"] = np.zeros(3)
        # The table's foot runs level from the ankle (row 25: d = b_8 h forward). The sole is taken b_8 h below
        # the ankle (the ankle height of a standing adult is about 0.04 h, close to b_8 h), the heel 0.5 b_8 h
        # behind it, the small toe at the toe joint and 0.5 b_8 h to the outside, the big toe at the toe tip.
        sole = -toe
        r_foot = radius(foot.name)
        foot.sites[f"{side}_heel"] = _local(foot, [-0.5 * toe, 0, sole])
        capsule(foot.name, _local(foot, [-0.5 * toe + r_foot, 0, sole + r_foot]),
                foot.end_rest + _local(foot, [0, 0, sole + r_foot]))
        toes.sites[f"{side}_small_toe"] = _local(toes, [0, sign * 0.5 * toe, sole])
        toes.sites[f"{side}_big_toe"] = toes.end_rest + _local(toes, [0, -sign * 0.1 * toe, sole])
        toes.sites[f"{side}_toe_tip"] = toes.end_rest.copy()
        r_toe = radius(toes.name)
        toes.geoms.append(GeomSpec(f"{toes.name}_geom", "sphere", r_toe,
                                   _local(toes, [0.5 * toe * 0.1, 0, sole + r_toe]), None, mass(toes.name)))


def rest_pelvis_height(bones: np.ndarray) -> float:
    """Height (m) of the pelvis above the floor in the rest pose: thigh + shank + ankle height (b_8 h)."""
    return float(bones[6] + bones[7] + bones[8])


def _fmt(v) -> str:
    return " ".join(f"{x:.9g}" for x in np.asarray(v, dtype=np.float64).ravel())


def _quat_from_rot(rot: np.ndarray) -> np.ndarray:
    import mujoco

    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rot, dtype=np.float64).ravel())
    return q


def build_mjcf(height_m: float = dh.DEFAULT_HEIGHT_M, mass_kg: float = DEFAULT_MASS_KG) -> str:
    """The dancer's MJCF as a string (bone ratios: the table's averages)."""
    bones = dh.bone_lengths_m(height_m)
    specs = body_specs(bones, height_m, mass_kg)
    children: dict[str, list[str]] = {}
    for name, spec in specs.items():
        children.setdefault(spec.parent, []).append(name)

    lines = [
        "<!-- HDVR digital dancer: 34 hinge joints (one per row of the paper's DH table) + a free root joint.",
        "     Generated by `python scripts/build_dancer_model.py` from hdvr/dh.py and hdvr/dancer_model.py;",
        "     do not edit by hand. Frames: world x forward (the dancer faces +x), y left, z up; metres, radians.",
        f"     Default: height {height_m:.2f} m, bone ratios = table averages, mass {mass_kg:.0f} kg. -->",
        '<mujoco model="hdvr_dancer">',
        '  <compiler angle="radian" autolimits="true"/>',
        '  <option timestep="0.002" integrator="implicitfast"/>',
        "  <default>",
        '    <joint type="hinge" damping="2" armature="0.02" limited="true"/>',
        '    <geom contype="1" conaffinity="1" condim="3" friction="0.9 0.02 0.002" rgba="0.80 0.55 0.40 1"/>',
        '    <site size="0.012" rgba="0.1 0.4 0.9 1" group="3"/>',
        "  </default>",
        "  <visual>",
        '    <headlight ambient="0.35 0.35 0.35" diffuse="0.55 0.55 0.55"/>',
        '    <quality shadowsize="1024"/>',
        "  </visual>",
        "  <asset>",
        '    <texture name="floor_tex" type="2d" builtin="checker" rgb1="0.82 0.80 0.76" rgb2="0.68 0.66 0.62" '
        'width="256" height="256"/>',
        '    <material name="floor_mat" texture="floor_tex" texrepeat="8 8" reflectance="0.05"/>',
        "  </asset>",
        "  <worldbody>",
        '    <light name="key" pos="2 -2 4" dir="-0.5 0.5 -1" directional="true" diffuse="0.6 0.6 0.6"/>',
        '    <geom name="floor" type="plane" size="10 10 0.05" material="floor_mat" rgba="1 1 1 1"/>',
    ]

    def emit(name: str, indent: int) -> None:
        spec = specs[name]
        pad = "  " * indent
        pos = spec.pos if name != "pelvis" else np.array([0.0, 0.0, rest_pelvis_height(bones)])
        attrs = f'name="{name}" pos="{_fmt(pos)}"'
        if name != "pelvis":
            attrs += f' quat="{_fmt(_quat_from_rot(spec.rot))}"'
        lines.append(f"{pad}<body {attrs}>")
        if name == "pelvis":
            lines.append(f'{pad}  <freejoint name="root"/>')
        for jname, axis, lo, hi, ref in spec.joints:
            lines.append(f'{pad}  <joint name="{jname}" axis="{_fmt(axis)}" range="{lo:.9g} {hi:.9g}" '
                         f'ref="{ref:.9g}"/>')
        for g in spec.geoms:
            if g.kind == "capsule":
                lines.append(f'{pad}  <geom name="{g.name}" type="capsule" size="{g.radius:.6g}" '
                             f'fromto="{_fmt(g.start)} {_fmt(g.end)}" mass="{g.mass:.6g}"/>')
            else:
                lines.append(f'{pad}  <geom name="{g.name}" type="sphere" size="{g.radius:.6g}" '
                             f'pos="{_fmt(g.start)}" mass="{g.mass:.6g}"/>')
        for sname, spos in spec.sites.items():
            lines.append(f"{pad}  <site name={quoteattr(sname)} pos=\"{_fmt(spos)}\"/>")
        for child in children.get(name, []):
            emit(child, indent + 1)
        lines.append(f"{pad}</body>")

    emit("pelvis", 2)
    lines += ["  </worldbody>", "</mujoco>", ""]
    return "\n".join(lines)
