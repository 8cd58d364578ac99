"""Pictures of the digital dancer for docs/dancer.md: rest pose (front, side, keypoint sites) and joint limits.

    MUJOCO_GL=egl python scripts/make_dancer_docs.py [--out docs/img]

Writes dancer_rest.jpg (front, side, three-quarter views with the 25 BODY_25 sites) and dancer_limits.jpg (a
contact sheet: every joint group at its minimum and maximum, labelled with the angle in degrees).
"""

import argparse
import os
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from hdvr import dh  # noqa: E402
from hdvr.render import DancerRenderer  # noqa: E402
from hdvr.skeleton import Skeleton  # noqa: E402


def label(img: np.ndarray, text: str, row: int = 0) -> np.ndarray:
    out = cv2.cvtColor(img, cv2.COLOR_RGB2BGR)
    cv2.putText(out, text, (6, 18 + 18 * row), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1, cv2.LINE_AA)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/img")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sk = Skeleton()
    rest = sk.rest_qpos()

    big = DancerRenderer(sk, 360, 480)
    views = []
    for name, az in (("front", 180.0), ("side (left)", 90.0), ("three-quarter", 140.0)):
        big.set_camera(distance=2.4, azimuth=az, elevation=-5.0, lookat=(0, 0, 0.72))
        views.append(label(big.render(rest, show_keypoints=True), f"rest pose, {name}"))
    big.close()
    cv2.imwrite(str(out / "dancer_rest.jpg"), np.hstack(views), [cv2.IMWRITE_JPEG_QUALITY, 85])

    small = DancerRenderer(sk, 200, 240)
    tiles = []
    seen = set()
    for j in dh.JOINTS:
        base = j.name.replace("left_", "").replace("right_", "")
        if base in seen:
            continue
        seen.add(base)
        rows = [r.row for r in dh.JOINTS if r.name.replace("left_", "").replace("right_", "") == base]
        for bound, value in (("min", j.lower), ("max", j.upper)):
            q = rest.copy()
            for r in rows:
                q[7 + r] = value
            small.set_camera(distance=2.6, azimuth=150.0, elevation=-8.0, lookat=(0, 0, 0.72))
            tile = label(small.render(q), base, 0)
            cv2.putText(tile, f"{bound} {np.rad2deg(value):+.1f} deg", (6, 36), cv2.FONT_HERSHEY_SIMPLEX, 0.45,
                        (255, 255, 255), 1, cv2.LINE_AA)
            tiles.append(tile)
    small.close()
    per_row = 8
    while len(tiles) % per_row:
        tiles.append(np.zeros_like(tiles[0]))
    sheet = np.vstack([np.hstack(tiles[i:i + per_row]) for i in range(0, len(tiles), per_row)])
    cv2.imwrite(str(out / "dancer_limits.jpg"), sheet, [cv2.IMWRITE_JPEG_QUALITY, 80])
    print(f"wrote {out / 'dancer_rest.jpg'} and {out / 'dancer_limits.jpg'}")


if __name__ == "__main__":
    main()
