"""``hdvr demo``: the main job on an embedded default, no arguments needed, no ../shared data.

Today it renders the digital dancer moving each joint through its full range (the model every later stage
stands on) to an H.264 video, with the joint's name overlaid; later stages add their steps here as they land.
"""

from __future__ import annotations

from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser("demo", help="run the pipeline on a built-in example (no arguments needed)")
    parser.add_argument("--out", default="hdvr-demo", help="output folder (default: ./hdvr-demo)")
    parser.add_argument("--size", default="480x360", help="video size WxH in pixels (default 480x360)")
    parser.add_argument("--seconds-per-joint", type=float, default=0.5, help="sweep duration per joint group (s)")
    parser.set_defaults(func=run)


def run(args) -> int:
    import cv2

    from hdvr.errors import HDVRError
    from hdvr.progress import progress
    from hdvr.render import DancerRenderer, joint_sweep
    from hdvr.skeleton import Skeleton
    from hdvr.video import VideoWriter

    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        raise HDVRError(f"--size must look like 480x360, got {args.size!r}") from None
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fps = 30.0
    sk = Skeleton()
    qpos, labels = joint_sweep(sk, args.seconds_per_joint, fps)
    renderer = DancerRenderer(sk, width, height, shadows=False)
    renderer.set_camera(distance=2.7, azimuth=150.0, elevation=-10.0, lookat=(0.0, 0.0, 0.72))
    video = out / "dancer_joint_ranges.mp4"
    with VideoWriter(video, fps, (width, height)) as writer:
        for q, label in progress(zip(qpos, labels), total=len(qpos), desc="rendering joint ranges"):
            frame = cv2.cvtColor(renderer.render(q), cv2.COLOR_RGB2BGR)
            cv2.putText(frame, label, (10, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (20, 20, 20), 2, cv2.LINE_AA)
            writer.write(frame)
    renderer.close()
    print(f"digital dancer: 34 hinges + free root, {len(qpos)} frames swept through every joint range")
    print(f"wrote {video}")
    return 0
