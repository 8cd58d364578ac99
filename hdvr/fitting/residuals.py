"""Residuals and analytic Jacobians of one frame's fit (the hot loop).

Residual groups (each a vector; the solver minimises the sum of squares):

- reprojection (pixels / ``sigma_px``): ``sqrt(w_j) (Psi(P_j; f, c) - p_j)`` for every keypoint j with weight
  w_j > 0 (detector confidence x joint weight), optionally through a robust Cauchy loss with scale
  ``robust_px``: the 2-vector e_j / sigma is scaled by ``sqrt(rho(|e|^2)) / |e|`` with
  ``rho(s) = c^2 log(1 + s / c^2)`` (iteratively reweighted: the Jacobian uses the same factor);
- linear keypoint terms in 3D (metres): ``w (c P + K)`` over the 25 keypoints, with a per-term (25,) mask. Temporal
  smoothness (first or second differences against fixed neighbouring frames), 3D targets for mirrored-limb seeds;
- linear keypoint terms in 2D (pixels): ``w (c p_hat + K)``, the paper's 2D temporal term;
- linear hinge terms (radians): ``w (c q + K)`` (hinge smoothness);
- floor terms (metres, when a floor is known): penetration ``w min(0, h_j)`` for the foot keypoints, with
  ``h = n . P - d`` the height above the floor plane; skating ``w (I - n n^T)(P_j - P_j^prev)`` for feet that were
  in contact in the previous frame;
- proximal term ``w_prox (x - x_start)`` on the 40 pose parameters (Tikhonov damping of directions the image
  does not constrain, e.g. head roll or toe flexion; without it a Gauss-Newton step can jump to a far basin);
- focal prior (when the focal length is a parameter): ``(log f - log f0) / sigma_log``;
- pose prior (radians, :mod:`hdvr.fitting.prior`): ``w L_k^T (q - mu_k)`` for one component k of the learned
  hinge-angle mixture, plus a constant row (the component's normaliser).

Parameters: the 40-value tangent of :mod:`hdvr.fitting.kinematics`, plus ``log f`` when ``estimate_focal``.
Every derivative is analytic: MuJoCo site Jacobians chained with the pinhole projection Jacobian.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hdvr.fitting.kinematics import NUM_TANGENT, DancerKinematics, qpos_from_tangent
from hdvr.fitting.prior import PriorTerm

FOOT_KEYPOINTS = np.array([19, 20, 21, 22, 23, 24])  # BODY_25 toes and heels


@dataclass
class LinearTerm:
    """A residual ``weight * (coef * X + const)`` over a quantity X (3D keypoints, 2D keypoints or hinges)."""

    coef: float
    const: np.ndarray
    weight: float
    mask: np.ndarray | None = None  # (J,) 0/1 per keypoint (keypoint terms only)


def collapse_terms(terms: list[LinearTerm]) -> tuple[list[LinearTerm], float]:
    """Merge linear terms over the same quantity into one (fewer Jacobian rows, same minimiser and gradient).

    ``sum_k |w_k (c_k X + K_k)|^2 = W^2 |X + K|^2 + const`` with ``W^2 = sum_k w_k^2 c_k^2`` (per masked keypoint)
    and ``K = sum_k w_k^2 c_k K_k / W^2``. Returns the merged term(s) and the constant (cost units).
    """
    if len(terms) <= 1:
        return terms, 0.0
    shape = terms[0].const.shape
    ones = np.ones(shape[0]) if len(shape) > 1 else np.ones(1)
    a = np.zeros(shape[0] if len(shape) > 1 else 1)
    b = np.zeros(shape)
    c = 0.0
    for t in terms:
        m = t.mask if t.mask is not None else ones
        w2 = (t.weight ** 2) * m
        a = a + w2 * t.coef ** 2
        wb = w2[:, None] if len(shape) > 1 else w2
        b = b + wb * t.coef * t.const
        c += float(np.sum(wb * t.const ** 2))
    safe = np.where(a > 0, a, 1.0)
    kk = b / (safe[:, None] if len(shape) > 1 else safe)
    c -= float(np.sum((b * kk)))
    weight = np.sqrt(a)
    if len(shape) > 1:
        mask = weight
        return [LinearTerm(1.0, kk, 1.0, mask)], c
    return [LinearTerm(1.0, kk, float(weight[0]) if weight.size == 1 else 1.0)], c


@dataclass
class FloorTerms:
    """Floor plane ``n . P = d`` (fitting frame, metres) and the foot terms it enables."""

    normal: np.ndarray
    offset: float
    penetration_weight: float
    skate_weight: float = 0.0
    previous_feet: np.ndarray | None = None  # (6, 3) foot keypoints of the previous frame
    contact_height_m: float = 0.03


@dataclass
class UprightTerm:
    """Trunk tilt prior: residual ``weight (I - v v^T) (P_neck - P_mid_hip) / trunk_m`` (about ``weight sin(tilt)``),
    with v the clip's vertical in the fitting frame (unit) and ``trunk_m`` the trunk length (metres)."""

    vertical: np.ndarray  # (3,) unit
    weight: float  # per unit sine of the tilt
    trunk_m: float
    robust_sine: float | None = None  # Cauchy scale (sine of the tilt) beyond which the prior gives way
    projector: np.ndarray = field(init=False)  # (3, 3) ``weight (I - v v^T) / trunk_m``, built once

    def __post_init__(self) -> None:
        v = np.asarray(self.vertical, dtype=np.float64)
        self.projector = self.weight * (np.eye(3) - np.outer(v, v)) / self.trunk_m

    def scale(self, r: np.ndarray) -> float:
        """Factor turning the residual r (3,) into its robust version (1 without a robust scale)."""
        if not self.robust_sine:
            return 1.0
        c2 = (self.weight * self.robust_sine) ** 2
        s = float(r @ r)
        return float(np.sqrt(c2 * np.log1p(s / c2) / s)) if s > 1e-12 else 1.0


