"""The paper's Denavit-Hartenberg model of the 34-DOF digital dancer, corrected, with a numpy reference FK.

Source: ``tab:DH_parameters`` and ``tab:bounds`` in the appendix of the HDVR paper. Every DH row j is a link
transform ``T_j = Rot_z(Theta_j) Trans_z(d_j) Trans_x(a_j) Rot_x(alpha_j)`` with ``Theta_j = offset_j + q_j``;
``q_j`` is the angle of hinge j (one hinge per row, 34 in all). ``d`` and ``a`` are ``length_factor * b_k * h``
(bone ratio b_k of height h).

Reading of the table (each deviation documented in docs/dancer.md and :data:`CORRECTIONS`):

- Rows 0-7 are the trunk and head: rows 0-2 rotate about one point (the lumbar joint, at the pelvis), then row 2
  translates by b_0 h to the neck base; rows 3-5 rotate about the neck base and row 5 translates b_1 h to the head
  joint; rows 6-7 rotate the head, and row 7's a = b_1 h reaches the top of the head.
- Rows 0 and 1 both use theta_0 in the table. The model gives each row its own hinge (34 hinges = the paper's
  "34-DOF"), so the lumbar joint has three rotational DOF (rows 0, 1, 2).
- The legs (rows 20-26, 27-33) branch at the pelvis, before rows 0-1, at +-b_5 h along the pelvis' lateral axis:
  with the free root joint carrying the pelvis' global pose, rows 0-1 before the legs would duplicate it.
- The arms (rows 8-13, 14-19) branch at the neck base (end of row 2) at +-b_2 h laterally.
- The table writes the second limb of each pair as the point inversion of the first (d and a negated, offsets and
  alpha kept). That chain is the mirror image of the first when its base frame is the first's turned by 180 degrees
  about the body's lateral axis, so the legs need no change. The arms follow that rule in 4 of 6 rows; rows 14
  (alpha), 15 and 19 (offset) are corrected to it. With that, equal angles give mirror-image poses (tested).
- Each branch's fixed base rotation (the table leaves it implicit) is chosen so that q = 0 is the rest pose:
  standing, arms hanging, feet forward, and the tabulated bounds mean anatomical ranges (knee flexion >= 0, ...).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# ---------------------------------------------------------------------------------------------------------------
# Bone ratios (tab:bounds): bone length = ratio * height.
BONE_NAMES: tuple[str, ...] = ("neck", "head", "shoulder", "upper_arm", "lower_arm", "hip", "upper_leg",
                               "lower_leg", "toe")
BONE_RATIO_MEAN = np.array([0.25, 0.08, 0.06, 0.17, 0.17, 0.04, 0.21, 0.21, 0.04])
BONE_RATIO_STD = np.full(9, 0.05)
DEFAULT_HEIGHT_M = 1.70


@dataclass(frozen=True)
class DHRow:
    """One row of the DH table.

    ``offset_deg``: constant part of Theta (degrees); ``theta_index``: which tabulated theta_k drives it;
    ``d_bone``/``a_bone``: (factor, bone index) so that d = factor * b[bone] * h (None: zero); ``alpha_deg``.
    """

    row: int
    offset_deg: float
    theta_index: int
    d_bone: tuple[float, int] | None
    a_bone: tuple[float, int] | None
    alpha_deg: float


def _r(row, off, k, d=None, a=None, alpha=0.0):
    return DHRow(row, off, k, d, a, alpha)


# The table as printed in the paper (tab:DH_parameters), before corrections.
PAPER_DH_TABLE: tuple[DHRow, ...] = (
    _r(0, 180, 0, alpha=90), _r(1, -90, 0, alpha=90), _r(2, 90, 1, a=(1, 0), alpha=-90),
    _r(3, 0, 2, alpha=90), _r(4, 90, 3, alpha=90), _r(5, 90, 4, d=(1, 1), alpha=90),
    _r(6, 90, 5, alpha=90), _r(7, 90, 6, a=(1, 1), alpha=0),
    _r(8, 0, 7, alpha=90), _r(9, 90, 8, alpha=90), _r(10, 90, 9, d=(1, 3), alpha=90),
    _r(11, 0, 10, alpha=-90), _r(12, 90, 11, d=(1, 4), alpha=90), _r(13, 90, 12, a=(0.6, 4), alpha=0),
    _r(14, 0, 13, alpha=-90), _r(15, -90, 14, alpha=90), _r(16, 90, 15, d=(-1, 3), alpha=90),
    _r(17, 0, 16, alpha=-90), _r(18, 90, 17, d=(-1, 4), alpha=90), _r(19, -90, 18, a=(-0.6, 4), alpha=0),
    _r(20, 0, 19, alpha=-90), _r(21, -90, 20, alpha=90), _r(22, 0, 21, d=(-1, 6), alpha=-90),
    _r(23, 90, 22, a=(1, 7), alpha=0), _r(24, 0, 23, alpha=90), _r(25, 0, 24, d=(1, 8), alpha=-90),
    _r(26, -90, 25, a=(0.1, 8), alpha=0),
    _r(27, 0, 26, alpha=-90), _r(28, -90, 27, alpha=90), _r(29, 0, 28, d=(1, 6), alpha=-90),
    _r(30, 90, 29, a=(-1, 7), alpha=0), _r(31, 0, 30, alpha=90), _r(32, 0, 31, d=(-1, 8), alpha=-90),
    _r(33, -90, 32, a=(-0.1, 8), alpha=0),
)

#: Corrections to the printed table: (row, field, paper value, model value, reason).
CORRECTIONS: tuple[tuple[int, str, float, float, str], ...] = (
    (14, "alpha_deg", -90, 90, "second arm = point inversion of the first (rows 8-13), as the legs are"),
    (15, "offset_deg", -90, 90, "second arm = point inversion of the first (rows 8-13), as the legs are"),
    (19, "offset_deg", -90, 90, "second arm = point inversion of the first; the printed -90 folds the hand back"),
)


def _corrected_table() -> tuple[DHRow, ...]:
    rows = list(PAPER_DH_TABLE)
    for row, field, paper, model, _ in CORRECTIONS:
        assert getattr(rows[row], field) == paper
        rows[row] = DHRow(**{**rows[row].__dict__, field: model})
    return tuple(rows)


DH_TABLE: tuple[DHRow, ...] = _corrected_table()

# ---------------------------------------------------------------------------------------------------------------
# Bounds (tab:bounds), radians, keyed by theta index. Thetas the paper leaves unbounded get anatomical limits
# in ANATOMICAL_BOUNDS (documented with reasons).
PI = np.pi
PAPER_BOUNDS: dict[int, tuple[float, float]] = {
    1: (-PI / 8, PI / 8), 2: (-PI / 4, PI / 4), 3: (-PI / 4, PI / 4),
    7: (-PI / 1.6, PI / 1.6), 8: (-PI / 4, PI / 1.6), 9: (-PI, 0.0), 10: (-PI / 2, 0.0),
    13: (-PI / 1.6, PI / 1.6), 14: (-PI / 4, PI / 1.6), 15: (-PI, 0.0), 16: (-PI / 2, 0.0),
    19: (-PI / 2, PI / 4), 20: (-PI, PI / 1.3), 21: (-PI / 2, PI / 2), 22: (0.0, PI / 1.3), 23: (-PI / 4, PI / 2),
    26: (-PI / 2, PI / 4), 27: (-PI, PI / 1.3), 28: (-PI / 2, PI / 2), 29: (0.0, PI / 1.3), 30: (-PI / 4, PI / 2),
}

#: Limits chosen for the thetas the paper leaves unbounded, by DH row: (min, max, reason). Ranges from standard
#: goniometry references (American Academy of Orthopaedic Surgeons normal ranges; Norkin & White, "Measurement of
#: Joint Motion", 5th ed.), rounded; sign conventions in JOINTS.
ANATOMICAL_BOUNDS: dict[int, tuple[float, float, str]] = {
    0: (-PI / 6, PI / 6, "thoracolumbar lateral flexion, about 30 deg each side"),
    1: (-PI / 4, PI / 4, "thoracolumbar axial rotation, about 45 deg each side"),
    5: (-4 * PI / 9, 4 * PI / 9, "cervical axial rotation, about 80 deg each side"),
    6: (-PI / 12, PI / 12, "head roll at the atlanto-occipital joint (neck_bend already gives 45 deg)"),
    7: (-PI / 6, PI / 6, "atlanto-occipital flexion/extension, about 30 deg"),
    12: (-PI / 2, PI / 2, "forearm pronation/supination, about 90 deg each way"),
    13: (-7 * PI / 18, 7 * PI / 18, "wrist flexion/extension, about 70 deg each way"),
    18: (-PI / 2, PI / 2, "forearm pronation/supination, about 90 deg each way"),
    19: (-7 * PI / 18, 7 * PI / 18, "wrist flexion/extension, about 70 deg each way"),
    25: (-PI / 6, PI / 6, "subtalar inversion/eversion, about 30 deg"),
    26: (-4 * PI / 9, PI / 6, "toe (metatarsophalangeal) extension 80 deg (demi-pointe), flexion 30 deg"),
    32: (-PI / 6, PI / 6, "subtalar inversion/eversion, about 30 deg"),
    33: (-4 * PI / 9, PI / 6, "toe (metatarsophalangeal) extension 80 deg (demi-pointe), flexion 30 deg"),
}


@dataclass(frozen=True)
class JointSpec:
    """One hinge of the dancer (one per DH row)."""

    row: int
    name: str
    theta_index: int  # the paper's theta_k
    lower: float  # radians
    upper: float
    bound_source: str  # "paper" or the reason for an anatomical choice
    rest: float  # angle (radians) in the rest pose (standing, arms hanging, feet forward)
    meaning: str  # what a positive angle does, from the rest pose


_JOINT_NAMES_MEANINGS: tuple[tuple[str, str], ...] = (
    ("lumbar_bend", "trunk bends to the dancer's right"),
    ("lumbar_twist", "trunk turns to the dancer's left"),
    ("lumbar_flex", "trunk bends forward"),
    ("neck_bend", "neck bends to the dancer's right"),
    ("neck_flex", "neck bends forward"),
    ("neck_twist", "head turns to the dancer's left"),
    ("head_roll", "head tilts to the dancer's right"),
    ("head_nod", "head nods forward"),
    ("left_shoulder_abduct", "left arm raises sideways"),
    ("left_shoulder_flex", "left arm raises forward"),
    ("left_shoulder_rotate", "left humerus rotates inward (rest -90 deg: elbow flexes forward)"),
    ("left_elbow_flex", "negative flexes the left elbow"),
    ("left_forearm_twist", "left forearm pronates/supinates"),
    ("left_wrist_flex", "left hand flexes/extends"),
    ("right_shoulder_abduct", "right arm raises sideways"),
    ("right_shoulder_flex", "right arm raises forward"),
    ("right_shoulder_rotate", "right humerus rotates inward (rest -90 deg: elbow flexes forward)"),
    ("right_elbow_flex", "negative flexes the right elbow"),
    ("right_forearm_twist", "right forearm pronates/supinates"),
    ("right_wrist_flex", "right hand flexes/extends"),
    ("right_hip_adduct", "right leg moves toward the midline (negative: abduction)"),
    ("right_hip_extend", "right leg moves backward (negative: flexion, forward kick)"),
    ("right_hip_rotate", "right leg rotates about its axis"),
    ("right_knee_flex", "right knee flexes (shank moves back)"),
    ("right_ankle_plantarflex", "right foot points (toes down)"),
    ("right_ankle_invert", "right foot rolls about its long axis"),
    ("right_toe_flex", "right toes flex (down); negative: extension (demi-pointe)"),
    ("left_hip_adduct", "left leg moves toward the midline (negative: abduction)"),
    ("left_hip_extend", "left leg moves backward (negative: flexion, forward kick)"),
    ("left_hip_rotate", "left leg rotates about its axis"),
    ("left_knee_flex", "left knee flexes (shank moves back)"),
    ("left_ankle_plantarflex", "left foot points (toes down)"),
    ("left_ankle_invert", "left foot rolls about its long axis"),
    ("left_toe_flex", "left toes flex (down); negative: extension (demi-pointe)"),
)

#: Rest pose angles that are not zero: the humeral rotation sits mid-range (its tabulated range is [-pi, 0]), and the
#: arms are abducted 12 deg so that, with the table's narrow shoulders (b_2 h = 0.10 m), they clear the hips.
REST_ANGLES: dict[int, float] = {8: np.deg2rad(12.0), 14: np.deg2rad(12.0), 10: -PI / 2, 16: -PI / 2}


def _joint_specs() -> tuple[JointSpec, ...]:
    specs = []
    for row in DH_TABLE:
        name, meaning = _JOINT_NAMES_MEANINGS[row.row]
        if row.row in ANATOMICAL_BOUNDS:
            lo, hi, why = ANATOMICAL_BOUNDS[row.row]
            source = f"anatomical: {why}"
        else:
            lo, hi = PAPER_BOUNDS[row.theta_index]
            source = f"paper (theta_{row.theta_index})"
        specs.append(JointSpec(row.row, name, row.theta_index, float(lo), float(hi), source,
                               REST_ANGLES.get(row.row, 0.0), meaning))
    return tuple(specs)


JOINTS: tuple[JointSpec, ...] = _joint_specs()
JOINT_NAMES: tuple[str, ...] = tuple(j.name for j in JOINTS)
NUM_HINGES = len(JOINTS)  # 34
LOWER = np.array([j.lower for j in JOINTS])
UPPER = np.array([j.upper for j in JOINTS])
REST_Q = np.array([j.rest for j in JOINTS])

# ---------------------------------------------------------------------------------------------------------------
# Branch structure. World/pelvis frame: x forward (the dancer faces +x), y to the dancer's left, z up.


@dataclass(frozen=True)
class Chain:
    """A serial run of DH rows hanging from a parent frame.

    ``parent``: "pelvis" or "neck_base" (end of the trunk rows 0-2). ``lateral``: offset along the pelvis' y axis
    (+1 left, -1 right) times bone ``lateral_bone`` * h, expressed in the parent frame at the rest pose.
    ``base_world``: rotation of the chain's base frame in the pelvis frame at the rest pose.
    """

    name: str
    rows: tuple[int, ...]
    parent: str
    lateral: float
    lateral_bone: int | None
    base_world: np.ndarray


def _rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


# Columns are the images of the chain base's x, y, z axes. Trunk: the DH spine runs along base +y (-> up) and the
# head's last segment along base +z (-> forward, to the nose). Limbs: the first limb of each pair runs along its
# base +x (-> down); for the right leg base +z is the foot direction (-> forward) and for the left arm base +y is
# the rest elbow axis (-> left, so that negative elbow angles flex forward). The second limb of each pair is the
# point inversion of the first, i.e. its mirror image once its base is turned 180 deg about the lateral (y) axis.
_TRUNK_BASE = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
_LIMB_BASE = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
_MIRROR_TURN = _rot_y(np.pi)

CHAINS: tuple[Chain, ...] = (
    Chain("trunk", (0, 1, 2), "pelvis", 0.0, None, _TRUNK_BASE),
    Chain("head", (3, 4, 5, 6, 7), "neck_base", 0.0, None, None),  # continues the trunk chain
    Chain("left_arm", (8, 9, 10, 11, 12, 13), "neck_base", +1.0, 2, _LIMB_BASE),
    Chain("right_arm", (14, 15, 16, 17, 18, 19), "neck_base", -1.0, 2, _MIRROR_TURN @ _LIMB_BASE),
    Chain("right_leg", (20, 21, 22, 23, 24, 25, 26), "pelvis", -1.0, 5, _LIMB_BASE),
    Chain("left_leg", (27, 28, 29, 30, 31, 32, 33), "pelvis", +1.0, 5, _MIRROR_TURN @ _LIMB_BASE),
)


def bone_lengths_m(height_m: float = DEFAULT_HEIGHT_M, ratios: np.ndarray | None = None) -> np.ndarray:
    """Bone lengths in metres: ``ratios`` (default: the table's averages) times ``height_m``."""
    r = BONE_RATIO_MEAN if ratios is None else np.asarray(ratios, dtype=np.float64)
    return r * float(height_m)


def _row_lengths(row: DHRow, bones: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    d = row.d_bone[0] * bones[..., row.d_bone[1]] if row.d_bone else np.zeros(bones.shape[:-1])
    a = row.a_bone[0] * bones[..., row.a_bone[1]] if row.a_bone else np.zeros(bones.shape[:-1])
    return d, a


def dh_transform(theta: np.ndarray, d: np.ndarray, a: np.ndarray, alpha: float) -> np.ndarray:
    """Batched ``Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha)``; theta, d, a shaped (...,); returns (..., 4, 4)."""
    theta = np.asarray(theta, dtype=np.float64)
    c, s = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    out = np.zeros(theta.shape + (4, 4))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2], out[..., 0, 3] = c, -s * ca, s * sa, a * c
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2], out[..., 1, 3] = s, c * ca, -c * sa, a * s
    out[..., 2, 1], out[..., 2, 2], out[..., 2, 3] = sa, ca, d
    out[..., 3, 3] = 1.0
    return out


