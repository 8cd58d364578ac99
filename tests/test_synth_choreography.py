import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.movements.labeller import MovementLabeller
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.synth.choreography import ChoreographyGenerator, foot_metrics, ramp_profile
from hdvr.synth.genres import GENRES


@pytest.fixture(scope="module")
def generator():
    return ChoreographyGenerator()


def test_ramp_profile_is_monotone_and_ends_at_one():
    p = ramp_profile(20)
    assert p[-1] == pytest.approx(1.0) and (np.diff(p) > 0).all()


def test_deterministic_for_a_seed(generator):
    a = generator.generate("tango", 6, np.random.default_rng([3, 1]))
    b = generator.generate("tango", 6, np.random.default_rng([3, 1]))
    c = generator.generate("tango", 6, np.random.default_rng([4, 1]))
    assert np.array_equal(a.qpos, b.qpos) and np.array_equal(a.labels, b.labels)
    assert not np.array_equal(a.qpos, c.qpos)


@pytest.mark.parametrize("genre", GENRES)
def test_generated_motion_is_valid_and_labels_are_recovered(generator, genre):
    chor = generator.generate(genre, 20, np.random.default_rng([11, GENRES.index(genre)]))
    sk = generator.sk
    assert chor.qpos.shape == (600, 41) and chor.labels.shape == (600, 16)
    assert sk.limit_violation(chor.qpos).max() == 0.0
    feet = foot_metrics(chor.keypoints, chor.airborne, chor.fps, stance=chor.stance)
    assert feet["penetration_m"] <= 0.01
    assert feet["skate_max_m_s"] < 0.02, feet  # weight-bearing feet do not slide
    # smooth: no joint jumps more than 0.5 rad between frames (kicks reach ~0.35)
    assert np.abs(np.diff(chor.qpos[:, 7:], axis=0)).max() < 0.5
    pred = MovementLabeller().label(chor.keypoints, chor.fps).ids
    accuracy = (pred == chor.labels).mean(0)  # micro F-score per part (one label per part and frame)
    assert accuracy.min() >= 0.85, dict(zip(load_taxonomy().part_names, accuracy.round(3)))


def test_couples_mirror(generator):
    lead = generator.generate("waltz", 5, np.random.default_rng(2))
    follow = generator.generate("waltz", 5, np.random.default_rng(2), start_xy=(0.75, 0.0), start_yaw=np.pi,
                                mirror_of=lead)
    assert follow.qpos.shape == lead.qpos.shape
    assert generator.sk.limit_violation(follow.qpos).max() == 0.0
    # mirrored: the follow's left elbow does what the lead's right elbow does
    from hdvr import dh
    j = dh.JOINT_NAMES.index
    assert np.allclose(follow.qpos[:, 7 + j("left_elbow_flex")], lead.qpos[:, 7 + j("right_elbow_flex")])


def test_unknown_genre(generator):
    with pytest.raises(HDVRError, match="unknown genre"):
        generator.generate("polka", 2, np.random.default_rng(0))


@pytest.mark.slow
def test_all_154_labels_produced_and_recovered(generator):
    """The issue's acceptance test: every label occurs, per-part F >= 0.95 (see scripts/bench_synth.py)."""
    from hdvr.synth.evaluate import evaluate_labeller

    report = evaluate_labeller(seconds=60, clips_per_genre=2, seed=0)
    assert report["missing_labels"] == []
    assert min(report["per_part_micro_f1"].values()) >= 0.95


def _leg_keypoints(sk, side, hinges):
    """Keypoints (25, 3) of the generator's rest pose with one leg's TURNED_OUT_JOINTS set to ``hinges``."""
    from hdvr.skeleton import ROOT_QPOS
    from hdvr.synth.choreography import REST, TURNED_OUT_JOINTS, leg_joints

    q = sk.rest_qpos()
    q[ROOT_QPOS:] = REST
    for name, v in zip(TURNED_OUT_JOINTS, hinges):
        q[ROOT_QPOS + leg_joints(side)[name]] = v
    return sk.keypoints(q)


def test_a_leg_without_turnout_stands_at_rest_and_bends_as_the_sagittal_plie(generator):
    from hdvr.synth.choreography import REST, leg_joints, turned_out_leg

    for side in ("left", "right"):
        G = leg_joints(side)
        rest = REST[[G[n] for n in ("hip_adduct", "hip_extend", "hip_rotate", "knee_flex", "ankle_plantarflex",
                                    "ankle_invert")]]
        assert np.allclose(turned_out_leg(generator.sk, side, 0.0, 0.0), rest, atol=1e-4)  # straight: rest pose
        hinges = turned_out_leg(generator.sk, side, 0.0, 0.4)
        # thigh forward 0.4, knee 0.8 more than at rest, the sole at its rest angle to the floor
        assert np.allclose(hinges, rest + [0.0, -0.4, 0.0, 0.8, -0.4, 0.0], atol=0.01), hinges


