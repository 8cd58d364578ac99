"""Pictures for docs/synth.md and docs/movements.md.

- ``docs/img/synth_contact_sheet.jpg``: one frame of a rendered clip per genre, with the ground truth drawn on
  it (BODY_25 skeleton: filled dots visible, hollow dots occluded; boxes with track ids).
- ``docs/img/synth_<genre>.gif``: a short clip per genre (2.5 s, 10 frames/s, 200x150).
- ``docs/img/synth_floor_paths.png``: top view of the floor paths of one 30 s clip per genre.
- ``docs/img/synth_plies.png``: the dancer's plie in parallel, turned out (first position) and in second position,
  from the front and from the side (:func:`hdvr.synth.choreography.turned_out_leg`).
- ``docs/img/movements_salsa_score.png`` and ``docs/img/movements_salsa_poses.png``: the labeller's score of the
  CMU salsa lead (60_01, 0-6 s) and stick figures of the same seconds (needs ../shared/data).

Usage: ``python3 scripts/make_synth_docs.py [--out docs/img] [--shared ../shared/data]``
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HDVR_NO_PROGRESS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
from PIL import Image, ImageDraw  # noqa: E402

from hdvr.layouts import BODY25_BONES, BODY25_NAMES  # noqa: E402
from hdvr.synth.dataset import read_frames  # noqa: E402
from hdvr.synth.genres import GENRE_DISPLAY, GENRES  # noqa: E402
from hdvr.synth.groundtruth import clip_spec, make_clip  # noqa: E402

TRACK_COLOURS = [(255, 64, 64), (64, 160, 255), (80, 220, 80), (255, 200, 40)]
BONES = [(BODY25_NAMES.index(a), BODY25_NAMES.index(b)) for a, b in BODY25_BONES]


def draw_truth(image: np.ndarray, gt, t: int) -> Image.Image:
    img = Image.fromarray(image)
    d = ImageDraw.Draw(img)
    for k in range(gt["keypoints2d"].shape[0]):
        c = TRACK_COLOURS[k % len(TRACK_COLOURS)]
        uv, vis, box = gt["keypoints2d"][k, t], gt["visibility"][k, t], gt["boxes"][k, t]
        if np.isfinite(box).all():
            x, y, w, h = box
            d.rectangle([x, y, x + w, y + h], outline=c, width=2)
            d.text((x + 3, y + 2), f"id {int(gt['track_ids'][k])}", fill=c)
        for a, b in BONES:
            if vis[a] > 0 and vis[b] > 0:
                d.line([tuple(uv[a]), tuple(uv[b])], fill=c, width=2)
        for j in range(25):
            if vis[j] == 0:
                continue
            x, y = uv[j]
            d.ellipse([x - 3, y - 3, x + 3, y + 3], fill=c if vis[j] == 2 else None, outline=c)
    return img


def genre_media(out: Path, seed: int) -> None:
    tiles = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, genre in enumerate(GENRES):
            spec = clip_spec(i, seed, GENRES, (2, 2) if genre not in ("ballet", "tap") else (1, 3), 6.0)
            make_clip(tmp, spec, render=True)
            folder = Path(tmp) / spec.name
            gt = np.load(folder / "gt.npz")
            frames = read_frames(folder / "video.mp4", 0, int(gt["keypoints2d"].shape[1]))
            t_sheet = frames.shape[0] // 2
            tile = draw_truth(frames[t_sheet], gt, t_sheet).resize((320, 240), Image.LANCZOS)
            ImageDraw.Draw(tile).text((6, 6), GENRE_DISPLAY[genre], fill=(255, 255, 255), stroke_width=2,
                                      stroke_fill=(0, 0, 0))
            tiles.append(tile)
            gif = [Image.fromarray(f).resize((200, 150), Image.LANCZOS) for f in frames[30:105:3]]
            gif[0].save(out / f"synth_{genre}.gif", save_all=True, append_images=gif[1:], duration=100, loop=0,
                        optimize=True)
            print(genre, "done", flush=True)
    sheet = Image.new("RGB", (3 * 320, 3 * 240))
    for i, tile in enumerate(tiles):
        sheet.paste(tile, ((i % 3) * 320, (i // 3) * 240))
    sheet.save(out / "synth_contact_sheet.jpg", quality=85)


def path_media(out: Path, seed: int, seconds: float = 30.0) -> None:
    """Top view of the dancers' floor paths (root x, y) in one motion-only clip per genre."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hdvr.synth.groundtruth import generate_motion

    fig, axes = plt.subplots(3, 3, figsize=(9, 9))
    for ax, (i, genre) in zip(axes.ravel(), enumerate(GENRES)):
        dancers, _ = generate_motion(clip_spec(i, seed, GENRES, (2, 2), seconds))
        for k, d in enumerate(dancers):
            xy = d.qpos[:, :2]
            c = np.array(TRACK_COLOURS[k % len(TRACK_COLOURS)]) / 255
            ax.plot(xy[:, 0], xy[:, 1], color=c, linewidth=1.2)
            ax.plot(*xy[0], "o", color=c, markersize=4)
            for side in (19, 22):  # big toes at the frames where a foot is planted: the footprints
                toe = d.keypoints[:, side]
                planted = toe[:, 2] < 0.005
                ax.plot(toe[planted, 0], toe[planted, 1], ".", color=c, markersize=1.5, alpha=0.4)
        ax.set_title(f"{GENRE_DISPLAY[genre]} ({seconds:.0f} s)", fontsize=9)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
    fig.suptitle("Floor paths: root (lines, start = dot) and planted toes, 2 dancers per clip, metres", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "synth_floor_paths.png", dpi=80)
    plt.close(fig)


