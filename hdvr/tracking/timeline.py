"""Pictures of tracks over time.

- :func:`draw_tracks_timeline` (``timeline.png`` of ``hdvr track``): where each dancer was seen, hidden or out, how
  much of its pose was found, and where the user corrected or swapped it. It answers what the overlay video answers
  only by watching it through: in which stretches a dancer's box rests on evidence (``tracked``: the tracker saw
  it) and in which it is a guess (``occluded``: predicted or filled with hindsight; ``hidden``: waiting behind
  another since its start), which is where to look for a lost dancer before correcting it (docs/tracking.md,
  "Correcting the tracks").
- :func:`draw_truth_timeline` (``hdvr evaluate tracks --plot``): against ground truth, which tracked id lies on each
  true dancer frame by frame, so that identity switches and misses show as changes of colour.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hdvr.layouts import BODY25_NAMES
from hdvr.pose2d.draw import dancer_colour

# status -> how its band is drawn: None = the dancer's own colour, a float = the dancer's colour mixed that far
# towards white, a string = a fixed colour
STATUS_STYLE = {"tracked": None, "occluded": 0.6, "hidden": "#a0a0a0", "out": "#e8e8e8", "absent": "#ffffff"}
STATUS_MEANING = {"tracked": "seen", "occluded": "hidden behind others (box predicted or filled)",
                  "hidden": "waiting hidden behind another since its start", "out": "out of the frame",
                  "absent": "not started"}


def _rgb(colour) -> np.ndarray:
    import matplotlib.colors as mcolors

    return np.array(mcolors.to_rgb(colour))


def dancer_rgb(dancer: int) -> np.ndarray:
    """The dancer's colour in the overlay video (:func:`hdvr.pose2d.draw.dancer_colour`, BGR) as RGB in [0, 1]."""
    b, g, r = dancer_colour(dancer)
    return np.array([r, g, b]) / 255.0


def status_colour(name: str, dancer: int) -> np.ndarray:
    """RGB in [0, 1] of status ``name`` for ``dancer`` (:data:`STATUS_STYLE`)."""
    style, own = STATUS_STYLE[name], dancer_rgb(dancer)
    if style is None:
        return own
    if isinstance(style, float):
        return own + (1.0 - own) * style
    return _rgb(style)


def status_image(status, num_dancers: int) -> np.ndarray:
    """(N, T, 3) RGB in [0, 1]: per dancer (row) and frame (column) the colour of its status (:func:`status_colour`).
    ``status``: T tuples of N status names, as :class:`hdvr.tracking.pipeline.TrackRun` holds them."""
    image = np.ones((num_dancers, len(status), 3))
    for i in range(num_dancers):
        names = np.array([s[i] for s in status], dtype=object)
        for name in STATUS_STYLE:
            mask = names == name
            if mask.any():
                image[i, mask] = status_colour(name, i)
    return image


def pose_fraction(keypoints: np.ndarray) -> np.ndarray:
    """(T, N) fraction of the 25 BODY_25 keypoints found (confidence > 0) per frame and dancer; ``keypoints``
    (T, N, 25, 3) x_px, y_px, confidence."""
    kp = np.asarray(keypoints, float)
    found = (np.nan_to_num(kp[..., 2]) > 0) & np.isfinite(kp[..., :2]).all(axis=-1)
    return found.mean(axis=-1)


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _banded_figure(image: np.ndarray, labels: list[str], fps: float | None, title: str, lower_height: float = 1.6):
    """A figure of two axes sharing the frame axis: on top ``image`` (N, T, 3) RGB as one band per row, labelled
    ``labels``, with seconds along the top when ``fps`` is given; below, an empty axes for a curve per row."""
    plt = _pyplot()
    N, T = image.shape[:2]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(12, 2.6 + 0.4 * N + lower_height), sharex=True,
                                      gridspec_kw={"height_ratios": [0.4 * N + 0.3, lower_height]})
    top.imshow(image, aspect="auto", interpolation="nearest", extent=(-0.5, T - 0.5, N - 0.5, -0.5))
    for i in range(1, N):
        top.axhline(i - 0.5, color="white", linewidth=2)
    top.set_yticks(range(N))
    top.set_yticklabels(labels)
    top.set_ylim(N - 0.5, -0.5)
    if fps:
        seconds = top.secondary_xaxis("top", functions=(lambda f: f / fps, lambda s: s * fps))
        seconds.set_xlabel("seconds", fontsize=8)
    top.set_title(title, fontsize=10)
    bottom.set_xlim(-0.5, T - 0.5)
    bottom.grid(axis="y", color="#dddddd", linewidth=0.6)
    return fig, top, bottom


