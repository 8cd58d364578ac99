"""Multi-person 2D pose from an ONNX model on CPU (onnxruntime).

Formats, recognised from the model's outputs:

- ``yolo``: Ultralytics YOLO-pose export, one output (1, 4 + 1 + 17*3, anchors): box centre/size, person score,
  17 COCO keypoints (x, y, visibility) in input pixels. Input RGB in [0, 1], letterboxed (grey 114), centred.
- ``yolo-end2end``: Ultralytics NMS-free export, one output (1, detections, 6 + 17*3): x1, y1, x2, y2, score,
  class, keypoints.
- ``rtmo``: RTMO (MMPose) export, two outputs: boxes (1, N, 5) = x1, y1, x2, y2, score and keypoints
  (1, N, 17, 3) = x, y, score. Input BGR in [0, 255], padded (114) at the bottom/right.

``input_size`` is the longer side of the network input in pixels (the frame is scaled to fit and padded to a
multiple of 32, so a 16:9 frame at 320 runs at 320x192); smaller is faster and finds fewer small people.
Models with a fixed input size use theirs. :meth:`OnnxPoseDetector.at_input_size` gives the same model at another
input size, sharing its session (the tracking pipeline runs it smaller on crops about single dancers).

``flip_test`` (off by default): the model also runs on the mirror image of the frame, and the people it finds there
(mirrored back, left and right keypoints exchanged) join those of the frame itself before one non-maximum
suppression, the horizontal-flip test-time augmentation of pose estimation. A person the model misses in one view is
often found in the other: on hdvr synth clips where tracking fails (YOLO11n-pose at 480 px), a detection on the
dancer (IoU >= 0.5 with her box) for 82 % of the dancers showing all their keypoints with the frame alone, 87 % with
both views; of those showing 40-90 % of them 50 % and 59 % (docs/benchmarks.md). It doubles the detector's time.
"""

from __future__ import annotations

import copy
import os
from pathlib import Path

import cv2
import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import COCO17_NAMES
from hdvr.pose2d.base import PersonPose

FORMATS = ("yolo", "yolo-end2end", "rtmo")

#: COCO-17 index of each joint's mirror image (left <-> right), for keypoints found on a mirrored frame
COCO17_MIRROR = np.array([COCO17_NAMES.index(n.replace("left_", "#").replace("right_", "left_").replace("#", "right_"))
                          for n in COCO17_NAMES])


