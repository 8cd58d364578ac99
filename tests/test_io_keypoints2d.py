import json

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import (Keypoints2D, load_keypoints2d, read_coco_json, read_openpose_folder,
                                 save_keypoints2d)
from hdvr.layouts import BODY25_NAMES, COCO17_NAMES


def _random_kp(t=5, j=25, seed=0):
    rng = np.random.default_rng(seed)
    kp = np.concatenate([rng.uniform(0, 640, (t, j, 2)), rng.uniform(0.1, 1, (t, j, 1))], -1).astype(np.float32)
    kp[1, 3] = [np.nan, np.nan, 0.0]
    return kp


def test_npz_round_trip(tmp_path):
    kp = Keypoints2D(_random_kp(), BODY25_NAMES, 30.0, (640, 480))
    save_keypoints2d(tmp_path / "a.npz", kp)
    back = load_keypoints2d(tmp_path / "a.npz")
    np.testing.assert_array_equal(back.keypoints, kp.keypoints)
    assert back.joint_names == BODY25_NAMES and back.fps == 30.0 and back.image_size == (640, 480)
    assert not list(tmp_path.glob(".a.npz*")), "no temporary file left behind"


def test_missing_keypoint_normalised():
    kp = _random_kp()
    kp[2, 4, :2] = np.nan  # NaN coordinates with positive confidence -> missing
    k = Keypoints2D(kp, BODY25_NAMES, 30, (640, 480))
    assert k.keypoints[2, 4, 2] == 0


@pytest.mark.parametrize("bad, message", [
    (dict(keypoints=np.zeros((5, 25))), "shaped"),
    (dict(joint_names=BODY25_NAMES[:24]), "joint names"),
    (dict(fps=0.0), "fps"),
])
def test_bad_input_is_one_line_error(bad, message):
    args = dict(keypoints=_random_kp(), joint_names=BODY25_NAMES, fps=30.0, image_size=(640, 480))
    args.update(bad)
    with pytest.raises(HDVRError, match=message):
        Keypoints2D(**args)


def test_load_errors(tmp_path):
    with pytest.raises(HDVRError, match="not found"):
        load_keypoints2d(tmp_path / "missing.npz")
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(HDVRError, match="not a valid NPZ"):
        load_keypoints2d(tmp_path / "bad.npz")
    np.savez(tmp_path / "nokeys.npz", keypoints=np.zeros((1, 25, 3)))
    with pytest.raises(HDVRError, match="lacks keys"):
        load_keypoints2d(tmp_path / "nokeys.npz")
    kp = np.full((4, 25, 3), np.nan, dtype=np.float32)
    save_keypoints2d(tmp_path / "nan.npz", Keypoints2D(kp, BODY25_NAMES, 30, (640, 480)))
    with pytest.raises(HDVRError, match="no visible keypoint"):
        load_keypoints2d(tmp_path / "nan.npz")


def test_openpose_folder(tmp_path):
    kp = _random_kp(t=3)
    for t in range(3):
        flat = np.nan_to_num(kp[t]).reshape(-1).tolist()
        doc = {"version": 1.3, "people": [{"pose_keypoints_2d": flat}] if t != 1 else []}
        (tmp_path / f"clip_{t:012d}_keypoints.json").write_text(json.dumps(doc))
    k = read_openpose_folder(tmp_path, fps=25, image_size=(640, 480))
    assert k.num_frames == 3 and k.joint_names == BODY25_NAMES
    assert (k.keypoints[1, :, 2] == 0).all()
    np.testing.assert_allclose(k.keypoints[0, :, :2], kp[0, :, :2], rtol=1e-6)


def test_coco_json(tmp_path):
    kp = _random_kp(t=2, j=17)
    doc = {"images": [{"id": 10 + t, "width": 640, "height": 480} for t in range(2)],
           "annotations": [{"image_id": 10 + t, "keypoints": np.column_stack(
               [np.nan_to_num(kp[t, :, :2]), np.full(17, 2.0)]).reshape(-1).tolist()} for t in range(2)]}
    (tmp_path / "c.json").write_text(json.dumps(doc))
    k = read_coco_json(tmp_path / "c.json", fps=30)
    assert k.joint_names == BODY25_NAMES and k.image_size == (640, 480)
    i = BODY25_NAMES.index("left_wrist")
    np.testing.assert_allclose(k.keypoints[0, i, :2], kp[0, COCO17_NAMES.index("left_wrist"), :2], rtol=1e-6)
