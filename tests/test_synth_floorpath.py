import numpy as np
import pytest

from hdvr.movements.labeller import _runs
from hdvr.skeleton import Skeleton
from hdvr.synth.choreography import SOLE_KEYPOINTS, ChoreographyGenerator, leg_fk, leg_ik


def test_leg_ik_inverts_fk():
    theta, knee = leg_ik(np.array([0.1, -0.2, 0.0]), np.array([0.8, 0.75, 0.83]), 0.43, 0.42, 0.05)
    x, z = leg_fk(theta, knee, 0.43, 0.42)
    assert np.allclose(x, [0.1, -0.2, 0.0], atol=1e-9) and np.allclose(z, [0.8, 0.75, 0.83], atol=1e-9)
    assert (knee >= 0.05 - 1e-9).all()


@pytest.mark.parametrize("genre", ["tango", "waltz"])
def test_dancers_travel_by_steps_without_skating(genre):
    """The root travels across the floor while each stance foot stays put (< 1 cm) and on the floor."""
    gen = ChoreographyGenerator(Skeleton(height_m=1.7))
    chor = gen.generate(genre, 30, np.random.default_rng(1))
    assert chor.walks, "no travelling phrase"
    travelled = 0.0
    for s, e in chor.walks:
        travelled += np.linalg.norm(chor.qpos[e - 1, :2] - chor.qpos[s, :2])
        for a, b, code in _runs(chor.stance[s:e]):
            side = "left" if code == 1 else "right"
            sole = chor.keypoints[s + a:s + b][:, list(SOLE_KEYPOINTS[side])]
            centre = sole[..., :2].mean(1)
            assert np.linalg.norm(centre - centre[0], axis=1).max() < 0.01
            assert sole[..., 2].min(1).max() < 0.005  # the stance foot is on the floor
    assert travelled >= 1.0
    # the floor path stays near the start (inside the visible floor area)
    assert np.linalg.norm(chor.qpos[:, :2] - chor.qpos[0, :2], axis=1).max() <= 2.5


def test_partner_walks_backward_with_the_lead():
    lead = ChoreographyGenerator(Skeleton(height_m=1.8)).generate("tango", 30, np.random.default_rng(1))
    follow = ChoreographyGenerator(Skeleton(height_m=1.6)).generate(
        "tango", 30, np.random.default_rng(1), start_xy=(1.0, 0.0), start_yaw=np.pi, mirror_of=lead)
    s, e = lead.walks[0]
    moved_lead = lead.qpos[e - 1, :2] - lead.qpos[s, :2]
    moved_follow = follow.qpos[e - 1, :2] - follow.qpos[s, :2]
    assert np.linalg.norm(moved_lead) > 0.5
    assert np.linalg.norm(moved_follow - moved_lead) < 0.1 * np.linalg.norm(moved_lead)  # same way, same distance
