"""Dancer boxes in and out: the ``--boxes`` argument, box files, MOT challenge text and JSON.

Boxes are (x, y, w, h) pixels, (x, y) the top-left corner. Track arrays are (T, N, 4) float with NaN rows where a
dancer has no box. MOT text (MOTChallenge ``gt.txt`` layout) has one line per box:
``frame, id, x, y, w, h, confidence, -1, -1, -1`` with 1-based frame numbers and ids.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.atomic import write_text_atomic


def parse_boxes(text: str) -> list[tuple[float, float, float, float]]:
    """``"x,y,w,h;x,y,w,h"`` -> list of boxes (whitespace allowed)."""
    boxes = []
    for part in text.replace("\n", ";").split(";"):
        part = part.strip()
        if not part:
            continue
        try:
            vals = [float(v) for v in part.replace(" ", ",").split(",") if v != ""]
        except ValueError:
            raise HDVRError(f"cannot read box {part!r}: expected four numbers x,y,w,h") from None
        if len(vals) != 4:
            raise HDVRError(f"box {part!r} has {len(vals)} numbers; expected four: x,y,w,h")
        if vals[2] <= 0 or vals[3] <= 0:
            raise HDVRError(f"box {part!r} must have a positive width and height")
        boxes.append(tuple(vals))
    if not boxes:
        raise HDVRError("no box given: expected x,y,w,h;x,y,w,h ...")
    return boxes


def _read_box_file(path: str | os.PathLike) -> tuple[Path, str, object]:
    """A boxes file read once: (path, kind, content), kind ``"json"`` with the decoded document, ``"mot"`` with the
    MOT tracks (:func:`read_mot`) or ``"lines"`` with the non-comment lines."""
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"boxes file not found: {p}")
    text = p.read_text(encoding="utf-8", errors="replace")
    if text.lstrip().startswith(("[", "{")):
        try:
            return p, "json", json.loads(text)
        except json.JSONDecodeError:
            raise HDVRError(f"corrupt JSON in boxes file {p}") from None
    rows = [line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#")]
    if rows and len(rows[0].split(",")) >= 6:  # MOT text
        return p, "mot", read_mot(p)
    return p, "lines", rows


def _first_frame_boxes(p: Path, kind: str, content) -> list[tuple[float, float, float, float]]:
    """The first frame's boxes of a file read by :func:`_read_box_file` (MOT text: ordered by id)."""
    if kind == "json":
        items = content.get("boxes", content.get("initial_boxes")) if isinstance(content, dict) else content
        if not isinstance(items, list):
            raise HDVRError(f"boxes file {p}: expected a list of [x, y, w, h] under 'boxes'")
        return parse_boxes(";".join(",".join(str(v) for v in b) for b in items))
    if kind == "mot":
        return [tuple(b) for b in content[0] if np.isfinite(b).all()]
    return parse_boxes(";".join(content))


def read_boxes_file(path: str | os.PathLike) -> list[tuple[float, float, float, float]]:
    """Initial boxes from a file: JSON (``[[x, y, w, h], ...]`` or ``{"boxes": [...]}``), MOT text (the boxes of
    the first frame, ordered by id) or plain ``x,y,w,h`` lines."""
    return _first_frame_boxes(*_read_box_file(path))


def read_start_boxes(path: str | os.PathLike) -> list[tuple[int, tuple[float, float, float, float]]]:
    """Each dancer's start frame (0-based) and box (x, y, w, h px) from a file, sorted by start frame (the order
    in which ``hdvr track`` numbers the dancers; equal frames keep the file's order). MOT text: each id starts at
    its first row (ids in order); JSON ``{"starts": [{"frame": F, "box": [x, y, w, h]}, ...]}``; the other
    formats of :func:`read_boxes_file`: every dancer at frame 0. A dancer hidden behind another in the first
    frame can so start later, where it is seen clearly."""
    p, kind, content = _read_box_file(path)
    if kind == "json" and isinstance(content, dict) and "starts" in content:
        items = content["starts"]
        if not isinstance(items, list) or not all(isinstance(i, dict) and "box" in i for i in items):
            raise HDVRError(f"boxes file {p}: expected 'starts' to be a list of {{\"frame\": F, \"box\": "
                            f"[x, y, w, h]}}")
        starts = []
        for item in items:
            frame = item.get("frame", 0)
            if not isinstance(frame, int) or isinstance(frame, bool) or frame < 0:
                raise HDVRError(f"boxes file {p}: start frame {frame!r} is not a whole number >= 0")
            box = item["box"]
            if not isinstance(box, list):
                raise HDVRError(f"boxes file {p}: box {box!r} is not a list [x, y, w, h]")
            starts.append((frame, parse_boxes(",".join(str(v) for v in box))[0]))
    elif kind == "mot":
        seen = np.isfinite(content).all(axis=2)  # (T, N)
        first = seen.argmax(axis=0)
        starts = [(int(first[i]), tuple(float(v) for v in content[first[i], i]))
                  for i in range(content.shape[1]) if seen[:, i].any()]
    else:
        starts = [(0, b) for b in _first_frame_boxes(p, kind, content)]
    if not starts:
        raise HDVRError(f"boxes file {p} has no box")
    return sorted(starts, key=lambda s: s[0])