_NECK, _MID_HIP = 1, 8  # BODY_25 indices


@dataclass
class FrameProblem:
    """Everything needed to fit one frame; call :meth:`residual` and :meth:`jacobian` with the parameters."""

    kin: DancerKinematics
    quat_ref: np.ndarray
    observed_px: np.ndarray  # (25, 2), NaN where missing
    weights: np.ndarray  # (25,)
    focal: float
    principal_point: np.ndarray  # (2,)
    sigma_px: float = 1.0
    robust_px: float | None = None
    terms3d: list[LinearTerm] = field(default_factory=list)
    terms2d: list[LinearTerm] = field(default_factory=list)
    hinge_terms: list[LinearTerm] = field(default_factory=list)
    floor: FloorTerms | None = None
    estimate_focal: bool = False
    focal_prior: tuple[float, float] | None = None  # (log f0, sigma of log f)
    proximal_weight: float = 0.0
    proximal_center: np.ndarray | None = None  # (40,) tangent the proximal term pulls towards
    pose_prior: PriorTerm | None = None  # learned hinge prior (one mixture component)
    upright: UprightTerm | None = None  # soft prior on the trunk's tilt from the clip's vertical

    def __post_init__(self) -> None:
        self.terms3d, c3 = collapse_terms(self.terms3d)
        self.terms2d, c2 = collapse_terms(self.terms2d)
        self.hinge_terms, ch = collapse_terms(self.hinge_terms)
        self.constant_cost = c3 + c2 + ch  # dropped by collapsing; added back by :meth:`total_cost`
        self.visible = np.flatnonzero((self.weights > 0) & np.isfinite(self.observed_px).all(axis=1))
        self._sqrt_w = np.sqrt(self.weights[self.visible])[:, None] / self.sigma_px
        self._obs = self.observed_px[self.visible]
        self.principal_point = np.asarray(self.principal_point, dtype=np.float64)

    # ---------------------------------------------------------------------------------------------------------
    @property
    def num_params(self) -> int:
        return NUM_TANGENT + (1 if self.estimate_focal else 0)

    def split(self, params: np.ndarray) -> tuple[np.ndarray, float]:
        x = params[:NUM_TANGENT]
        f = float(np.exp(params[NUM_TANGENT])) if self.estimate_focal else self.focal
        return x, f

    def qpos(self, params: np.ndarray) -> np.ndarray:
        return qpos_from_tangent(params[:NUM_TANGENT], self.quat_ref)

    def _project(self, kp: np.ndarray, f: float) -> np.ndarray:
        z = np.maximum(kp[:, 2:3], 1e-3)
        return f * kp[:, :2] / z + self.principal_point

    def _robust_scale(self, e: np.ndarray) -> np.ndarray | float:
        """(V, 1) factor turning the scaled error e (V, 2) into a robust residual (1.0 without a robust loss)."""
        if not self.robust_px:
            return 1.0
        c2 = (self.robust_px / self.sigma_px) ** 2
        s = (e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1])[:, None]
        safe = np.maximum(s, 1e-12)
        return np.sqrt(np.where(s > 1e-12, c2 * np.log1p(safe / c2) / safe, 1.0))

    def _evaluate(self, params: np.ndarray, with_jacobian: bool):
        x, f = self.split(params)
        qpos = qpos_from_tangent(x, self.quat_ref)
        if with_jacobian:
            kp, jac = self.kin.keypoints_and_jacobian(qpos, x[3:6])
        else:
            kp, jac = self.kin.keypoints(qpos), None
        return x, f, kp, jac

    def residual_parts(self, params: np.ndarray) -> dict[str, np.ndarray]:
        """Named residual groups at ``params`` (for reporting)."""
        x, f, kp, _ = self._evaluate(params, False)
        return self._residuals(x, f, kp)

    def _residuals(self, x, f, kp) -> dict[str, np.ndarray]:
        parts = {}
        proj = self._project(kp[self.visible], f)
        e = (proj - self._obs) * self._sqrt_w
        parts["reprojection"] = (e * self._robust_scale(e)).ravel()
        if self.terms3d:
            parts["temporal3d"] = np.concatenate([
                (t.weight * (t.coef * kp + t.const) * (1.0 if t.mask is None else t.mask[:, None])).ravel()
                for t in self.terms3d])
        if self.terms2d:
            p_all = self._project(kp, f)
            parts["temporal2d"] = np.concatenate([
                (t.weight * np.nan_to_num(t.coef * p_all + t.const)).ravel() for t in self.terms2d])
        if self.hinge_terms:
            parts["hinges"] = np.concatenate([t.weight * (t.coef * x[6:] + t.const) for t in self.hinge_terms])
        if self.floor is not None:
            fl = self.floor
            feet = kp[FOOT_KEYPOINTS]
            h = feet @ fl.normal - fl.offset
            parts["penetration"] = fl.penetration_weight * np.minimum(h, 0.0)
            if fl.skate_weight > 0 and fl.previous_feet is not None:
                parts["skating"] = self._skate(feet, fl).ravel()
        if self.proximal_weight > 0 and self.proximal_center is not None:
            parts["proximal"] = self.proximal_weight * (x - self.proximal_center)
        if self.estimate_focal and self.focal_prior is not None:
            parts["focal_prior"] = np.array([(np.log(f) - self.focal_prior[0]) / self.focal_prior[1]])
        if self.pose_prior is not None:
            pp = self.pose_prior
            parts["pose_prior"] = np.append(pp.sqrt_precision @ (x[6:] - pp.mean), pp.offset)
        if self.upright is not None:
            r = self.upright.projector @ (kp[_NECK] - kp[_MID_HIP])
            parts["upright"] = r * self.upright.scale(r)
        return parts

    def _skate_mask(self, fl: FloorTerms) -> np.ndarray:
        h_prev = fl.previous_feet @ fl.normal - fl.offset
        return (h_prev < fl.contact_height_m).astype(np.float64)

    def _skate(self, feet: np.ndarray, fl: FloorTerms) -> np.ndarray:
        tangential = np.eye(3) - np.outer(fl.normal, fl.normal)
        return fl.skate_weight * self._skate_mask(fl)[:, None] * ((feet - fl.previous_feet) @ tangential)

    def residual_vector(self, params: np.ndarray) -> np.ndarray:
        """(m,) residuals at one parameter vector (the LM solver's hot path)."""
        x, f, kp, _ = self._evaluate(params, False)
        parts = self._residuals(x, f, kp)
        return np.concatenate(list(parts.values())) if len(parts) > 1 else parts["reprojection"]

    # solver interface (mujoco.minimize.least_squares: x shaped (n, k), residual (m, k)) ----------------------
    def residual(self, params: np.ndarray) -> np.ndarray:
        p = np.asarray(params, dtype=np.float64)
        cols = p.reshape(p.shape[0], -1)
        out = []
        for k in range(cols.shape[1]):
            x, f, kp, _ = self._evaluate(cols[:, k], False)
            out.append(np.concatenate(list(self._residuals(x, f, kp).values())))
        return np.stack(out, axis=1)

    def jacobian(self, params: np.ndarray, _residual=None) -> np.ndarray:
        p = np.asarray(params, dtype=np.float64).ravel()
        x, f, kp, jac = self._evaluate(p, True)
        n = self.num_params
        blocks = []
        # reprojection
        vis = self.visible
        pv = kp[vis]
        inv_z = 1.0 / np.maximum(pv[:, 2], 1e-3)
        uv = pv[:, :2] * inv_z[:, None]  # normalised image coordinates
        proj = f * uv + self.principal_point
        e = (proj - self._obs) * self._sqrt_w
        scale = self._robust_scale(e) * self._sqrt_w * f  # (V, 2): pixels per normalised unit, robust, weighted
        jv = jac[vis]
        # d(u, v)/dP = f / z [[1, 0, -u], [0, 1, -v]]: hdvr.camera.projection_jacobian's formula, applied to the
        # site Jacobians directly (28 instead of 50 us per call; this runs ~25 times per frame)
        dxy = (jv[:, :2, :] - uv[:, :, None] * jv[:, 2:3, :]) * inv_z[:, None, None]
        block = np.zeros((len(vis), 2, n))
        block[:, :, :NUM_TANGENT] = dxy * scale[:, :, None]
        if self.estimate_focal:
            block[:, :, NUM_TANGENT] = uv * scale
        blocks.append(block.reshape(-1, n))
        if self.terms3d:
            for t in self.terms3d:
                b = np.zeros((25, 3, n))
                m = 1.0 if t.mask is None else t.mask[:, None, None]
                b[:, :, :NUM_TANGENT] = t.weight * t.coef * jac * m
                blocks.append(b.reshape(-1, n))
        if self.terms2d:
            z_all = np.maximum(kp[:, 2], 1e-3)
            d_all = np.zeros((25, 2, 3))
            d_all[:, 0, 0] = f / z_all
            d_all[:, 0, 2] = -f * kp[:, 0] / z_all ** 2
            d_all[:, 1, 1] = f / z_all
            d_all[:, 1, 2] = -f * kp[:, 1] / z_all ** 2
            jp = np.einsum("vij,vjk->vik", d_all, jac)
            for t in self.terms2d:
                b = np.zeros((25, 2, n))
                b[:, :, :NUM_TANGENT] = t.weight * t.coef * jp
                if self.estimate_focal:
                    b[:, :, NUM_TANGENT] = t.weight * t.coef * f * kp[:, :2] / z_all[:, None]
                blocks.append(b.reshape(-1, n))
        if self.hinge_terms:
            for t in self.hinge_terms:
                b = np.zeros((34, n))
                b[:, 6:NUM_TANGENT] = t.weight * t.coef * np.eye(34)
                blocks.append(b)
        if self.floor is not None:
            fl = self.floor
            feet = kp[FOOT_KEYPOINTS]
            h = feet @ fl.normal - fl.offset
            b = np.zeros((len(FOOT_KEYPOINTS), n))
            active = (h < 0).astype(np.float64)
            b[:, :NUM_TANGENT] = fl.penetration_weight * active[:, None] * np.einsum(
                "i,jik->jk", fl.normal, jac[FOOT_KEYPOINTS])
            blocks.append(b)
            if fl.skate_weight > 0 and fl.previous_feet is not None:
                tangential = np.eye(3) - np.outer(fl.normal, fl.normal)
                b = np.zeros((len(FOOT_KEYPOINTS), 3, n))
                b[:, :, :NUM_TANGENT] = fl.skate_weight * self._skate_mask(fl)[:, None, None] * np.einsum(
                    "ij,fjk->fik", tangential, jac[FOOT_KEYPOINTS])
                blocks.append(b.reshape(-1, n))
        if self.proximal_weight > 0 and self.proximal_center is not None:
            b = np.zeros((NUM_TANGENT, n))
            b[:, :NUM_TANGENT] = self.proximal_weight * np.eye(NUM_TANGENT)
            blocks.append(b)
        if self.estimate_focal and self.focal_prior is not None:
            b = np.zeros((1, n))
            b[0, NUM_TANGENT] = 1.0 / self.focal_prior[1]
            blocks.append(b)
        if self.pose_prior is not None:
            b = np.zeros((len(self.pose_prior.sqrt_precision) + 1, n))
            b[:-1, 6:NUM_TANGENT] = self.pose_prior.sqrt_precision  # the constant row has no derivative
            blocks.append(b)
        if self.upright is not None:
            b = np.zeros((3, n))
            r = self.upright.projector @ (kp[_NECK] - kp[_MID_HIP])
            b[:, :NUM_TANGENT] = self.upright.scale(r) * (self.upright.projector @ (jac[_NECK] - jac[_MID_HIP]))
            blocks.append(b)
        return np.concatenate(blocks, axis=0)

    def reprojection_error_px(self, params: np.ndarray) -> float:
        """Mean distance (pixels) between projected and observed visible keypoints."""
        x, f, kp, _ = self._evaluate(params, False)
        if len(self.visible) == 0:
            return float("nan")
        return float(np.linalg.norm(self._project(kp[self.visible], f) - self._obs, axis=1).mean())
