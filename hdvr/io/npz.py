"""Shared NPZ reading with one-line errors."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError


def open_npz(path: str | os.PathLike, required: tuple[str, ...], what: str):
    """``np.load`` an NPZ (no pickles) and check it has ``required`` keys; ``what`` names the file kind."""
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"{what} file not found: {p}")
    try:
        data = np.load(p, allow_pickle=False)
        files = data.files
    except Exception as exc:  # zipfile.BadZipFile, ValueError, OSError ...
        raise HDVRError(f"cannot read {what} file {p}: not a valid NPZ ({type(exc).__name__})") from None
    missing = [k for k in required if k not in files]
    if missing:
        raise HDVRError(f"{what} file {p} lacks keys {missing} (has {sorted(files)})")
    return data