class OnnxPoseDetector:
    """A YOLO-pose or RTMO ONNX model as a :class:`hdvr.pose2d.base.PoseDetector`."""

    def __init__(self, model_path: str | os.PathLike, input_size: int = 640,
                 score_threshold: float = 0.3, nms_iou: float = 0.6, threads: int | None = None,
                 model_format: str | None = None, weak_threshold: float | None = None, flip_test: bool = False):
        """``score_threshold``: the lowest score of a sure find. ``weak_threshold`` (None: none): people scoring
        from it up to ``score_threshold`` are returned too, marked ``weak`` (:class:`PersonPose`). ``flip_test``:
        look at the mirrored frame too (module docstring)."""
        import onnxruntime as ort

        path = Path(model_path)
        if not path.is_file():
            raise HDVRError(f"pose model not found: {path}")
        options = ort.SessionOptions()
        options.intra_op_num_threads = threads or min(os.cpu_count() or 1, 4)
        options.inter_op_num_threads = 1
        options.log_severity_level = 3
        # no busy-waiting between runs: the tracker works in between, on the same cores
        options.add_session_config_entry("session.intra_op.allow_spinning", "0")
        try:
            self.session = ort.InferenceSession(str(path), options, providers=["CPUExecutionProvider"])
        except Exception as exc:  # onnxruntime raises its own exception types for bad files
            raise HDVRError(f"cannot load ONNX pose model {path}: {type(exc).__name__}: "
                            f"{str(exc).splitlines()[0][:200]}") from None
        self.name = f"onnx:{path.name}"
        inp = self.session.get_inputs()[0]
        self.input_name = inp.name
        outs = self.session.get_outputs()
        self.model_format = model_format or self._guess_format(outs)
        if self.model_format not in FORMATS:
            raise HDVRError(f"unknown pose model format {self.model_format!r}; expected one of {FORMATS}")
        fixed_h, fixed_w = inp.shape[2], inp.shape[3]
        self.fixed_size = (fixed_w, fixed_h) if isinstance(fixed_w, int) and isinstance(fixed_h, int) else None
        self.input_size = int(input_size)
        self.score_threshold = score_threshold
        if weak_threshold is not None and not 0 < weak_threshold <= score_threshold:
            raise HDVRError(f"weak detection threshold must be in (0, {score_threshold:g}], got {weak_threshold:g}")
        self.weak_threshold = score_threshold if weak_threshold is None else weak_threshold
        self.nms_iou = nms_iou
        self.flip_test = bool(flip_test)
        self.model_path = path

    def at_input_size(self, input_size: int) -> "OnnxPoseDetector":
        """This detector at another network input size (the longer side, px), sharing its model session: the
        tracking pipeline looks at crops about single dancers with a smaller input than whole frames
        (:data:`hdvr.tracking.pipeline.ZOOM_INPUT_SIZE`). A model exported with a fixed input size keeps it."""
        if self.fixed_size or int(input_size) == self.input_size:
            return self
        if int(input_size) < 32:
            raise HDVRError(f"pose model input size must be at least 32 px, got {input_size}")
        view = copy.copy(self)
        view.input_size = int(input_size)
        return view

    def cache_key(self) -> dict:
        """The model file and every setting that changes the people found (:mod:`hdvr.pose2d.cache`)."""
        stat = self.model_path.stat()
        return {"model": self.model_path.name, "model_bytes": stat.st_size, "model_mtime_ns": stat.st_mtime_ns,
                "format": self.model_format, "input_size": self.fixed_size or self.input_size,
                "score_threshold": self.score_threshold, "weak_threshold": self.weak_threshold,
                "nms_iou": self.nms_iou, "flip_test": self.flip_test}

    @staticmethod
    def _guess_format(outputs) -> str:
        if len(outputs) >= 2:
            return "rtmo"
        shape = outputs[0].shape
        if len(shape) == 3 and shape[1] == 56:
            return "yolo"
        if len(shape) == 3 and shape[2] == 57:
            return "yolo-end2end"
        raise HDVRError(f"cannot tell the pose model's format from its output shape {shape}; "
                        f"pass model_format (one of {FORMATS})")

    # ------------------------------------------------------------ preprocess
    def _letterbox(self, frame: np.ndarray, centred: bool):
        h, w = frame.shape[:2]
        if self.fixed_size:
            w_in, h_in = self.fixed_size
            r = min(w_in / w, h_in / h)
            nw, nh = int(round(w * r)), int(round(h * r))
        else:
            r = self.input_size / max(w, h)
            nw, nh = int(round(w * r)), int(round(h * r))
            w_in, h_in = -(-nw // 32) * 32, -(-nh // 32) * 32
        resized = cv2.resize(frame, (nw, nh), interpolation=cv2.INTER_LINEAR if r > 1 else cv2.INTER_AREA)
        canvas = np.full((h_in, w_in, 3), 114, np.uint8)
        ox, oy = ((w_in - nw) // 2, (h_in - nh) // 2) if centred else (0, 0)
        canvas[oy:oy + nh, ox:ox + nw] = resized
        return canvas, r, ox, oy

    # --------------------------------------------------------------- detect
    def _candidates(self, canvas: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The model's people on a letterboxed ``canvas`` scoring ``weak_threshold`` or more: boxes (K, 4) x1, y1,
        x2, y2, scores (K,) and keypoints (K, 17, 3), in canvas pixels; raw anchors (before non-maximum suppression)
        for ``yolo``."""
        if self.model_format == "rtmo":
            blob = np.ascontiguousarray(canvas.transpose(2, 0, 1))[None].astype(np.float32)
            boxes, kpts = self.session.run(None, {self.input_name: blob})[:2]
            xyxy, scores, kp = boxes[0][:, :4], boxes[0][:, 4], kpts[0].astype(np.float32)
        else:
            blob = cv2.dnn.blobFromImage(np.ascontiguousarray(canvas), 1 / 255.0, swapRB=True)
            out = self.session.run(None, {self.input_name: blob})[0][0]
            if self.model_format == "yolo":
                out = out.T  # (anchors, 56)
                cx, cy, bw, bh = out[:, 0], out[:, 1], out[:, 2], out[:, 3]
                xyxy = np.stack([cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2], axis=1)
                scores, kp = out[:, 4], out[:, 5:].reshape(-1, 17, 3)
            else:
                xyxy, scores, kp = out[:, :4], out[:, 4], out[:, 6:].reshape(-1, 17, 3)
        keep = scores >= self.weak_threshold
        return xyxy[keep], scores[keep], kp[keep]

    def detect(self, frame_bgr: np.ndarray, frame_index: int = 0) -> list[PersonPose]:
        canvas, r, ox, oy = self._letterbox(frame_bgr, centred=self.model_format != "rtmo")
        xyxy, scores, kp = self._candidates(canvas)
        if self.flip_test:
            # the mirrored canvas's pixel column u is the canvas's column width - u: mirror the finds back, and
            # a left joint seen there is the right one
            width = canvas.shape[1]
            fx, fs, fk = self._candidates(canvas[:, ::-1])
            fk = fk[:, COCO17_MIRROR]  # a copy (fancy indexing): the model's output is not written to
            fx = np.column_stack([width - fx[:, 2], fx[:, 1], width - fx[:, 0], fx[:, 3]])
            fk[..., 0] = width - fk[..., 0]
            xyxy, scores, kp = np.concatenate([xyxy, fx]), np.concatenate([scores, fs]), np.concatenate([kp, fk])
        # greedy NMS: a weaker candidate never suppresses a stronger one, so the sure finds are the same with or
        # without weak ones (NMS-free formats need it only to merge the two views of the flip test)
        if len(scores) and (self.model_format == "yolo" or self.flip_test):
            boxes_xywh = np.column_stack([xyxy[:, :2], xyxy[:, 2:] - xyxy[:, :2]]).tolist()
            idx = cv2.dnn.NMSBoxes(boxes_xywh, scores.tolist(), self.weak_threshold, self.nms_iou)
            idx = np.asarray(idx, int).ravel()
            xyxy, scores, kp = xyxy[idx], scores[idx], kp[idx]
        # back to frame pixels
        xyxy = (xyxy - np.array([ox, oy, ox, oy])) / r
        kp = kp.copy()
        kp[..., 0] = (kp[..., 0] - ox) / r
        kp[..., 1] = (kp[..., 1] - oy) / r
        conf = np.clip(kp[..., 2], 0, 1)
        kp[..., 2] = conf
        kp[conf <= 0.0, :2] = np.nan
        people = []
        h, w = frame_bgr.shape[:2]
        for box, score, k in zip(xyxy, scores, kp):
            x0, y0 = max(box[0], 0.0), max(box[1], 0.0)
            x1, y1 = min(box[2], w), min(box[3], h)
            if x1 - x0 < 2 or y1 - y0 < 2:
                continue
            people.append(PersonPose(k.astype(np.float32), (float(x0), float(y0), float(x1 - x0), float(y1 - y0)),
                                     float(score), COCO17_NAMES, weak=bool(score < self.score_threshold)))
        people.sort(key=lambda p: -p.score)
        return people
