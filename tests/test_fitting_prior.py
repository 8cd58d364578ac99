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


def test_a_prior_file_is_loaded_once_and_the_shipped_one_by_default():
    from hdvr.fitting.prior import load_prior

    assert load_prior(None) is shipped_prior()
    assert load_prior(str(PRIOR_PATH)) is load_prior(str(PRIOR_PATH))


def test_a_missing_or_wrong_prior_file_stops_with_one_line(tmp_path):
    import pytest

    from hdvr.errors import HDVRError
    from hdvr.fitting.prior import PosePrior

    with pytest.raises(HDVRError, match="not found"):
        PosePrior(tmp_path / "none.npz")
    np.savez(tmp_path / "other.npz", something=np.zeros(3))
    with pytest.raises(HDVRError, match="not a prior NPZ"):
        PosePrior(tmp_path / "other.npz")
    bad = dict(np.load(PRIOR_PATH))
    bad["means"] = bad["means"][:, :10]
    np.savez(tmp_path / "bad.npz", **bad)
    with pytest.raises(HDVRError, match="wrong shapes"):
        PosePrior(tmp_path / "bad.npz")


def test_the_fit_uses_the_prior_its_settings_name(tmp_path):
    """FitSettings.pose_prior_path reaches the window fitter (hdvr fit3d / hdvr run --pose-prior)."""
    from hdvr.fitting.presets import FitSettings
    from hdvr.fitting.prior import load_prior
    from hdvr.fitting.window import WindowFitter

    path = tmp_path / "copy.npz"
    path.write_bytes(PRIOR_PATH.read_bytes())

    class Kin:
        bone_lengths = np.ones(9)

    obs = np.zeros((3, 25, 2))
    fitter = WindowFitter(Kin(), obs, np.ones((3, 25)), 1000.0, (320, 240), FitSettings(pose_prior_path=str(path)),
                          estimate_focal=False)
    assert fitter.prior is load_prior(str(path)) and fitter.prior is not shipped_prior()
    assert WindowFitter(Kin(), obs, np.ones((3, 25)), 1000.0, (320, 240), FitSettings(),
                        estimate_focal=False).prior is shipped_prior()


def test_the_partner_dance_prior_is_shipped_by_name():
    from hdvr.fitting.prior import NAMED_PRIORS, load_prior

    partner = load_prior("partner")
    assert partner is not shipped_prior() and "rumba, swing, tango, waltz" in partner.source
    assert load_prior("all") is not None and NAMED_PRIORS["all"] == PRIOR_PATH
