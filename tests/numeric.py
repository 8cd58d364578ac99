"""Central finite differences for the Jacobian tests (tests only: the fit itself never differentiates numerically)."""

import numpy as np


def numeric_jacobian(f, x: np.ndarray, eps: float = 1e-6) -> np.ndarray:
    """d f / d x by central differences: (..., len(x)) for f(x) of any shape."""
    cols = []
    for i in range(len(x)):
        d = np.zeros_like(x)
        d[i] = eps
        cols.append((f(x + d) - f(x - d)) / (2 * eps))
    return np.stack(cols, axis=-1)
