import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.layouts import (BODY25, BODY25_NAMES, COCO17, COCO17_NAMES, EVAL_JOINTS, H36M17, convert,
                          eval_indices, guess_layout)


def test_body25_is_openpose_order():
    assert len(BODY25_NAMES) == 25
    assert BODY25_NAMES[1] == "neck" and BODY25_NAMES[8] == "mid_hip" and BODY25_NAMES[24] == "right_heel"


def test_coco_to_body25_derives_neck_and_midhip():
    rng = np.random.default_rng(0)
    coco = np.concatenate([rng.uniform(0, 100, (4, 17, 2)), np.ones((4, 17, 1))], axis=-1)
    body = convert(coco, COCO17, BODY25, has_confidence=True)
    ls, rs = COCO17.index("left_shoulder"), COCO17.index("right_shoulder")
    np.testing.assert_allclose(body[:, BODY25.index("neck"), :2], (coco[:, ls, :2] + coco[:, rs, :2]) / 2)
    assert np.isnan(body[:, BODY25.index("left_heel"), :2]).all()
    assert (body[:, BODY25.index("left_heel"), 2] == 0).all()
    # a missing source makes the derived point missing
    coco[0, ls, 2] = 0
    body = convert(coco, COCO17, BODY25, has_confidence=True)
    assert body[0, BODY25.index("neck"), 2] == 0 and np.isnan(body[0, BODY25.index("neck"), 0])
    back = convert(body, BODY25, COCO17, has_confidence=True)
    np.testing.assert_allclose(back[1:], coco[1:])


def test_h36m_round_trip_of_shared_joints():
    pts = np.random.default_rng(1).normal(size=(3, 25, 3))
    h36 = convert(pts, BODY25, H36M17, has_confidence=False)
    np.testing.assert_allclose(h36[:, H36M17.index("spine")],
                               (pts[:, BODY25.index("mid_hip")] + pts[:, BODY25.index("neck")]) / 2)
    back = convert(h36, H36M17, BODY25, has_confidence=False)
    idx = eval_indices(BODY25)
    np.testing.assert_allclose(back[:, idx], pts[:, idx])


def test_guess_layout_and_errors():
    assert guess_layout(COCO17_NAMES) is COCO17
    with pytest.raises(HDVRError, match="unknown joint names"):
        guess_layout(["nose", "tail"])
    with pytest.raises(HDVRError, match="unknown joint name"):
        BODY25.index("tail")
    with pytest.raises(HDVRError, match="expected keypoints shaped"):
        convert(np.zeros((3, 10, 3)), COCO17, BODY25, has_confidence=True)
    assert set(EVAL_JOINTS) <= set(BODY25_NAMES)