def salsa_media(out: Path, shared: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hdvr.io.bvh import load_mocap_body25
    from hdvr.movements.labeller import label_keypoints
    from hdvr.movements.score import draw_score

    kp, fps = load_mocap_body25(shared / "cmu-salsa" / "60_01_scaled.bvh", fps=30)
    labels = label_keypoints(kp, fps)
    draw_score(labels, out / "movements_salsa_score.png", "CMU salsa 60_01 (lead), labeller output, 0-6 s", 0, 6,
               dpi=90)
    # stick figures every 0.5 s, seen from the dancer's initial front (world x axis toward the viewer)
    times = np.arange(0.0, 6.01, 0.5)
    fig, axes = plt.subplots(1, len(times), figsize=(1.5 * len(times), 4.0), sharey=True)
    for ax, ts in zip(axes, times):
        p = kp[int(ts * fps)]
        centre = p[8]
        for a, b in BONES:
            side = "tab:red" if "left" in BODY25_NAMES[b] else "tab:blue" if "right" in BODY25_NAMES[b] else "k"
            ax.plot([p[a, 1] - centre[1], p[b, 1] - centre[1]], [p[a, 2], p[b, 2]], color=side, linewidth=1.5)
        hip_line = p[12] - p[9]  # right hip -> left hip; the dancer faces 90 deg clockwise of it
        facing = np.degrees(np.arctan2(hip_line[1], hip_line[0])) - 90.0
        facing = (facing + 180.0) % 360.0 - 180.0
        ax.set_title(f"{ts:.1f} s", fontsize=8)
        ax.set_xlim(-0.6, 0.6)
        ax.set_ylim(0, 1.8)
        ax.set_aspect("equal")
        ax.axis("off")
        ax.text(0, 0.02, f"faces {facing:+.0f}°", ha="center", fontsize=7)
    fig.suptitle("CMU salsa 60_01 (lead): BODY_25 from the mocap, seen along the world x axis "
                 "(red = left side, blue = right side; 'faces' = pelvis heading in the world, 0 = +x)",
                 fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "movements_salsa_poses.png", dpi=90)
    plt.close(fig)


def plie_media(out: Path) -> None:
    """Three plies (parallel; turned out 0.9 rad; turned out 0.9 rad in second position, 0.25 rad open), bent
    0.5 rad at the thigh, front and side views, rendered by MuJoCo."""
    from hdvr.render import DancerRenderer
    from hdvr.skeleton import ROOT_QPOS, Skeleton
    from hdvr.synth.choreography import REST, TURNED_OUT_JOINTS, leg_joints, turned_out_leg

    sk = Skeleton()
    renderer = DancerRenderer(sk, width=240, height=320)
    tiles = []
    for title, turnout, opened in (("parallel", 0.0, 0.0), ("turned out (first position)", 0.9, 0.0),
                                   ("second position", 0.9, 0.25)):
        q = sk.rest_qpos()
        q[ROOT_QPOS:] = REST
        for side in ("left", "right"):
            for name, v in zip(TURNED_OUT_JOINTS, turned_out_leg(sk, side, turnout, 0.5, opened)):
                q[ROOT_QPOS + leg_joints(side)[name]] = v
        q[2] -= sk.keypoints(q)[:, 2].min()  # lowest keypoint on the floor
        row = []
        for azimuth in (180.0, 90.0):  # facing the dancer (+x), then from its right side
            renderer.set_camera(distance=2.6, azimuth=azimuth, elevation=-5.0, lookat=(0.0, 0.0, 0.6))
            row.append(renderer.render(q))
        tile = Image.fromarray(np.concatenate(row, axis=1))
        ImageDraw.Draw(tile).text((6, 6), title, fill=(255, 255, 255))
        tiles.append(np.asarray(tile))
    renderer.close()
    path = out / "synth_plies.png"
    Image.fromarray(np.concatenate(tiles, axis=1)).save(path)
    print(f"wrote {path}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/img")
    ap.add_argument("--shared", default=str(Path(__file__).resolve().parents[2] / "shared" / "data"))
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--skip-genres", action="store_true")
    ap.add_argument("--only-plies", action="store_true", help="only docs/img/synth_plies.png")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    plie_media(out)
    if args.only_plies:
        return 0
    if Path(args.shared).is_dir():
        salsa_media(out, Path(args.shared))
    else:
        print(f"no shared data at {args.shared}: salsa pictures skipped")
    if not args.skip_genres:
        path_media(out, args.seed)
        genre_media(out, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
