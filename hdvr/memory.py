"""Process memory settings for long video jobs.

glibc's malloc raises its mmap threshold each time a large block that came from mmap is freed, after which
frame-sized blocks (hundreds of kB: decoded frames, encoder pictures, overlay images) are carved from the heap
instead; interleaved with the tracker's and detector's small allocations the heap then fragments and the resident
size grows with video length (measured: `hdvr track` with an overlay, 2400 frames, 593 MB and still rising;
with a fixed threshold 270 MB, flat). :func:`keep_large_blocks_out_of_heap` fixes the threshold so that such
blocks always go back to the system when freed. There is no Python or NumPy API for this, hence ctypes.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys

M_MMAP_THRESHOLD = -3  # mallopt parameter (malloc.h)
LARGE_BLOCK_BYTES = 256 * 1024
_done = {"applied": False}


def keep_large_blocks_out_of_heap(threshold_bytes: int = LARGE_BLOCK_BYTES) -> bool:
    """Fix glibc's mmap threshold (process-wide, once); True when applied, False on other C libraries."""
    if _done["applied"]:
        return True
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):  # musl and others have no mallopt
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    _done["applied"] = bool(mallopt(M_MMAP_THRESHOLD, int(threshold_bytes)))
    return _done["applied"]