def row_transform(row_index: int, q: np.ndarray, bones: np.ndarray) -> np.ndarray:
    """The DH link transform of ``row_index`` for hinge angle(s) ``q`` (rad) and bone lengths (metres)."""
    row = DH_TABLE[row_index]
    d, a = _row_lengths(row, np.asarray(bones, dtype=np.float64))
    return dh_transform(np.deg2rad(row.offset_deg) + q, d, a, np.deg2rad(row.alpha_deg))


def _homogeneous(rot: np.ndarray, pos) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = pos
    return out


def _chain_rest_frame(rows, bones) -> np.ndarray:
    out = np.eye(4)
    for r in rows:
        out = out @ row_transform(r, REST_Q[r], bones)
    return out


def chain_base_transforms(bones: np.ndarray) -> dict[str, np.ndarray]:
    """Fixed transform from each chain's parent frame to the chain's base frame (4x4, metres).

    The trunk hangs from the pelvis; the head continues the trunk (identity); the arms hang from the neck base
    (the frame after row 2) and the legs from the pelvis, offset laterally by b_2 h and b_5 h.
    """
    bones = np.asarray(bones, dtype=np.float64)
    trunk = next(c for c in CHAINS if c.name == "trunk")
    neck_rest_rot = trunk.base_world @ _chain_rest_frame(trunk.rows, bones)[:3, :3]
    out = {}
    for chain in CHAINS:
        if chain.name == "head":
            out[chain.name] = np.eye(4)
            continue
        parent_rot = np.eye(3) if chain.parent == "pelvis" else neck_rest_rot
        offset_world = np.array([0.0, chain.lateral * (bones[chain.lateral_bone] if chain.lateral_bone is not None
                                                       else 0.0), 0.0])
        out[chain.name] = _homogeneous(parent_rot.T @ chain.base_world, parent_rot.T @ offset_world)
    return out


