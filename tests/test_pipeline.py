"""The whole hierarchy wired together: synthetic clip -> hdvr run (OpenPose-JSON poses) -> 3D, BVH, movements,
genre."""

import json

import numpy as np
import pytest

from hdvr.cli import main
from hdvr.io.bvh import read_bvh
from hdvr.io.result3d import load_result3d
from hdvr.movements.labeller import Labels
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.pipeline import active_movements
from hdvr.synth.groundtruth import clip_spec, make_clip


@pytest.fixture(scope="module")
def synthetic_clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("synthetic")
    spec = clip_spec(0, 11, ("ballet",), (1, 1), 2.0)
    make_clip(out, spec, render=True)
    return out / spec.name


def test_run_on_a_synthetic_clip_with_precomputed_poses(synthetic_clip, tmp_path, capsys):
    gt = np.load(synthetic_clip / "gt.npz")
    poses = tmp_path / "openpose"
    poses.mkdir()
    for t in range(gt["keypoints2d"].shape[1]):
        kp = np.concatenate([gt["keypoints2d"][0, t], (gt["visibility"][0, t] > 0)[:, None]], axis=1)
        doc = {"people": [{"pose_keypoints_2d": kp.reshape(-1).tolist()}]}
        (poses / f"clip_{t:012d}_keypoints.json").write_text(json.dumps(doc))
    box = gt["boxes"][0, 0]
    out = tmp_path / "analysis"
    assert main(["run", str(synthetic_clip / "video.mp4"), "--out", str(out), "--boxes",
                 ",".join(f"{v:.1f}" for v in box), "--detector", "openpose", "--openpose-json", str(poses),
                 "--detect-every", "1"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    dancer = summary["dancers"][0]
    assert dancer["skipped"] is None and dancer["pose_coverage"] > 0.9
    result = load_result3d(out / "dancer_0.result3d.npz")
    assert result.num_frames == gt["keypoints2d"].shape[1]
    assert np.nanmedian(result.reprojection_error_px) < 10
    assert read_bvh(out / "dancer_0.bvh").num_frames == result.num_frames
    labels = json.loads((out / "dancer_0.labels.json").read_text())
    assert {s["part"] for s in labels["segments"]} >= {"head", "torso", "left_foot"}
    assert (out / "dancer_0.score.png").stat().st_size > 10_000
    genres = set(summary["genre"]["probabilities"])  # the shipped genre recogniser ran (hdvr.recognition.genre)
    assert summary["genre"]["available"] and summary["genre"]["dancers"] == 1 and len(genres) == 9
    assert summary["genre"]["top"] in genres and sum(summary["genre"]["probabilities"].values()) == \
        pytest.approx(1.0, abs=1e-3)
    assert dancer["genre"]["probabilities"] == pytest.approx(summary["genre"]["probabilities"], abs=1e-3)
    assert dancer["active_movements"] == [list(m) for m in active_movements(
        Labels(_label_ids(labels, gt["keypoints2d"].shape[1]), 30.0, load_taxonomy()))]
    printed = capsys.readouterr().out
    assert "dancer 0: pose on" in printed and "genre of the video: " in printed
    assert "most frequent movements: " in printed


def _label_ids(labels_json: dict, frames: int) -> np.ndarray:
    """(T, 16) global label ids from a labels.json's segments."""
    taxonomy = load_taxonomy()
    ids = np.full((frames, len(taxonomy.parts)), -1)
    for seg in labels_json["segments"]:
        ids[seg["start"]:seg["end"], taxonomy.part(seg["part"]).index] = seg["label_id"]
    assert (ids >= 0).all()
    return ids


def test_active_movements_rank_what_the_dancer_does_over_keeping_still():
    """Keeping still, a relaxed foot and unknown never count; the rest ranks by frames over all parts, with the
    fraction of the clip each covers."""
    taxonomy = load_taxonomy()
    part = {p.name: p for p in taxonomy.parts}
    gid = {lab.key: i for i, lab in enumerate(taxonomy.labels)}

    def label(part_name: str, kind: str, **attrs) -> int:
        lab = part[part_name].find(kind, **attrs) if attrs else part[part_name].label(kind)
        return gid[lab.key]

    arm = next(p.name for p in taxonomy.parts if any(lab.kind == "direction" for lab in p.labels))
    arm_move = gid[next(lab for lab in part[arm].labels if lab.kind == "direction").key]
    ids = np.empty((10, len(taxonomy.parts)), dtype=np.int16)
    for p in taxonomy.parts:
        ids[:, p.index] = label(p.name, "state", condition="relaxed") if p.name.endswith("foot") else \
            label(p.name, "still")
    ids[:6, part[arm].index] = arm_move
    ids[:, part["left_foot"].index] = label("left_foot", "state", condition="relaxed")
    ids[:3, part["right_foot"].index] = label("right_foot", "state", condition="extension")
    ids[3:, part["right_foot"].index] = label("right_foot", "unknown")
    top = active_movements(Labels(ids, 30.0, taxonomy))
    assert top == [(taxonomy.labels[arm_move].name, 0.6), ("Right Foot Extension", 0.3)]
    ids[:] = label("head", "still")
    assert active_movements(Labels(ids, 30.0, taxonomy)) == []


@pytest.mark.slow
def test_full_demo(tmp_path):
    assert main(["demo", "--out", str(tmp_path), "--size", "96x72", "--seconds-per-joint", "0.1"]) == 0
    scores = json.loads((tmp_path / "demo_scores.json").read_text())
    assert scores["tracking"]["IDSW"] == 0 and len(scores["dancers"]) == 2
    assert scores["genre"]["available"] and scores["genre"]["truth"] == "hip_hop"


def test_run_takes_hdvr_track_s_start_boxes_and_corrections(tmp_path, capsys):
    """``hdvr run`` passes start and correction options to the tracking stage as ``hdvr track`` does: a correction
    of a dancer that does not exist is refused before any work, with one line naming it."""
    from hdvr.tracking.testclips import default_crossing_specs, render_clip

    path = tmp_path / "two.mp4"
    truth = render_clip(path, frames=6, size=(320, 240), specs=default_crossing_specs(num_figures=2, seed=1,
                                                                                     size=(320, 240)))
    boxes = ";".join(",".join(f"{v:g}" for v in b) for b in truth.boxes[0])
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--boxes", boxes, "--correct",
                 "2@3:10,10,40,80", "--no-genre"]) == 2
    err = capsys.readouterr().err
    assert "correction at frame 3: no dancer 2" in err and len(err.strip().splitlines()) == 1
    (tmp_path / "starts.json").write_text(json.dumps({"starts": [{"frame": 0, "box": truth.boxes[0, 0].tolist()}],
                                                      "corrections": [{"frame": 9, "dancer": 0,
                                                                       "box": truth.boxes[0, 0].tolist()}]}))
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--boxes-file", str(tmp_path / "starts.json"),
                 "--no-genre"]) == 2
    assert "the video has 6 frames" in capsys.readouterr().err
