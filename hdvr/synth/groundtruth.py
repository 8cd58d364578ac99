"""One synthetic clip, end to end: choreographies -> scene -> camera -> (render) -> ground-truth files.

Clip folder ``clip_{index:05d}/`` (all files written atomically; ``meta.json`` last, it marks the clip done):

- ``video.mp4``: H.264 (PyAV), ``image_size`` at ``fps`` (absent with ``render=False``).
- ``gt.npz`` (fixed keys; N dancers, T frames):
  ``qpos`` float64 (N, T, 41) dancer world (see :mod:`hdvr.skeleton`); ``keypoints3d_world`` float32 (N, T, 25, 3)
  metres; ``keypoints3d_camera`` float32 (N, T, 25, 3) metres, camera frame (x right, y down, z forward);
  ``keypoints2d`` float32 (N, T, 25, 2) pixels (NaN behind the camera); ``visibility`` int8 (N, T, 25):
  2 visible, 1 occluded by another dancer (with ``render=False`` occlusion is not computed and
  in-image keypoints are 2), 0 outside the image; ``boxes`` float32 (N, T, 4) x, y, w, h pixels (amodal, NaN
  when the dancer is out of view); ``track_ids`` int32 (N,); ``labels`` int16 (N, T, 16) global movement
  label ids (:mod:`hdvr.movements.taxonomy`, part order of the taxonomy); ``camera_rotation`` float64 (T, 3, 3)
  and ``camera_centre`` (T, 3): ``P_cam = R (P_world - C)``; ``focal`` float64 (T,) px; ``principal_point`` (2,)
  px; ``image_size`` int (2,) (width, height); ``fps`` float; ``genre_index`` int (index in
  :data:`hdvr.synth.genres.GENRES`; -1 for mocap clips, genre "salsa"); ``heights_m`` float64 (N,).
- ``dancer_{k}.keypoints2d.npz``: dancer k's BODY_25 2D keypoints in the 2D keypoint contract
  (:mod:`hdvr.io.keypoints2d`): confidence 1 visible, 0.5 occluded, 0 (NaN) outside.
- ``mot.txt``: MOT Challenge ground truth: ``frame, id, left, top, width, height, 1, 1, visibility`` (frames
  from 1; visibility = fraction of the dancer's keypoints visible).
- ``labels.json``: genre, fps, per dancer the movement segments (part, label, label_id, start, end, start_s,
  end_s; frames, end exclusive).
- ``meta.json``: seed, clip index, genre, dancer count, frames, heights, motion checks (joint-limit violation,
  foot penetration and skating, deepest penetration between dancers' geoms), visible / occluded keypoint
  fractions, render speed.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hdvr.io.atomic import save_npz_atomic, write_text_atomic
from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
from hdvr.layouts import BODY25_NAMES
from hdvr.movements.labeller import Labels
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.skeleton import Skeleton
from hdvr.synth.choreography import ChoreographyGenerator, foot_metrics
from hdvr.synth.genres import GENRES, genre_style
from hdvr.video import VideoWriter

GT_KEYS = ("qpos", "keypoints3d_world", "keypoints3d_camera", "keypoints2d", "visibility", "boxes", "track_ids",
           "labels", "camera_rotation", "camera_centre", "focal", "principal_point", "image_size", "fps",
           "genre_index", "heights_m")
FORMAT_VERSION = 1


@dataclass
class ClipSpec:
    """What to generate for one clip (all derived deterministically from (seed, index))."""

    index: int
    seed: int
    genre: str
    n_dancers: int
    seconds: float
    fps: float = 30.0
    size: tuple[int, int] = (640, 480)
    prefix: str = "clip"  # "mocap" for clips of retargeted real mocap

    @property
    def name(self) -> str:
        return f"{self.prefix}_{self.index:05d}"


def clip_spec(index: int, seed: int, genres: tuple[str, ...], dancers: tuple[int, int], seconds: float,
              fps: float = 30.0, size=(640, 480)) -> ClipSpec:
    """Clip ``index`` of a run: genres cycle through ``genres``; the dancer count is drawn in ``dancers``
    (partner dances get couples: an odd count is made even within the range when possible)."""
    rng = np.random.default_rng([seed, index, 0])
    genre = genres[index % len(genres)]
    lo, hi = dancers
    n = int(rng.integers(lo, hi + 1))
    if genre_style(genre).couple and n % 2 == 1:
        n = n + 1 if n + 1 <= hi else (n - 1 if n - 1 >= max(lo, 2) else n)
    return ClipSpec(index, seed, genre, n, float(seconds), fps, tuple(size))


def generate_motion(spec: ClipSpec):
    """Choreographies of the clip's dancers: (list of Choreography, heights (N,), start positions, yaws)."""
    from hdvr.synth.scene import place_dancers

    rng = np.random.default_rng([spec.seed, spec.index, 1])
    style = genre_style(spec.genre)
    positions, yaws = place_dancers(rng, spec.n_dancers, style.couple)
    heights = rng.uniform(1.55, 1.85, spec.n_dancers)
    dancers = []
    for k in range(spec.n_dancers):
        gen = ChoreographyGenerator(Skeleton(height_m=float(heights[k])), spec.fps)
        if style.couple and k % 2 == 1:  # the partner mirrors the lead
            dancers.append(gen.generate(spec.genre, spec.seconds, rng, positions[k], yaws[k], mirror_of=dancers[k - 1]))
        else:
            dancers.append(gen.generate(spec.genre, spec.seconds, rng, positions[k], yaws[k]))
    from hdvr.synth.scene import separate_dancers

    separate_dancers(dancers, heights)  # no dancer passes through another
    return dancers, heights


