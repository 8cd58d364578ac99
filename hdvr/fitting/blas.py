"""Single-threaded BLAS while fitting.

The fit multiplies many tiny matrices (40 x 40 normal equations); OpenBLAS's thread pool costs more than it saves
there and, on 2 cores, competes with MuJoCo (measured: refinement 5x slower with 2 BLAS threads). Without
threadpoolctl in the dependencies, this talks to numpy's bundled OpenBLAS through ctypes when it is found, and
does nothing otherwise.
"""

from __future__ import annotations

import contextlib
import ctypes
import glob
import os

import numpy as np

_LIB = None
_SEARCHED = False


def _openblas():
    global _LIB, _SEARCHED
    if not _SEARCHED:
        _SEARCHED = True
        libs = os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs")
        for path in sorted(glob.glob(os.path.join(libs, "libscipy_openblas*.so*"))):
            try:
                lib = ctypes.CDLL(path)
                lib.scipy_openblas_get_num_threads64_.restype = ctypes.c_int
                lib.scipy_openblas_set_num_threads64_.argtypes = [ctypes.c_int]
                _LIB = lib
                break
            except (OSError, AttributeError):
                continue
    return _LIB


@contextlib.contextmanager
def single_threaded_blas():
    """Run the block with one BLAS thread (restores the previous count)."""
    lib = _openblas()
    if lib is None:
        yield
        return
    before = lib.scipy_openblas_get_num_threads64_()
    lib.scipy_openblas_set_num_threads64_(1)
    try:
        yield
    finally:
        lib.scipy_openblas_set_num_threads64_(before)