def forward_kinematics(q: np.ndarray, bones: np.ndarray, root: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Reference DH forward kinematics in numpy.

    ``q``: (..., 34) hinge angles (rad, Theta_j = offset_j + q_j); ``bones``: (9,) metres; ``root``: (..., 4, 4)
    pelvis pose in the world (default identity). Returns ``frames`` (..., 35, 4, 4): entry 0 is the pelvis and
    entry j+1 the DH frame after row j (its origin is the joint position J_j); ``hinge_pos`` and ``hinge_axis``
    (..., 34, 3): each hinge's anchor and world axis (z of the frame before its row).
    """
    q = np.asarray(q, dtype=np.float64)
    batch = q.shape[:-1]
    root_t = np.broadcast_to(np.eye(4), batch + (4, 4)) if root is None else np.asarray(root, dtype=np.float64)
    bases = chain_base_transforms(bones)
    frames = np.zeros(batch + (NUM_HINGES + 1, 4, 4))
    before = np.zeros(batch + (NUM_HINGES, 4, 4))
    frames[..., 0, :, :] = root_t
    neck_base = None
    for chain in CHAINS:
        if chain.name == "head":
            parent = neck_base
        else:
            parent = root_t if chain.parent == "pelvis" else neck_base
        current = parent @ bases[chain.name]
        for r in chain.rows:
            before[..., r, :, :] = current
            current = current @ row_transform(r, q[..., r], bones)
            frames[..., r + 1, :, :] = current
        if chain.name == "trunk":
            neck_base = current
    return {"frames": frames, "hinge_pos": before[..., :3, 3], "hinge_axis": before[..., :3, 2]}