def _point(values, what: str) -> tuple[float, float]:
    """Two numbers -> an (x, y) px point."""
    try:
        point = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        point = ()
    if len(point) != 2 or not all(np.isfinite(point)):
        raise HDVRError(f"{what}: expected a point x,y (two numbers), got {values!r}")
    return point


def _correction(item, where: str) -> tuple[int, int, tuple[float, ...]]:
    """One ``{"frame": F, "dancer": i, "box": [x, y, w, h]}`` (or ``"point": [x, y]``) -> (frame, dancer, box or
    point). With both (as ``tracks.json`` lists a correction given by a point), the box: the person found there."""
    if not isinstance(item, dict) or not {"frame", "dancer"} <= set(item) or not ("box" in item or "point" in item):
        raise HDVRError(f"{where}: expected each correction as {{\"frame\": F, \"dancer\": i, \"box\": "
                        f"[x, y, w, h]}} or with \"point\": [x, y], got {item!r}")
    frame, dancer = item["frame"], item["dancer"]
    for name, value in (("frame", frame), ("dancer", dancer)):
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise HDVRError(f"{where}: correction {name} {value!r} is not a whole number >= 0")
    if item.get("box") is None and "point" in item:  # (a run stopped before it found the person: box null)
        return frame, dancer, _point(item["point"], f"{where}: correction point")
    box = item["box"]
    if not isinstance(box, list):
        raise HDVRError(f"{where}: correction box {box!r} is not a list [x, y, w, h]")
    return frame, dancer, parse_boxes(",".join(str(v) for v in box))[0]


def read_corrections(path: str | os.PathLike, required: bool = True) -> list[tuple[int, int, tuple[float, ...]]]:
    """Corrections of the tracks from a JSON file: ``[{"frame": F, "dancer": i, "box": [x, y, w, h]}, ...]`` or
    ``{"corrections": [...]}`` (0-based frames and dancer ids as ``hdvr track`` numbers them, boxes px; ``"point":
    [x, y]`` in place of the box names the person the detector finds there), as (frame, dancer, box or point)
    sorted by frame. ``required`` False: a boxes file without corrections (any format of :func:`read_start_boxes`)
    gives an empty list instead of an error."""
    p, kind, content = _read_box_file(path)
    items = content.get("corrections") if kind == "json" and isinstance(content, dict) else \
        content if kind == "json" and required else None
    if items is None:
        if required:
            raise HDVRError(f"corrections file {p}: expected JSON {{\"corrections\": [{{\"frame\": F, "
                            f"\"dancer\": i, \"box\": [x, y, w, h]}}, ...]}}")
        return []
    if not isinstance(items, list):
        raise HDVRError(f"corrections file {p}: 'corrections' is not a list")
    return sorted((_correction(item, f"corrections file {p}") for item in items), key=lambda c: c[0])


def parse_correction(text: str) -> tuple[int, int, tuple[float, ...]]:
    """``"DANCER@FRAME:x,y,w,h"`` (0-based dancer id and frame, box px) or ``"DANCER@FRAME:x,y"`` (a point on the
    dancer: the person the detector finds there) -> (frame, dancer, box or point)."""
    head, sep, where = text.partition(":")
    dancer, at, frame = head.partition("@")
    try:
        if not sep or not at:
            raise ValueError
        dancer_id, frame_index = int(dancer), int(frame)
    except ValueError:
        raise HDVRError(f"cannot read correction {text!r}: expected DANCER@FRAME:x,y,w,h or DANCER@FRAME:x,y (e.g. "
                        f"1@120:300,80,90,260)") from None
    if dancer_id < 0 or frame_index < 0:
        raise HDVRError(f"correction {text!r}: dancer and frame are counted from 0")
    if len([v for v in where.replace(" ", ",").split(",") if v]) == 2:
        return frame_index, dancer_id, _point(where.replace(" ", ",").split(","), f"correction {text!r}")
    return frame_index, dancer_id, parse_boxes(where)[0]


