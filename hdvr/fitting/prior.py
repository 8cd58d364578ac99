"""Learned pose prior: a Gaussian mixture over the 34 hinge angles (radians) fitted on HDVR's synthetic dance
motion (``hdvr/data/pose_prior.npz``, built by ``scripts/build_pose_prior.py`` from :mod:`hdvr.synth`; no real 3D
data). Hinges the synthetic dancer cannot reach over the whole fitting range (elbow and trunk flexion) are
marginalised out (zero columns).

In a frame's fit the prior is the component k of highest responsibility at the start pose, as residual rows
``w L_k^T (q - mu_k)`` (L_k L_k^T = precision) plus one constant row ``w sqrt(c_k - c_min)`` with
``c_k = log det Sigma_k - 2 log pi_k``, so that the squared rows are ``w^2`` times ``-2 log`` of the component's
density up to one constant, comparable between seeds that use different components.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError

PRIOR_PATH = Path(__file__).resolve().parents[1] / "data" / "pose_prior.npz"
#: Priors shipped with the package, by name: ``all`` (the default, the nine genres) and ``partner`` (the partner
#: dances rumba, swing, tango and waltz: legs near parallel, for salsa and ballroom; docs/fitting.md).
NAMED_PRIORS = {"all": PRIOR_PATH, "partner": PRIOR_PATH.with_name("pose_prior_partner.npz")}


@dataclass
class PriorTerm:
    """Residual rows ``sqrt_precision (q - mean)`` and one constant row ``offset`` (all already weighted)."""

    sqrt_precision: np.ndarray  # (R, 34) per radian
    mean: np.ndarray  # (34,) radians
    offset: float


class PosePrior:
    """The hinge-angle Gaussian mixture (see module doc)."""

    def __init__(self, path: str | Path = PRIOR_PATH):
        path = Path(path)
        if not path.is_file():
            raise HDVRError(f"pose prior {path} not found (build one with scripts/build_pose_prior.py)")
        try:
            with np.load(path) as data:
                self.means = data["means"]  # (K, 34) radians
                self.sqrt_precision = data["sqrt_precision"]  # (K, R, 34)
                self.log_norm = data["log_norm"] - data["log_norm"].min()  # (K,) >= 0
                self.source = str(data["source"])
        except (OSError, ValueError, KeyError) as exc:
            raise HDVRError(f"pose prior {path} is not a prior NPZ of scripts/build_pose_prior.py ({exc})") from None
        k = len(self.means)
        if self.means.shape != (k, 34) or self.sqrt_precision.shape[::2] != (k, 34) or self.log_norm.shape != (k,):
            raise HDVRError(f"pose prior {path} has the wrong shapes: means {self.means.shape}, sqrt_precision "
                            f"{self.sqrt_precision.shape}, log_norm {self.log_norm.shape} (34 hinges expected)")

    @property
    def num_components(self) -> int:
        return len(self.means)

    def energies(self, hinges: np.ndarray) -> np.ndarray:
        """(K,) ``-2 log(pi_k N(q; mu_k, Sigma_k))`` up to one constant, for hinges (34,) in radians."""
        z = np.einsum("krd,kd->kr", self.sqrt_precision, hinges[None] - self.means)
        return (z * z).sum(axis=1) + self.log_norm

    def energy(self, hinges: np.ndarray) -> float:
        """The prior's energy of a pose: the least component energy (hard assignment)."""
        return float(self.energies(hinges).min())

    def term(self, hinges: np.ndarray, weight: float) -> PriorTerm:
        """Residual rows of the component with the highest responsibility at ``hinges``, times ``weight``."""
        k = int(np.argmin(self.energies(hinges)))
        return PriorTerm(weight * self.sqrt_precision[k], self.means[k], weight * float(np.sqrt(self.log_norm[k])))


def shipped_prior() -> PosePrior:
    """The prior shipped with the package (loaded once per process)."""
    return load_prior(None)


def load_prior(path: str | None) -> PosePrior:
    """The prior named ``path`` (:data:`NAMED_PRIORS`; None: ``all``) or in the NPZ file ``path``, loaded once
    per process and file."""
    return _load_prior_file(str(NAMED_PRIORS.get("all" if path is None else path, path)))


@lru_cache(maxsize=4)
def _load_prior_file(path: str) -> PosePrior:
    return PosePrior(path)