def mocap_motion(spec: ClipSpec, bvh_paths: list[str]):
    """Dancers of a mocap clip: BVH takes sharing one world frame (e.g. CMU salsa lead 60_XX and follow 61_XX),
    resampled to ``spec.fps``, a ``spec.seconds`` stretch from a start drawn from (seed, index), retargeted to the
    dancer (:mod:`hdvr.synth.retarget`). Their movement labels come from the reference labeller (no primitives)."""
    from hdvr.io.bvh import load_mocap_body25
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.synth.choreography import Choreography
    from hdvr.synth.retarget import retarget, stature_from_body25

    takes = [load_mocap_body25(p, fps=spec.fps)[0] for p in bvh_paths]
    T_all = min(k.shape[0] for k in takes)
    T = min(max(int(round(spec.seconds * spec.fps)), 3), T_all)
    start = int(np.random.default_rng([spec.seed, spec.index, 3]).integers(0, T_all - T + 1))
    dancers, heights = [], []
    for kp in takes:
        kp = kp[start:start + T]
        height = stature_from_body25(kp)
        sk = Skeleton(height_m=height)
        qpos, _ = retarget(kp, sk)
        world = sk.keypoints(qpos)
        labels = MovementLabeller().label(world, spec.fps).ids
        dancers.append(Choreography(spec.genre, spec.fps, qpos, world, labels, np.zeros(T, dtype=bool)))
        heights.append(height)
    return dancers, np.array(heights)