def _save(fig, handles: list, path: str | os.PathLike, dpi: int) -> Path:
    """Put ``handles`` in a legend under the figure and write it to ``path`` atomically."""
    from hdvr.io.atomic import atomic_path

    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.06 + 0.02 * ((len(handles) + 3) // 4), 1, 1))
    suffix = os.path.splitext(str(path))[1] or ".png"
    with atomic_path(path, suffix=suffix) as tmp:
        fig.savefig(tmp, dpi=dpi)
    _pyplot().close(fig)
    return Path(path)


def draw_tracks_timeline(path: str | os.PathLike, status, keypoints: np.ndarray, fps: float,
                         corrections=(), swaps=(), hidden_starts=(), title: str = "", dpi: int = 110) -> Path:
    """Write the timeline of a tracking run to ``path`` (PNG or JPEG, atomically) and return the path.

    Top: one band per dancer, coloured by status per frame (the dancer's colour where seen, paler where its box is
    a guess, grey while it waits hidden since its start, light grey out of the frame). Marks: a black triangle at
    each correction (``corrections``: (frame, dancer) pairs), a dashed line joining the two dancers of each swap
    (``swaps``: (frame, dancer, dancer)), a grey diamond where a dancer starts (or is corrected to) straight behind
    another (``hidden_starts``: (frame, dancer, dancer in front)). Bottom: the fraction of its BODY_25 keypoints
    found per frame and dancer. Frames along the bottom axis (0-based, as ``--correct`` counts), seconds along the
    top (``fps``)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    kp = np.asarray(keypoints, float)
    T, N = kp.shape[:2]
    if len(status) != T or kp.shape[2:] != (len(BODY25_NAMES), 3):
        raise ValueError(f"timeline: {len(status)} status rows for keypoints of shape {kp.shape} "
                         f"(expected T rows and (T, N, 25, 3))")
    fig, top, bottom = _banded_figure(status_image(status, N), [f"dancer {i}" for i in range(N)], fps,
                                      title or "Tracks over time")
    for frame, dancer in corrections:
        top.plot(frame, dancer - 0.3, marker="v", color="black", markersize=7, clip_on=False)
    for frame, first, second in swaps:
        top.plot([frame, frame], [first, second], color="black", linestyle="--", linewidth=1.2, marker="o",
                 markersize=3)
    for frame, dancer, _front in hidden_starts:
        top.plot(frame, dancer, marker="D", color="#505050", markeredgecolor="white", markersize=6)
    found = np.rint(pose_fraction(kp) * len(BODY25_NAMES))
    for i in range(N):  # each dancer's line a little apart, so that equal counts stay visible
        bottom.plot(np.arange(T), found[:, i] + 0.25 * (i - (N - 1) / 2), color=dancer_rgb(i), linewidth=1.0,
                    drawstyle="steps-mid")
    bottom.set_ylim(-0.5, len(BODY25_NAMES) + 0.5)
    bottom.set_yticks([0, 5, 10, 15, 20, 25])
    bottom.set_ylabel("keypoints found\n(of 25)", fontsize=8)
    bottom.set_xlabel("frame (0-based, as --correct counts)", fontsize=8)
    handles = [Patch(facecolor=status_colour(name, 0), edgecolor="#666666", label=f"{name}: {meaning}")
               for name, meaning in STATUS_MEANING.items() if any(name in row for row in status)]
    if len(corrections):
        handles.append(Line2D([], [], marker="v", color="black", linestyle="none", label="correction"))
    if len(swaps):
        handles.append(Line2D([], [], marker="o", color="black", linestyle="--", markersize=3, label="swap"))
    if len(hidden_starts):
        handles.append(Line2D([], [], marker="D", color="#505050", linestyle="none", label="starts behind another"))
    handles += [Line2D([], [], color=dancer_rgb(i), label=f"dancer {i}") for i in range(N)]
    return _save(fig, handles, path, dpi)


def draw_truth_timeline(path: str | os.PathLike, owner: np.ndarray, best_iou: np.ndarray, fps: float | None = None,
                        iou_threshold: float = 0.5, title: str = "", dpi: int = 110) -> Path:
    """Write (PNG or JPEG, atomically) how tracks cover the ground truth, from
    :func:`hdvr.tracking.evaluation.track_on_truth`'s ``owner`` and ``best_iou`` (T, M): one band per ground-truth
    dancer, coloured per frame in the overlay colour of the tracked id lying on it (so an identity switch is a change
    of colour along a band), grey where no tracked box does (a miss), blank where the dancer is absent; below, the
    best IoU of a tracked box with each dancer, with the threshold dashed. Frames along the bottom axis, seconds
    along the top when ``fps`` is given."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from hdvr.tracking.evaluation import ABSENT, MISSED

    owner = np.asarray(owner)
    best_iou = np.asarray(best_iou, float)
    if owner.ndim != 2 or owner.shape != best_iou.shape:
        raise ValueError(f"timeline: owner {owner.shape} and IoU {best_iou.shape} must be the same (T, M)")
    T, M = owner.shape
    image = np.ones((M, T, 3))
    image[owner.T == MISSED] = _rgb(STATUS_STYLE["hidden"])
    tracks = [int(k) for k in np.unique(owner[owner >= 0])]
    for track in tracks:
        image[owner.T == track] = dancer_rgb(track)
    fig, top, bottom = _banded_figure(image, [f"true dancer {i}" for i in range(M)], fps,
                                      title or "Which track lies on each true dancer")
    line_colours = [_pyplot().cm.tab10(i % 10) for i in range(M)]
    for i in range(M):
        bottom.plot(np.arange(T), best_iou[:, i], color=line_colours[i], linewidth=1.0)
    bottom.axhline(iou_threshold, color="black", linestyle="--", linewidth=0.8)
    bottom.set_ylim(-0.02, 1.02)
    bottom.set_ylabel("best IoU", fontsize=8)
    bottom.set_xlabel("frame (0-based)", fontsize=8)
    handles = [Patch(facecolor=dancer_rgb(k), edgecolor="#666666", label=f"track {k} on it") for k in tracks]
    handles.append(Patch(facecolor=_rgb(STATUS_STYLE["hidden"]), edgecolor="#666666",
                         label=f"no track (IoU < {iou_threshold:g})"))
    if (owner == ABSENT).any():
        handles.append(Patch(facecolor="white", edgecolor="#666666", label="not in the frame"))
    handles += [Line2D([], [], color=line_colours[i], label=f"true dancer {i}: best IoU") for i in range(M)]
    return _save(fig, handles, path, dpi)
