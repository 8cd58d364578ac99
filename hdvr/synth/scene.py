"""Multi-dancer scenes: placement, clothing, stage (floor, backdrop, lights) and the MJCF with N dancers.

The scene MJCF holds N copies of the digital dancer (:func:`hdvr.dancer_model.build_mjcf` at each dancer's
height), names prefixed ``d{i}_``, in order, so the scene's qpos is the concatenation of the dancers' (41,)
qpos. Clothing: per dancer a top and a bottom material (built-in flat / checker / gradient textures in two
random colours), skin for head, neck, forearms and hands. Collisions between dancers are disabled (the scene
is kinematic; contype/conaffinity 0). Shadows, reflections and the skybox are off for speed; the background is
a textured backdrop (three walls).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from hdvr.dancer_model import build_mjcf

SKIN_TONES = np.array([[0.96, 0.80, 0.69], [0.87, 0.67, 0.52], [0.76, 0.57, 0.42], [0.55, 0.38, 0.26],
                       [0.40, 0.27, 0.18], [0.93, 0.75, 0.60]])
HAIR_TONES = np.array([[0.08, 0.06, 0.05], [0.25, 0.15, 0.08], [0.45, 0.3, 0.15], [0.7, 0.55, 0.3],
                       [0.3, 0.3, 0.3]])
TOP_BODIES = ("torso", "neck_geom_never", "left_upper_arm", "right_upper_arm")
BOTTOM_BODIES = ("pelvis", "left_thigh", "right_thigh", "left_shank", "right_shank")
SHOE_BODIES = ("left_foot", "right_foot", "left_toes", "right_toes")


@dataclass
class DancerLook:
    """Clothing of one dancer: RGB in [0, 1], texture kinds (``flat``, ``checker``, ``gradient``), skin tone."""

    top_rgb: tuple
    top_rgb2: tuple
    top_kind: str
    bottom_rgb: tuple
    bottom_rgb2: tuple
    bottom_kind: str
    skin_rgb: tuple
    shoe_rgb: tuple
    hair_rgb: tuple = (0.1, 0.07, 0.05)
    skirt: bool = False  # a skirt over the thighs (bottom material)


@dataclass
class Stage:
    """Floor, backdrop and lighting of a scene."""

    floor_rgb: tuple
    floor_rgb2: tuple
    floor_kind: str
    floor_repeat: float
    wall_rgb: tuple
    wall_rgb2: tuple
    wall_kind: str
    headlight_ambient: float
    headlight_diffuse: float
    lights: list  # (pos (3,), dir (3,), diffuse) per light


def _distinct_colours(rng: np.random.Generator, n: int) -> list[np.ndarray]:
    """n saturated colours with well separated hues."""
    offset = rng.uniform(0, 1)
    hues = (offset + np.arange(n) / max(n, 1) + rng.uniform(-0.05, 0.05, n)) % 1.0
    out = []
    for h in hues:
        s, v = rng.uniform(0.55, 0.95), rng.uniform(0.45, 0.95)
        k = (np.array([5, 3, 1]) + h * 6) % 6
        out.append(v - v * s * np.clip(np.minimum(k, 4 - k), 0, 1))
    return out


def random_looks(rng: np.random.Generator, n: int) -> list[DancerLook]:
    tops = _distinct_colours(rng, n)
    bottoms = _distinct_colours(rng, n)
    rng.shuffle(bottoms)
    looks = []
    for i in range(n):
        skin = SKIN_TONES[rng.integers(len(SKIN_TONES))] * rng.uniform(0.9, 1.05)
        for c in (tops, bottoms):  # clothing must not read as bare skin
            if np.abs(c[i] - skin).max() < 0.3:
                c[i] = c[i] * 0.35
        looks.append(DancerLook(
            tuple(tops[i]), tuple(np.clip(tops[i] * rng.uniform(0.3, 0.7) + rng.uniform(0, 0.3), 0, 1)),
            str(rng.choice(["flat", "checker", "gradient"])), tuple(bottoms[i]),
            tuple(np.clip(bottoms[i] * rng.uniform(0.3, 0.7), 0, 1)), str(rng.choice(["flat", "checker", "gradient"])),
            tuple(skin), tuple(np.full(3, rng.uniform(0.05, 0.3))),
            tuple(HAIR_TONES[rng.integers(len(HAIR_TONES))] * min(1.0, 0.6 * skin.mean() / 0.75)),
            bool(rng.random() < 0.35)))
    return looks


def random_stage(rng: np.random.Generator) -> Stage:
    floor = rng.uniform(0.2, 0.85, 3)
    wall = rng.uniform(0.15, 0.9, 3)
    lights = []
    for _ in range(int(rng.integers(1, 3))):
        az = rng.uniform(0, 2 * np.pi)
        pos = np.array([4 * np.cos(az), 4 * np.sin(az), rng.uniform(3, 6)])
        lights.append((pos, -pos / np.linalg.norm(pos), float(rng.uniform(0.25, 0.6))))
    return Stage(tuple(floor), tuple(np.clip(floor * rng.uniform(0.6, 0.9), 0, 1)),
                 str(rng.choice(["checker", "checker", "gradient", "flat"])), float(rng.uniform(4, 16)),
                 tuple(wall), tuple(np.clip(wall * rng.uniform(0.4, 0.8), 0, 1)),
                 str(rng.choice(["checker", "gradient", "flat"])), float(rng.uniform(0.25, 0.5)),
                 float(rng.uniform(0.3, 0.6)), lights)


def _fmt(v) -> str:
    return " ".join(f"{float(x):.4g}" for x in np.ravel(v))


def _material(asset, name, kind, rgb, rgb2, repeat=1.0):
    if kind == "flat":
        ET.SubElement(asset, "material", name=name, rgba=_fmt(list(rgb) + [1.0]), specular="0.1")
        return
    ET.SubElement(asset, "texture", name=f"{name}_tex", type="2d",
                  builtin=kind, rgb1=_fmt(rgb), rgb2=_fmt(rgb2), width="64", height="64")
    ET.SubElement(asset, "material", name=name, texture=f"{name}_tex", texrepeat=f"{repeat:.3g} {repeat:.3g}",
                  specular="0.1")


def build_scene_xml(heights_m: list[float], looks: list[DancerLook], stage: Stage, size=(640, 480)) -> str:
    """The scene MJCF (string) with one dancer per height, ``d{i}_``-prefixed names, and camera ``cam``."""
    root = ET.Element("mujoco", model="hdvr_scene")
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    default = ET.SubElement(root, "default")
    ET.SubElement(default, "joint", type="hinge", limited="true")
    # no default rgba: a geom rgba other than MuJoCo's default overrides its material's colour
    ET.SubElement(default, "geom", contype="0", conaffinity="0")
    ET.SubElement(default, "site", size="0.012", rgba="0.1 0.4 0.9 1", group="3")
    visual = ET.SubElement(root, "visual")
    ET.SubElement(visual, "headlight", ambient=_fmt([stage.headlight_ambient] * 3),
                  diffuse=_fmt([stage.headlight_diffuse] * 3), specular="0 0 0")
    ET.SubElement(visual, "quality", shadowsize="0", offsamples="0")
    ET.SubElement(visual, "global", offwidth=str(size[0]), offheight=str(size[1]))
    ET.SubElement(visual, "map", znear="0.02", zfar="60")
    asset = ET.SubElement(root, "asset")
    _material(asset, "floor_mat", stage.floor_kind if stage.floor_kind != "gradient" else "checker", stage.floor_rgb,
              stage.floor_rgb2, stage.floor_repeat)
    _material(asset, "wall_mat", stage.wall_kind, stage.wall_rgb, stage.wall_rgb2, 6.0)
    world = ET.SubElement(root, "worldbody")
    for k, (pos, direction, diffuse) in enumerate(stage.lights):
        ET.SubElement(world, "light", name=f"light{k}", pos=_fmt(pos), dir=_fmt(direction), directional="true",
                      diffuse=_fmt([diffuse] * 3), castshadow="false")
    ET.SubElement(world, "geom", name="floor", type="plane", size="12 12 2", material="floor_mat")
    for k, (pos, euler) in enumerate((([0, 12, 4], [np.pi / 2, 0, 0]), ([0, -12, 4], [-np.pi / 2, 0, 0]),
                                      ([12, 0, 4], [0, -np.pi / 2, 0]), ([-12, 0, 4], [0, np.pi / 2, 0]))):
        ET.SubElement(world, "geom", name=f"wall{k}", type="plane", size="12 4 2" if k < 2 else "4 12 2",
                      pos=_fmt(pos),
                      euler=_fmt(euler), material="wall_mat")
    ET.SubElement(world, "camera", name="cam", pos="5 0 1.5", xyaxes="0 1 0 -0.2 0 1", fovy="45")

    for i, (height, look) in enumerate(zip(heights_m, looks)):
        pre = f"d{i}_"
        _material(asset, f"{pre}top", look.top_kind, look.top_rgb, look.top_rgb2, 3.0)
        _material(asset, f"{pre}bottom", look.bottom_kind, look.bottom_rgb, look.bottom_rgb2, 3.0)
        ET.SubElement(asset, "material", name=f"{pre}skin", rgba=_fmt(list(look.skin_rgb) + [1.0]), specular="0.2")
        ET.SubElement(asset, "material", name=f"{pre}shoe", rgba=_fmt(list(look.shoe_rgb) + [1.0]), specular="0.3")
        ET.SubElement(asset, "material", name=f"{pre}hair", rgba=_fmt(list(look.hair_rgb) + [1.0]), specular="0.1")
        ET.SubElement(asset, "material", name=f"{pre}eye", rgba="0.05 0.04 0.04 1", specular="0.5")
        ET.SubElement(asset, "material", name=f"{pre}mouth",
                      rgba=_fmt(list(np.array(look.skin_rgb) * [0.75, 0.45, 0.45]) + [1.0]), specular="0.1")
        dancer = ET.fromstring(build_mjcf(height))
        pelvis = dancer.find("worldbody/body")
        for el in pelvis.iter():
            if "name" in el.attrib:
                el.set("name", pre + el.get("name"))
            if el.tag == "geom":
                body = el.get("name")[len(pre):].removesuffix("_geom")
                mat = "top" if body in TOP_BODIES else "bottom" if body in BOTTOM_BODIES else \
                    "shoe" if body in SHOE_BODIES else "skin"
                el.set("material", pre + mat)
                el.attrib.pop("rgba", None)
                if body in LIMB_BULK:  # limbs a little fuller than the kinematic model's capsules
                    el.set("size", f"{float(el.get('size').split()[0]) * LIMB_BULK[body]:.4g}")
            if el.tag == "freejoint":
                pass
            if el.tag == "joint":
                for attr in ("damping", "armature"):
                    el.attrib.pop(attr, None)
        _add_body_shape(pelvis, asset, pre, height, look)
        world.append(pelvis)
    return ET.tostring(root, encoding="unicode")


#: radius factors of the rendered limb capsules (the collision and kinematic model keep theirs)
LIMB_BULK = {"left_thigh": 1.3, "right_thigh": 1.3, "left_shank": 1.15, "right_shank": 1.15,
             "left_upper_arm": 1.2, "right_upper_arm": 1.2, "left_forearm": 1.15, "right_forearm": 1.15,
             "neck": 1.6}


#: volumes of the rendered body (body, name, type, pos, size (m, 1.70 m dancer), material); also collision geoms
BODY_VOLUMES = [
    ("torso", "chest", "ellipsoid", (0, 0.31, 0.0), (0.145, 0.12, 0.095), "top"),
    ("torso", "waist", "ellipsoid", (0, 0.14, 0.0), (0.12, 0.13, 0.08), "top"),
    ("pelvis", "hips", "ellipsoid", (0.0, 0.0, 0.01), (0.095, 0.15, 0.1), "bottom"),
]


def _add_body_shape(pelvis: ET.Element, asset: ET.Element, pre: str, height: float, look: DancerLook) -> None:
    """Visual-only geoms that make the stick dancer read as a person: chest, waist and hips with a human
    cross-section, hair, eyes, nose and mouth on the head, optionally a skirt. Sizes in metres for a 1.70 m
    dancer, scaled with height. Body frames (rest): torso and head x left, y up, z front; pelvis x front, y left,
    z up. Named with the dancer's prefix, so they count as the dancer in the segmentation (occlusion)."""
    k = height / 1.70
    bodies = {el.get("name")[len(pre):]: el for el in pelvis.iter("body")}
    bodies["pelvis"] = pelvis
    shapes = BODY_VOLUMES + [  # body, name, type, pos, size, material
        ("head", "hair", "ellipsoid", (0, 0.07, -0.012), (0.091, 0.075, 0.088), "hair"),
        ("head", "eye_l", "sphere", (0.03, 0.06, 0.122), (0.013,), "eye"),
        ("head", "eye_r", "sphere", (-0.03, 0.06, 0.122), (0.013,), "eye"),
        ("head", "nose", "ellipsoid", (0, 0.035, 0.13), (0.014, 0.022, 0.016), "skin"),
        ("head", "mouth", "ellipsoid", (0, 0.0, 0.118), (0.025, 0.007, 0.01), "mouth"),
    ]
    for body, name, kind, pos, size, mat in shapes:
        ET.SubElement(bodies[body], "geom", name=f"{pre}vis_{name}", type=kind, pos=_fmt(np.array(pos) * k),
                      size=_fmt(np.array(size) * k), material=f"{pre}{mat}", contype="0", conaffinity="0",
                      mass="0")
    if look.skirt:  # a flared skirt: the convex hull of a 0.12 m ring at the waist and a 0.26 m ring below
        ring = np.linspace(0, 2 * np.pi, 16, endpoint=False)
        verts = [(r * np.cos(a), r * np.sin(a), z) for r, z in ((0.12, 0.06), (0.26, -0.36)) for a in ring]
        ET.SubElement(asset, "mesh", name=f"{pre}skirt", vertex=_fmt(np.array(verts) * k))
        ET.SubElement(pelvis, "geom", name=f"{pre}vis_skirt", type="mesh", mesh=f"{pre}skirt",
                      material=f"{pre}bottom", contype="0", conaffinity="0", mass="0")