@pytest.mark.parametrize("side", ["left", "right"])
def test_a_turned_out_leg_bends_its_knee_over_its_toes(generator, side):
    """Knee and foot point the turnout out from straight ahead, the ankle stays where it stands, the sole level."""
    from hdvr.layouts import BODY25_NAMES as B
    from hdvr.synth.choreography import turned_out_leg

    sk, out = generator.sk, 1.0 if side == "left" else -1.0
    rest = _leg_keypoints(sk, side, turned_out_leg(sk, side, 0.0, 0.0))
    stand = (rest[B.index(f"{side}_ankle")] - rest[B.index(f"{side}_hip")])[:2]  # the ankle at rest, from the hip
    for turnout, thigh in ((0.8, 0.5), (1.0, 0.3), (0.4, 0.6)):
        kp = _leg_keypoints(sk, side, turned_out_leg(sk, side, turnout, thigh))
        hip, knee, ankle = (kp[B.index(f"{side}_{n}")] for n in ("hip", "knee", "ankle"))
        toe, heel = kp[B.index(f"{side}_big_toe")], kp[B.index(f"{side}_heel")]
        line = (ankle - hip) / np.linalg.norm(ankle - hip)
        d, f = (knee - hip) - ((knee - hip) @ line) * line, toe - heel  # the knee off the hip-ankle line
        assert np.degrees(np.arctan2(out * d[1], d[0])) == pytest.approx(np.degrees(turnout), abs=2.0)
        assert np.degrees(np.arctan2(out * f[1], f[0])) == pytest.approx(np.degrees(turnout), abs=8.0)
        assert np.linalg.norm((ankle - hip)[:2] - stand) < 0.005  # metres: the foot stays where it stands
        sole = kp[[B.index(f"{side}_{n}") for n in ("big_toe", "small_toe", "heel")], 2]
        assert np.ptp(sole) < 0.01


def test_a_leg_in_second_position_keeps_its_foot_out_while_it_bends(generator):
    from hdvr.layouts import BODY25_NAMES as B
    from hdvr.synth.choreography import turned_out_leg

    sk = generator.sk
    widths = []
    for thigh in (0.0, 0.3, 0.55):
        kp = _leg_keypoints(sk, "left", turned_out_leg(sk, "left", 0.8, thigh, abduction=0.25))
        widths.append((kp[B.index("left_ankle")] - kp[B.index("left_hip")])[1])
    assert widths[0] == pytest.approx(0.714 * np.sin(0.25), abs=0.02)  # leg length 0.714 m at the default height
    assert np.ptp(widths) < 0.01


def _plie_knee_angles(generator, genre, seeds=4):
    """Degrees the knees point out from the pelvis' forward direction wherever both knees bend over 0.5 rad."""
    from hdvr.layouts import BODY25_NAMES as B
    from hdvr.skeleton import ROOT_QPOS
    from hdvr.synth.choreography import JI

    angles = []
    for seed in range(seeds):
        chor = generator.generate(genre, 20, np.random.default_rng([5, seed]))
        kp, q = chor.keypoints, chor.qpos[:, ROOT_QPOS:]
        for t in np.flatnonzero((q[:, JI["left_knee_flex"]] > 0.5) & (q[:, JI["right_knee_flex"]] > 0.5)):
            across = kp[t, B.index("left_hip")] - kp[t, B.index("right_hip")]
            across = across[:2] / np.linalg.norm(across[:2])
            ahead = np.array([across[1], -across[0]])
            for side, out in (("left", 1.0), ("right", -1.0)):
                d = (kp[t, B.index(f"{side}_knee")] - kp[t, B.index(f"{side}_hip")])[:2]
                angles.append(np.degrees(np.arctan2(out * d @ across, d @ ahead)))
    return np.array(angles)


def test_ballet_bends_its_knees_turned_out_and_tango_in_parallel(generator):
    ballet, tango = _plie_knee_angles(generator, "ballet"), _plie_knee_angles(generator, "tango")
    assert ballet.size > 50 and tango.size > 50
    assert np.median(ballet) > 30.0
    assert np.median(tango) < 15.0


@pytest.mark.parametrize("genre", ["ballet", "hip_hop", "belly_dance", "flamenco"])
def test_weight_bearing_feet_do_not_slide_in_turned_out_plies(genre):
    """Dancers of several heights (bone sets), as the synthetic-data benchmark draws them: no weight-bearing foot
    slides, and a foot sliding out to second position (unweighted) stays below 1 m/s."""
    from hdvr.skeleton import Skeleton

    for seed in range(3):
        rng = np.random.default_rng([9, seed])
        gen = ChoreographyGenerator(Skeleton(height_m=float(rng.uniform(1.5, 1.9))))
        chor = gen.generate(genre, 30, rng)
        assert foot_metrics(chor.keypoints, chor.airborne, chor.fps, stance=chor.stance)["skate_max_m_s"] < 0.02
        assert foot_metrics(chor.keypoints, chor.airborne, chor.fps)["skate_max_m_s"] < 1.0
