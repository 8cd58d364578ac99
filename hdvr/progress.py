"""Progress bars for long-running commands (tqdm on stderr; silent when ``HDVR_NO_PROGRESS=1``)."""

from __future__ import annotations

import os

from tqdm.auto import tqdm


def progress(iterable=None, total: int | None = None, desc: str = "", unit: str = "frame", **kwargs):
    """A tqdm progress bar with HDVR's defaults; pass-through when progress is disabled."""
    asked_off = kwargs.pop("disable", False)
    disable = os.environ.get("HDVR_NO_PROGRESS", "") == "1" or asked_off
    return tqdm(iterable, total=total, desc=desc, unit=unit, disable=disable, dynamic_ncols=True,
                leave=False, **kwargs)