def make_clip(out_dir: str | os.PathLike, spec: ClipSpec, render: bool = True, motion=None) -> dict:
    """Generate, (render) and write one clip; returns its meta dict. Skips nothing: callers check ``is_done``.
    ``motion``: precomputed (dancers, heights), e.g. from :func:`mocap_motion`."""
    from hdvr.synth.render import (OCCLUDED, OUTSIDE, VISIBLE, SceneRenderer, boxes_overlap, keypoint_boxes,
                                   keypoint_visibility,
                                   random_camera_path)
    from hdvr.synth.scene import build_scene_xml, random_looks, random_stage

    folder = Path(out_dir) / spec.name
    folder.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    dancers, heights = generate_motion(spec) if motion is None else motion
    n, T = len(dancers), dancers[0].qpos.shape[0]
    t_motion = time.perf_counter() - t_start
    rng = np.random.default_rng([spec.seed, spec.index, 2])
    kp_world = np.stack([d.keypoints for d in dancers])  # (N, T, 25, 3)
    cam = random_camera_path(rng, kp_world[:, :, 8, :2].transpose(1, 0, 2), T, spec.fps, spec.size)
    kp_cam = np.stack([cam.to_camera(kp_world[k]) for k in range(n)])
    intr = cam.intrinsics
    kp2d = np.full((n, T, 25, 2), np.nan)
    vis = np.zeros((n, T, 25), dtype=np.int8)
    boxes = np.full((n, T, 4), np.nan)
    w, h = spec.size
    render_seconds = render_cpu_seconds = 0.0
    looks = random_looks(rng, n)
    stage = random_stage(rng)
    if render:
        import mujoco

        model = mujoco.MjModel.from_xml_string(build_scene_xml(list(heights), looks, stage, spec.size))
        renderer = SceneRenderer(model, n, spec.size)
        writer = VideoWriter(folder / "video.mp4", spec.fps, spec.size, preset="ultrafast", pixel_format="rgb24",
                             background=True)
        qpos_scene = np.concatenate([d.qpos for d in dancers], axis=1)
        ok = False
        t0 = time.perf_counter()
        cpu0 = time.process_time()  # all threads of this process: renderer (llvmpipe) and encoder
        try:
            from hdvr.camera import project

            uv_all = project(kp_cam, intr.focal, intr.principal_point)
            pre_boxes = keypoint_boxes(uv_all, kp_cam, np.isfinite(uv_all).all(-1).any(-1), intr, spec.size)
            for t in range(T):
                overlap = boxes_overlap(pre_boxes[:, t])
                renderer.set_camera(cam.rotation[t], cam.centre[t], intr)
                image, dancer_map = renderer.render(qpos_scene[t], segmentation=bool(overlap.any()))
                writer.write(image)
                for k in range(n):
                    kp2d[k, t], vis[k, t] = keypoint_visibility(kp_cam[k, t], dancer_map if overlap[k] else None,
                                                                k, intr, spec.size)
            ok = True
        finally:
            writer.close() if ok else writer.abort()
            renderer.close()
        render_seconds = time.perf_counter() - t0
        render_cpu_seconds = time.process_time() - cpu0
    else:
        from hdvr.camera import project

        kp2d = project(kp_cam, intr.focal, intr.principal_point)
        inside = np.isfinite(kp2d).all(-1) & (kp2d[..., 0] >= 0) & (kp2d[..., 0] < w) & (kp2d[..., 1] >= 0) & \
            (kp2d[..., 1] < h)
        vis = np.where(inside, VISIBLE, OUTSIDE).astype(np.int8)
    boxes = keypoint_boxes(kp2d, kp_cam, (vis > 0).any(-1), intr, spec.size)
    labels = np.stack([d.labels for d in dancers])
    track_ids = np.arange(1, n + 1, dtype=np.int32)
    # uncompressed: compression costs more than the whole motion generation
    save_npz_atomic(folder / "gt.npz", False, qpos=np.stack([d.qpos for d in dancers]),
                    keypoints3d_world=kp_world.astype(np.float32), keypoints3d_camera=kp_cam.astype(np.float32),
                    keypoints2d=kp2d.astype(np.float32), visibility=vis, boxes=boxes.astype(np.float32),
                    track_ids=track_ids, labels=labels, camera_rotation=cam.rotation, camera_centre=cam.centre,
                    focal=np.full(T, intr.focal), principal_point=np.array(intr.principal_point),
                    image_size=np.array(spec.size, dtype=np.int64), fps=np.float64(spec.fps),
                    genre_index=np.int64(GENRES.index(spec.genre) if spec.genre in GENRES else -1),
                    heights_m=np.asarray(heights))
    for k in range(n):
        conf = np.select([vis[k] == VISIBLE, vis[k] > 0], [1.0, 0.5], 0.0)
        arr = np.concatenate([kp2d[k], conf[..., None]], axis=-1).astype(np.float32)
        kp2 = Keypoints2D(arr, BODY25_NAMES, spec.fps, spec.size)  # validates the 2D keypoint contract
        save_keypoints2d(folder / f"dancer_{k}.keypoints2d.npz", kp2, compress=False)
    vis_frac = (vis == VISIBLE).mean(-1)
    lines = [f"{t + 1},{track_ids[k]},{boxes[k, t, 0]:.2f},{boxes[k, t, 1]:.2f},{boxes[k, t, 2]:.2f},"
             f"{boxes[k, t, 3]:.2f},1,1,{vis_frac[k, t]:.3f}"
             for t, k in zip(*np.nonzero(np.isfinite(boxes[..., 0]).T))]
    write_text_atomic(folder / "mot.txt", "\n".join(lines) + ("\n" if lines else ""))
    tax = load_taxonomy()
    write_text_atomic(folder / "labels.json", json.dumps({
        "genre": spec.genre, "fps": spec.fps,
        "dancers": [{"track_id": int(track_ids[k]), "segments": Labels(labels[k], spec.fps, tax).segments()}
                    for k in range(n)]}))
    from hdvr import dh

    violation = max(float((np.maximum(dh.LOWER - d.qpos[:, 7:], 0) + np.maximum(d.qpos[:, 7:] - dh.UPPER, 0)).max())
                    for d in dancers)
    feet = [foot_metrics(d.keypoints, d.airborne, d.fps, stance=d.stance) for d in dancers]
    from hdvr.synth.scene import collision_model, inter_dancer_penetration

    if all(d.between_m is not None for d in dancers):  # checked when the motion was made
        between = np.array([d.between_m for d in dancers])
    else:
        between = inter_dancer_penetration(collision_model(list(heights)), np.stack([d.qpos for d in dancers])) \
            if n > 1 else np.zeros((1, 1))
    frames = T
    meta = {"format_version": FORMAT_VERSION, "clip": spec.name, "index": spec.index, "seed": spec.seed,
            "genre": spec.genre, "n_dancers": n, "frames": frames, "fps": spec.fps, "seconds": spec.seconds,
            "image_size": list(spec.size), "rendered": bool(render), "heights_m": [float(x) for x in heights],
            "focal_px": float(intr.focal), "joint_limit_violation_rad": violation,
            "foot_penetration_m": max(f["penetration_m"] for f in feet),
            "foot_skate_max_m_s": max(f["skate_max_m_s"] for f in feet),
            "inter_dancer_penetration_m": float(between.max()),
            "visible_fraction": float((vis == VISIBLE).mean()),
            "occluded_fraction": float((vis == OCCLUDED).sum() / max((vis > 0).sum(), 1)),
            "motion_seconds": t_motion, "render_seconds": render_seconds,
            "render_fps": T / render_seconds if render_seconds > 0 else None,
            "render_cpu_seconds": render_cpu_seconds,
            "looks": [{"top_rgb": list(map(float, lk.top_rgb)), "top_texture": lk.top_kind,
                       "bottom_rgb": list(map(float, lk.bottom_rgb)), "bottom_texture": lk.bottom_kind}
                      for lk in looks],
            "stage": {"floor_texture": stage.floor_kind, "wall_texture": stage.wall_kind, "lights": len(stage.lights)}}
    write_text_atomic(folder / "meta.json", json.dumps(meta, indent=1))
    return meta