def read_swaps(path: str | os.PathLike) -> list[tuple[int, int, int]]:
    """Identity swaps from a JSON file's ``"swaps": [{"frame": F, "dancers": [a, b]}, ...]`` (0-based frame and ids
    as ``hdvr track`` numbers them) as (frame, a, b) sorted by frame; none when the file has no "swaps" (any format
    of :func:`read_start_boxes` or :func:`read_corrections`)."""
    p, kind, content = _read_box_file(path)
    items = content.get("swaps") if kind == "json" and isinstance(content, dict) else None
    if items is None:
        return []
    if not isinstance(items, list):
        raise HDVRError(f"file {p}: 'swaps' is not a list")
    swaps = []
    for item in items:
        dancers = item.get("dancers") if isinstance(item, dict) else None
        frame = item.get("frame") if isinstance(item, dict) else None
        if not isinstance(dancers, list) or len(dancers) != 2 or not all(
                isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in dancers + [frame]):
            raise HDVRError(f"file {p}: expected each swap as {{\"frame\": F, \"dancers\": [a, b]}} (whole numbers "
                            f">= 0), got {item!r}")
        swaps.append((frame, dancers[0], dancers[1]))
    return sorted(swaps, key=lambda s: s[0])


def parse_swap(text: str) -> tuple[int, int, int]:
    """``"A,B@FRAME"`` (0-based dancer ids and frame) -> (frame, a, b)."""
    pair, at, frame = text.partition("@")
    try:
        a, b = (int(v) for v in pair.split(","))
        frame_index = int(frame)
        if not at:
            raise ValueError
    except ValueError:
        raise HDVRError(f"cannot read swap {text!r}: expected A,B@FRAME (e.g. 0,1@240)") from None
    if min(a, b, frame_index) < 0:
        raise HDVRError(f"swap {text!r}: dancers and frames are counted from 0")
    return frame_index, a, b


def check_boxes_in_frame(boxes, size: tuple[int, int]) -> None:
    """Raise :class:`HDVRError` for a box that lies (mostly) outside a frame of ``size`` = (w, h)."""
    w, h = size
    for i, (x, y, bw, bh) in enumerate(boxes):
        ix = max(0.0, min(x + bw, w) - max(x, 0.0))
        iy = max(0.0, min(y + bh, h) - max(y, 0.0))
        if ix * iy < 0.5 * bw * bh:
            raise HDVRError(f"box {i} ({x:g},{y:g},{bw:g},{bh:g}) lies outside the {w}x{h} frame "
                            f"(less than half of it is inside)")


def write_mot(path: str | os.PathLike, tracks: np.ndarray, confidence: np.ndarray | None = None) -> None:
    """Write (T, N, 4) tracks as MOT text (atomically); NaN rows are skipped."""
    lines = []
    for t, frame_boxes in enumerate(np.asarray(tracks, float)):
        for i, b in enumerate(frame_boxes):
            if not np.isfinite(b).all():
                continue
            conf = 1.0 if confidence is None else float(confidence[t, i])
            lines.append(f"{t + 1},{i + 1},{b[0]:.2f},{b[1]:.2f},{b[2]:.2f},{b[3]:.2f},{conf:.3f},-1,-1,-1")
    write_text_atomic(path, "\n".join(lines) + ("\n" if lines else ""))


