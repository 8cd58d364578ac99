"""scripts/build_pose_prior.py: a prior for chosen genres, written whole, loadable by the fit."""

import subprocess
import sys
from pathlib import Path

import numpy as np

from hdvr.fitting.prior import PosePrior

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "build_pose_prior.py"


def test_a_prior_for_one_genre_is_built_and_loads(tmp_path):
    out = tmp_path / "ballet_prior.npz"
    run = subprocess.run([sys.executable, str(SCRIPT), "--genres", "ballet", "--clips-per-genre", "2",
                          "--seconds", "4", "--components", "2", "--held-out-clips-per-genre", "1",
                          "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "held out (seed 1" in run.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ballet_prior.npz"]  # no partial file left
    prior = PosePrior(out)
    assert prior.num_components == 2 and "ballet" in prior.source
    assert list(np.load(out)["genres"]) == ["ballet"]
    # a turned-out style: the mixture's mean hip rotation is external (negative) on both legs
    from hdvr import dh

    w = np.load(out)["weights"]
    for side in ("left", "right"):
        rotation = w @ prior.means[:, dh.JOINT_NAMES.index(f"{side}_hip_rotate")]
        assert rotation < -0.05, rotation