def place_dancers(rng: np.random.Generator, n: int, couple: bool) -> tuple[list[np.ndarray], list[float]]:
    """Start positions (x, y) metres and headings (rad) of n dancers: couples face each other 0.75 m apart,
    others stand in a loose line or arc 1.1-1.6 m apart, roughly facing the same way."""
    positions, yaws = [], []
    base_yaw = rng.uniform(-np.pi, np.pi)
    if couple:
        n_pairs = (n + 1) // 2
        for p in range(n_pairs):
            centre = np.array([rng.uniform(-0.6, 0.6), (p - (n_pairs - 1) / 2) * rng.uniform(1.6, 2.0)])
            yaw = base_yaw + rng.uniform(-0.5, 0.5)
            d = 0.375 * np.array([np.cos(yaw), np.sin(yaw)])
            positions += [centre - d, centre + d]
            yaws += [yaw, yaw + np.pi]
        return positions[:n], yaws[:n]
    spacing = rng.uniform(1.1, 1.6)
    lateral = np.array([-np.sin(base_yaw), np.cos(base_yaw)])
    forward = np.array([np.cos(base_yaw), np.sin(base_yaw)])
    for i in range(n):
        off = (i - (n - 1) / 2) * spacing
        positions.append(off * lateral + forward * rng.uniform(-0.7, 0.7))
        yaws.append(base_yaw + rng.uniform(-0.4, 0.4))
    return positions, yaws


