import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.io.result3d import Result3D, load_result3d, save_result3d
from hdvr.skeleton import Skeleton


def test_round_trip(tmp_path):
    sk = Skeleton()
    q = np.stack([sk.rest_qpos()] * 4)
    r = Result3D(keypoints3d=sk.keypoints(q), qpos=q, focal=1500.0, principal_point=(960, 540),
                 bone_lengths=sk.bone_lengths, reprojection_error_px=np.arange(4.0), fps=30.0,
                 meta={"seeds": 2})
    save_result3d(tmp_path / "r.npz", r)
    back = load_result3d(tmp_path / "r.npz")
    np.testing.assert_array_equal(back.keypoints3d, r.keypoints3d)
    np.testing.assert_array_equal(back.qpos, r.qpos)
    assert back.focal.shape == (4,) and back.principal_point.shape == (4, 2)
    assert back.meta == {"seeds": 2} and back.fps == 30.0


def test_shape_errors():
    with pytest.raises(HDVRError, match="keypoints3d"):
        Result3D(np.zeros((4, 17, 3)), np.zeros((4, 41)), 1.0, (0, 0), np.ones(9), np.zeros(4))
    with pytest.raises(HDVRError, match="qpos"):
        Result3D(np.zeros((4, 25, 3)), np.zeros((3, 41)), 1.0, (0, 0), np.ones(9), np.zeros(4))
