import numpy as np
import pytest

from hdvr import dh
from hdvr.movements.labeller import body_signals
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.skeleton import ROOT_QPOS, Skeleton
from hdvr.synth.choreography import REST, ChoreographyGenerator
from hdvr.synth.declare import JOINT_EFFECTS, Intent, declared_labels


@pytest.fixture(scope="module")
def sk():
    return Skeleton()


def _qpos(hinges):
    q = np.zeros((hinges.shape[0], 41))
    q[:, 2] = 1.0
    q[:, 3] = 1.0
    q[:, ROOT_QPOS:] = hinges
    return q


@pytest.mark.parametrize("part", sorted(JOINT_EFFECTS))
def test_joint_effects_match_forward_kinematics(sk, part):
    """Each declared hinge moves its component in the declared direction (and more than the other components)."""
    for joint, comp, sign in JOINT_EFFECTS[part]:
        h = np.tile(REST, (2, 1))
        h[1, dh.JOINT_NAMES.index(joint)] += 0.2
        sig = body_signals(sk.keypoints(_qpos(h)))[part]
        change = sig.components[1] - sig.components[0]
        k = sig.names.index(comp)
        assert np.sign(change[k]) == sign and abs(change[k]) >= 0.8 * 0.2, (joint, comp, change)
        assert abs(change[k]) == pytest.approx(np.abs(change[list(sig.motion)]).max())


def test_declared_labels_of_a_planned_arm_raise(sk):
    """Raising the left arm sideways (shoulder abduction) inside an arm intent declares Moving Upward while the
    plan moves faster than the still threshold, Holding High after it, Keeping Still outside the intent."""
    tax = load_taxonomy()
    T = 60
    h = np.tile(REST, (T, 1))
    j = dh.JOINT_NAMES.index("left_shoulder_abduct")
    h[10:30, j] = np.linspace(REST[j], 1.85, 20)
    h[30:, j] = 1.85
    ids = declared_labels(tax, sk, _qpos(h), np.zeros(T), np.zeros(T), [Intent("left_arm", "move", 10, 30)], [],
                          30.0)
    part = tax.part("left_upper_arm")
    names = [tax.labels[i].name for i in ids[:, part.index]]
    assert names[5] == "Left Upper Arm Keeping Still"
    assert names[20] == "Left Upper Arm Moving Upward"
    assert names[45] == "Left Upper Arm Holding High"
    # no intent of the right arm: it keeps still
    assert {tax.labels[i].name for i in ids[:, tax.part("right_upper_arm").index]} == {"Right Upper Arm Keeping Still"}


def test_generator_labels_do_not_come_from_the_labeller(monkeypatch):
    """The generator's labels must not depend on the labeller: break it and generate."""
    import hdvr.movements.labeller as lab

    def broken(*a, **k):
        raise AssertionError("the generator called the labeller")

    monkeypatch.setattr(lab.MovementLabeller, "label", broken)
    chor = ChoreographyGenerator().generate("belly_dance", 4, np.random.default_rng(5))
    assert chor.labels.shape == (120, 16)
    assert all(isinstance(it, Intent) for it in chor.primitives)