def collision_model(heights_m: list[float]):
    """A MuJoCo model of the dancers' bodies as rendered (the model's capsules and spheres with the rendered limb
    thickness, chest, waist and hip volumes; not the face details or a skirt) in which only geoms of different
    dancers collide (dancer i: contype bit i, conaffinity all other bits), for measuring inter-dancer
    penetration. Cached per tuple of heights (the model is read-only here)."""
    return _collision_model(tuple(float(h) for h in heights_m))


@lru_cache(maxsize=8)
def _collision_model(heights_m: tuple):
    import mujoco

    root = ET.Element("mujoco", model="hdvr_collide")
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    world = ET.SubElement(root, "worldbody")
    n = len(heights_m)
    everyone = (1 << n) - 1
    for i, height in enumerate(heights_m):
        pelvis = ET.fromstring(build_mjcf(height)).find("worldbody/body")
        for el in pelvis.iter():
            if "name" in el.attrib:
                el.set("name", f"d{i}_" + el.get("name"))
            if el.tag == "geom":
                body = el.get("name")[len(f"d{i}_"):].removesuffix("_geom")
                if body in LIMB_BULK:
                    el.set("size", f"{float(el.get('size').split()[0]) * LIMB_BULK[body]:.4g}")
            if el.tag == "site":
                el.attrib.pop("name", None)
        bodies = {el.get("name")[len(f"d{i}_"):]: el for el in pelvis.iter("body")}
        k = height / 1.70
        for body, name, kind, pos, size, _ in BODY_VOLUMES:
            ET.SubElement(bodies[body], "geom", name=f"d{i}_vol_{name}", type=kind, pos=_fmt(np.array(pos) * k),
                          size=_fmt(np.array(size) * k), mass="0")
        for el in pelvis.iter("geom"):
            el.set("contype", str(1 << i))
            el.set("conaffinity", str(everyone & ~(1 << i)))
        world.append(pelvis)
    return mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))


