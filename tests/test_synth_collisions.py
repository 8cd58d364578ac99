import numpy as np

from hdvr.skeleton import Skeleton
from hdvr.synth.choreography import ChoreographyGenerator
from hdvr.synth.groundtruth import clip_spec, generate_motion
from hdvr.synth.scene import collision_model, inter_dancer_penetration, separate_dancers


def test_penetration_is_measured_between_dancers_only():
    """Two dancers on the same spot interpenetrate deeply; apart they do not; a dancer's own geoms never count."""
    sk = Skeleton()
    q = sk.rest_qpos()
    model = collision_model([1.7, 1.7])
    same = inter_dancer_penetration(model, np.stack([q[None], q[None]]))
    assert same[0, 1] > 0.05 and same[0, 0] == 0.0
    far = q.copy()
    far[0] += 1.0
    assert inter_dancer_penetration(model, np.stack([q[None], far[None]])).max() == 0.0


def test_separation_moves_dancers_apart_without_changing_their_motion():
    gen = ChoreographyGenerator(Skeleton(height_m=1.7))
    a = gen.generate("swing", 4, np.random.default_rng(0), start_xy=(0.0, 0.0))
    b = gen.generate("swing", 4, np.random.default_rng(1), start_xy=(0.05, 0.0))  # on top of each other
    hinges = b.qpos[:, 7:].copy()
    pen = separate_dancers([a, b], [1.7, 1.7])
    assert pen.max() <= 0.002
    assert np.array_equal(b.qpos[:, 7:], hinges)
    assert np.linalg.norm(b.qpos[0, :2] - a.qpos[0, :2]) > 0.15  # started 0.05 m apart


def test_generated_couples_do_not_pass_through_each_other():
    spec = clip_spec(4, 3, ("swing",), (2, 2), 8.0)  # a partner dance: one couple
    dancers, heights = generate_motion(spec)
    pen = inter_dancer_penetration(collision_model(list(heights)), np.stack([d.qpos for d in dancers]))
    assert pen.max() <= 0.01
