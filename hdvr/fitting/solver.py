"""Box-bounded Levenberg-Marquardt for one frame, with analytic Jacobians.

Two solvers, same problem (:class:`hdvr.fitting.residuals.FrameProblem`):

- ``"lm"`` (default): projected Levenberg-Marquardt. Each iteration solves
  ``(J_F^T J_F + lambda diag(J_F^T J_F)) dx_F = -J_F^T r`` over the free parameters F (those not held at a bound
  by a gradient pointing outwards), clips ``x + dx`` into the box, accepts it if the cost drops (lambda / 3) and
  otherwise retries with lambda x 4. lambda starts at 1e-3 (Marquardt's scaling), and is carried from one iteration
  to the next. The solve is a 40 x 40 system: far below the cost of the MuJoCo Jacobian.
- ``"mujoco"``: ``mujoco.minimize.least_squares`` (box-bounded LM of the MuJoCo bindings). Kept for comparison:
  it starts every solve with zero damping (a Gauss-Newton step, which on this rank-deficient problem jumps to far
  basins) and raises the damping in small steps, which on the benchmark made it slower and less accurate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from mujoco import minimize

from hdvr.fitting.kinematics import NUM_TANGENT
from hdvr.fitting.residuals import FrameProblem

ROOT_TRANSLATION_BOUND_M = 200.0
FREE_HINGE_BOUND_RAD = 2 * np.pi  # hinges when joint limits are switched off
LOG_FOCAL_BOUNDS = (np.log(50.0), np.log(50000.0))


@dataclass
class FrameSolution:
    params: np.ndarray  # tangent (40,) [+ log f]
    cost: float  # sum of squared residuals at the solution
    iterations: int


def parameter_bounds(problem: FrameProblem, lower: np.ndarray, upper: np.ndarray,
                     joint_limits: bool) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the frame parameters; hinges at their ranges (hard joint limits) or +-2 pi when switched off."""
    lo = np.empty(problem.num_params)
    hi = np.empty(problem.num_params)
    lo[:3], hi[:3] = -ROOT_TRANSLATION_BOUND_M, ROOT_TRANSLATION_BOUND_M
    lo[3:6], hi[3:6] = -np.pi, np.pi
    if joint_limits:
        lo[6:NUM_TANGENT], hi[6:NUM_TANGENT] = lower, upper
    else:
        lo[6:NUM_TANGENT], hi[6:NUM_TANGENT] = -FREE_HINGE_BOUND_RAD, FREE_HINGE_BOUND_RAD
    if problem.estimate_focal:
        lo[NUM_TANGENT], hi[NUM_TANGENT] = LOG_FOCAL_BOUNDS
    return lo, hi


SOLVERS = ("lm", "mujoco")
_solver_choice = {"name": "lm"}


def set_default_solver(name: str) -> None:
    """Select the per-frame solver used by :func:`solve_frame` ("lm" or "mujoco")."""
    if name not in SOLVERS:
        raise ValueError(f"unknown solver {name!r}; choose from {SOLVERS}")
    _solver_choice["name"] = name


def projected_lm(residual, jacobian, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, max_iter: int = 10,
                 tolerance: float = 1e-6, damping: float = 1e-3) -> tuple[np.ndarray, float, int]:
    """Box-bounded Levenberg-Marquardt (see module doc). ``residual(x)`` -> (m,) and ``jacobian(x)`` -> (m, n).

    Returns (x, cost = sum of squared residuals, iterations).
    """
    x = np.clip(x0, lo, hi)
    r = residual(x)
    cost = float(r @ r)
    lam = damping
    it = 0
    for it in range(1, max_iter + 1):
        jac = jacobian(x)
        grad = jac.T @ r
        hess = jac.T @ jac
        at_lo = (x <= lo + 1e-12) & (grad > 0)
        at_hi = (x >= hi - 1e-12) & (grad < 0)
        free = ~(at_lo | at_hi)
        all_free = bool(free.all())  # the common case: no fancy indexing
        h, g = (hess, grad) if all_free else (hess[np.ix_(free, free)], grad[free])
        diag = h.diagonal().copy()
        floor = 1e-9 * max(float(diag.max(initial=0.0)), 1e-12)
        improved = False
        base = np.maximum(diag, floor)
        idx = np.arange(len(diag))
        for _ in range(8):
            a = h.copy()
            a[idx, idx] += lam * base + floor
            try:
                step = -np.linalg.solve(a, g)
            except np.linalg.LinAlgError:
                lam *= 4.0
                continue
            x_new = x.copy()
            if all_free:
                x_new += step
            else:
                x_new[free] += step
            np.clip(x_new, lo, hi, out=x_new)
            r_new = residual(x_new)
            cost_new = float(r_new @ r_new)
            if cost_new < cost:
                improved = True
                decrease = cost - cost_new
                moved = float(np.max(np.abs(x_new - x)))
                x, r, cost = x_new, r_new, cost_new
                lam = max(lam / 3.0, 1e-9)
                break
            lam *= 4.0
        if not improved or decrease <= tolerance * max(cost, 1e-12) or moved < 1e-9:
            break
    return x, cost, it


def solve_frame(problem: FrameProblem, params0: np.ndarray, bounds: tuple[np.ndarray, np.ndarray],
                max_iter: int = 10, tolerance: float = 1e-3, mu_factor: float = 10.0 ** 0.5,
                solver: str | None = None) -> FrameSolution:
    """Minimise the frame's residuals from ``params0`` within ``bounds`` (solver: "lm" or "mujoco")."""
    lo, hi = bounds
    x0 = np.clip(np.asarray(params0, dtype=np.float64), lo + 1e-9, hi - 1e-9)
    if problem.proximal_weight > 0:
        problem.proximal_center = x0[:NUM_TANGENT].copy()
    if (solver or _solver_choice["name"]) == "lm":
        x, cost, iters = projected_lm(problem.residual_vector, problem.jacobian,
                                      x0, lo, hi, max_iter=max_iter, tolerance=tolerance)
        return FrameSolution(x, cost, iters)
    x, trace = minimize.least_squares(x0, problem.residual, bounds=(lo, hi), jacobian=problem.jacobian,
                                      max_iter=max_iter, xtol=tolerance, gtol=tolerance, verbose=0,
                                      mu_factor=mu_factor)
    r = problem.residual(x)
    return FrameSolution(np.asarray(x, dtype=np.float64).ravel(), float(np.sum(r * r)), len(trace))
