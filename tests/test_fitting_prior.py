"""The shipped learned pose prior (hdvr/data/pose_prior.npz, built by scripts/build_pose_prior.py)."""

import numpy as np

from hdvr import dh
from hdvr.fitting.prior import PRIOR_PATH, shipped_prior

COVARIANCE_FLOOR_DEG = 6.0  # scripts/build_pose_prior.py --covariance-floor-deg default


def _covariances(prior):
    """(K, 31, 31) covariances over the kept hinges, from the stored square-root precisions (radians^2)."""
    kept = np.load(PRIOR_PATH)["kept"]
    roots = prior.sqrt_precision[:, :, kept]  # (K, 31, 31): rows L_k^T
    return np.linalg.inv(np.einsum("kri,krj->kij", roots, roots)), kept


def test_every_kept_hinge_has_at_least_the_covariance_floor_in_every_component():
    # The synthetic generator hardly moves hip adduction / rotation and ankle inversion; without the floor the
    # prior pinned them within 2 deg of neutral. Each component's covariance is S_k + floor^2 I, so every
    # diagonal entry is at least floor^2.
    covs, kept = _covariances(shipped_prior())
    std_deg = np.degrees(np.sqrt(np.einsum("kii->ki", covs)))
    assert std_deg.min() >= COVARIANCE_FLOOR_DEG - 0.01
    names = [dh.JOINT_NAMES[i] for i in kept]
    ankle = names.index("left_ankle_invert")
    assert std_deg[:, ankle].max() < 3 * COVARIANCE_FLOOR_DEG  # still a prior there, not a free hinge


def test_elbow_and_trunk_flexion_are_left_out_of_the_prior():
    prior = shipped_prior()
    kept = set(np.load(PRIOR_PATH)["kept"].tolist())
    for name in ("left_elbow_flex", "right_elbow_flex", "lumbar_flex"):
        index = dh.JOINT_NAMES.index(name)
        assert index not in kept
        assert np.all(prior.sqrt_precision[:, :, index] == 0.0)