def is_done(out_dir: str | os.PathLike, spec: ClipSpec, render: bool) -> bool:
    """A clip is done when its meta.json exists with the same spec (and a video when rendering is asked for)."""
    meta_path = Path(out_dir) / spec.name / "meta.json"
    if not meta_path.is_file():
        return False
    try:
        meta = json.loads(meta_path.read_text())
    except (json.JSONDecodeError, OSError):
        return False
    frames_ok = meta.get("frames") == max(int(round(spec.seconds * spec.fps)), 3) or spec.prefix == "mocap"
    same = (meta.get("seed") == spec.seed and meta.get("genre") == spec.genre and frames_ok
            and meta.get("seconds") == spec.seconds and meta.get("format_version") == FORMAT_VERSION
            and meta.get("n_dancers") == spec.n_dancers and meta.get("fps") == spec.fps
            and tuple(meta.get("image_size", ())) == tuple(spec.size))
    if render and not (meta.get("rendered") and (Path(out_dir) / spec.name / "video.mp4").is_file()):
        return False
    return same


def write_index(out_dir: str | os.PathLike) -> dict:
    """Scan the clip folders (``clip_*``, ``mocap_*``) and write ``index.json`` (fixed keys: format_version, genres,
    label_count, clips: list of {clip, genre, genre_index (-1: not one of the nine), n_dancers, frames, fps,
    rendered})."""
    out = Path(out_dir)
    clips = []
    for meta_path in sorted(out.glob("clip_*/meta.json")) + sorted(out.glob("mocap_*/meta.json")):
        try:
            m = json.loads(meta_path.read_text())
        except (json.JSONDecodeError, OSError):
            continue
        clips.append({"clip": m["clip"], "genre": m["genre"],
                      "genre_index": GENRES.index(m["genre"]) if m["genre"] in GENRES else -1,
                      "n_dancers": m["n_dancers"], "frames": m["frames"], "fps": m["fps"], "rendered": m["rendered"]})
    index = {"format_version": FORMAT_VERSION, "genres": list(GENRES), "label_count": len(load_taxonomy().labels),
             "clips": clips}
    write_text_atomic(out / "index.json", json.dumps(index, indent=1))
    return index