def close_frames(keypoints: np.ndarray, margin_m: float = 0.25) -> np.ndarray:
    """(T,) frames in which some two dancers' keypoint boxes (N, T, 25, 3), grown by ``margin_m`` (more than the
    thickest body volume), overlap: only there can their geoms touch."""
    lo, hi = keypoints.min(2) - margin_m, keypoints.max(2) + margin_m  # (N, T, 3)
    n = keypoints.shape[0]
    out = np.zeros(keypoints.shape[1], dtype=bool)
    for i in range(n):
        for j in range(i + 1, n):
            out |= ((lo[i] <= hi[j]) & (lo[j] <= hi[i])).all(-1)
    return out


def inter_dancer_penetration(model, qpos: np.ndarray, stride: int = 1, frames: np.ndarray | None = None) -> np.ndarray:
    """(N, N) deepest penetration (metres, >= 0) between the geoms of each pair of dancers over the frames of
    ``qpos`` (N, T, 41) (every ``stride``-th frame; only where ``frames`` (T,) bool is True, when given)."""
    import mujoco

    data = mujoco.MjData(model)
    n, T = qpos.shape[:2]
    body_dancer = np.array([int(model.body(b).name[1:model.body(b).name.index("_")]) if b else -1
                            for b in range(model.nbody)])
    geom_dancer = body_dancer[model.geom_bodyid]
    out = np.zeros((n, n))
    flat = np.concatenate(list(qpos), axis=1)  # (T, N * 41)
    for t in range(0, T, stride):
        if frames is not None and not frames[t]:
            continue
        data.qpos[:] = flat[t]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        if data.ncon == 0:
            continue
        con = data.contact
        depth = -np.asarray(con.dist)
        a, b = geom_dancer[np.asarray(con.geom1)], geom_dancer[np.asarray(con.geom2)]
        np.maximum.at(out, (a, b), depth)
        np.maximum.at(out, (b, a), depth)
    return np.maximum(out, 0.0)