def read_mot(path: str | os.PathLike, num_frames: int | None = None, ground_truth: bool = False) -> np.ndarray:
    """MOT text -> (T, N, 4) with N = the largest id and T = the last frame (or ``num_frames``).

    ``ground_truth``: the 7th column is the MOT challenge's (and CVAT's MOT export's) consider flag, not a
    confidence: where every row has 0 or 1 there, the rows marked 0 (ignored boxes) are dropped."""
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"MOT file not found: {p}")
    try:
        data = np.loadtxt(p, delimiter=",", ndmin=2)
    except ValueError:  # rows of different lengths: the six box columns are all that is needed
        try:
            data = np.loadtxt(p, delimiter=",", ndmin=2, usecols=range(6))
        except ValueError:
            raise HDVRError(f"cannot read MOT text {p}: expected lines frame,id,x,y,w,h,...") from None
    if data.size == 0:
        raise HDVRError(f"MOT file {p} has no boxes")
    if data.shape[1] < 6:
        raise HDVRError(f"cannot read MOT text {p}: expected lines frame,id,x,y,w,h,... (got {data.shape[1]} "
                        f"columns)")
    if ground_truth and data.shape[1] >= 7 and np.isin(data[:, 6], (0, 1)).all():
        data = data[data[:, 6] == 1]
        if not len(data):
            raise HDVRError(f"MOT file {p} marks every box as ignored (7th column 0)")
    frames = data[:, 0].astype(int)
    ids = data[:, 1].astype(int)
    if frames.min() < 1 or ids.min() < 1:
        raise HDVRError(f"MOT file {p}: frame numbers and ids start at 1")
    t = num_frames or int(frames.max())
    out = np.full((t, int(ids.max()), 4), np.nan)
    for f, i, row in zip(frames, ids, data[:, 2:6]):
        if f <= t:
            out[f - 1, i - 1] = row
    return out


def write_tracks_json(path: str | os.PathLike, tracks: np.ndarray, status, fps: float, size: tuple[int, int],
                      confidence: np.ndarray | None = None, extra: dict | None = None) -> None:
    """Write tracks as JSON (atomically): per dancer the per-frame box [x, y, w, h] (null where absent), status
    ("tracked": seen; "occluded": hidden behind others, box predicted or filled with hindsight; "hidden": started
    hidden behind another and not come out yet; "out": out of the frame; "absent": not started yet) and
    confidence."""
    tracks = np.asarray(tracks, float)
    dancers = []
    for i in range(tracks.shape[1]):
        dancers.append({
            "id": i,
            "boxes": [None if not np.isfinite(b).all() else [round(float(v), 2) for v in b] for b in tracks[:, i]],
            "status": [s[i] for s in status],
            "confidence": None if confidence is None else [round(float(c), 3) for c in confidence[:, i]],
        })
    doc = {"format": "hdvr-tracks-1", "box": "x, y, w, h pixels, top-left origin", "fps": fps,
           "image_size": list(size), "num_frames": int(tracks.shape[0]), "dancers": dancers, **(extra or {})}
    write_text_atomic(path, json.dumps(doc, separators=(",", ":")))


@dataclass(frozen=True)
class TracksFile:
    """What ``tracks.json`` holds (:func:`write_tracks_json`; written by ``hdvr track``)."""

    boxes: np.ndarray  # (T, N, 4) x, y, w, h px, NaN where absent or out
    status: list  # T tuples of N status names ("tracked", "occluded", "hidden", "out", "absent")
    fps: float
    image_size: tuple[int, int]  # (width, height) px


def read_tracks_json(path: str | os.PathLike) -> TracksFile:
    """Read ``tracks.json`` (or the ``tracks.json`` in a folder ``path``), checking its format and shapes."""
    p = Path(path)
    if p.is_dir():
        p = p / "tracks.json"
    if not p.is_file():
        raise HDVRError(f"tracks file not found: {p} (the tracks.json that hdvr track writes)")
    try:
        doc = json.loads(p.read_text())
        if doc.get("format") != "hdvr-tracks-1":
            raise ValueError(f"format {doc.get('format')!r}, expected 'hdvr-tracks-1'")
        T = int(doc["num_frames"])
        dancers = doc["dancers"]
        boxes = np.full((T, len(dancers), 4), np.nan)
        status = [[None] * len(dancers) for _ in range(T)]
        for i, d in enumerate(dancers):
            if len(d["boxes"]) != T or len(d["status"]) != T:
                raise ValueError(f"dancer {i} has {len(d['boxes'])} boxes and {len(d['status'])} statuses for "
                                 f"{T} frames")
            for t, (b, st) in enumerate(zip(d["boxes"], d["status"])):
                if b is not None:
                    boxes[t, i] = [float(v) for v in b]
                status[t][i] = str(st)
        return TracksFile(boxes, [tuple(row) for row in status], float(doc["fps"]),
                          (int(doc["image_size"][0]), int(doc["image_size"][1])))
    except (ValueError, KeyError, TypeError, IndexError) as exc:
        raise HDVRError(f"cannot read tracks file {p}: {exc}") from None