def separate_dancers(dancers, heights_m, limit_m: float = 0.002, step_m: float = 0.05, max_rounds: int = 40):
    """Move whole dancers apart (a horizontal translation of their motion: feet stay pinned, labels unchanged)
    until no pair's geoms penetrate more than ``limit_m``: the later dancer of a penetrating pair moves away from
    the other along the line between their mean positions, ``step_m`` plus the depth at a time. Returns the
    final (N, N) penetration matrix (metres) and sets each dancer's ``between_m``."""
    n = len(dancers)
    if n < 2:
        for d in dancers:
            d.between_m = 0.0
        return np.zeros((n, n))
    model = None
    stride = 3  # coarse rounds first, then every frame until none is left
    for round_ in range(max_rounds + 1):
        close = close_frames(np.stack([d.keypoints for d in dancers]))
        if not close.any():
            pen = np.zeros((n, n))
            break
        model = model or collision_model(list(heights_m))
        pen = inter_dancer_penetration(model, np.stack([d.qpos for d in dancers]), stride, close)
        if pen.max() <= limit_m and stride > 1:
            stride = 1
            pen = inter_dancer_penetration(model, np.stack([d.qpos for d in dancers]), stride, close)
        if pen.max() <= limit_m or round_ == max_rounds:
            break
        for i in range(n):
            for j in range(i + 1, n):
                if pen[i, j] <= limit_m:
                    continue
                away = dancers[j].qpos[:, :2].mean(0) - dancers[i].qpos[:, :2].mean(0)
                away = away / max(np.linalg.norm(away), 1e-6) if np.linalg.norm(away) > 1e-6 else np.array([1.0, 0])
                shift = (step_m + pen[i, j]) * away
                dancers[j].qpos[:, :2] += shift
                dancers[j].keypoints[..., :2] += shift
    for i, d in enumerate(dancers):
        d.between_m = float(pen[i].max())
    return pen
