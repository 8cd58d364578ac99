import json

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.tracking.boxes import (check_boxes_in_frame, parse_boxes, read_boxes_file, read_mot, read_start_boxes,
                                 read_tracks_json, write_mot, write_tracks_json)


def test_parse_boxes():
    assert parse_boxes("1,2,3,4; 5,6,7,8") == [(1, 2, 3, 4), (5, 6, 7, 8)]
    for bad in ("1,2,3", "a,b,c,d", "1,2,0,4", ""):
        with pytest.raises(HDVRError):
            parse_boxes(bad)


def test_box_files(tmp_path):
    (tmp_path / "b.json").write_text(json.dumps({"boxes": [[1, 2, 3, 4], [5, 6, 7, 8]]}))
    assert read_boxes_file(tmp_path / "b.json") == [(1, 2, 3, 4), (5, 6, 7, 8)]
    (tmp_path / "b.txt").write_text("10,20,30,40\n50,60,70,80\n")
    assert read_boxes_file(tmp_path / "b.txt")[1] == (50, 60, 70, 80)
    with pytest.raises(HDVRError, match="not found"):
        read_boxes_file(tmp_path / "none.json")


def test_mot_round_trip_and_first_frame_boxes(tmp_path):
    tracks = np.array([[[1, 2, 3, 4], [np.nan] * 4], [[2, 3, 4, 5], [9, 9, 9, 9]]], float)
    write_mot(tmp_path / "t.txt", tracks)
    lines = (tmp_path / "t.txt").read_text().splitlines()
    assert lines[0].startswith("1,1,1.00,2.00,3.00,4.00")
    back = read_mot(tmp_path / "t.txt")
    np.testing.assert_allclose(back, tracks)
    assert read_boxes_file(tmp_path / "t.txt") == [(1, 2, 3, 4)]


def test_tracks_json(tmp_path):
    tracks = np.array([[[1, 2, 3, 4]], [[np.nan] * 4]], float)
    write_tracks_json(tmp_path / "t.json", tracks, [("tracked",), ("absent",)], 30.0, (64, 48))
    doc = json.loads((tmp_path / "t.json").read_text())
    assert doc["dancers"][0]["boxes"] == [[1, 2, 3, 4], None]
    assert doc["image_size"] == [64, 48]


def test_tracks_json_reads_back_what_was_written_and_names_what_is_wrong(tmp_path):
    tracks = np.array([[[1, 2, 3, 4], [np.nan] * 4], [[5, 6, 7, 8], [9, 10, 11, 12]]], float)
    status = [("tracked", "absent"), ("occluded", "hidden")]
    write_tracks_json(tmp_path / "tracks.json", tracks, status, 25.0, (64, 48), extra={"swaps": []})
    for where in (tmp_path / "tracks.json", tmp_path):  # the file, or hdvr track's output folder
        back = read_tracks_json(where)
        np.testing.assert_array_equal(back.boxes, tracks)
        assert back.status == status and back.fps == 25.0 and back.image_size == (64, 48)
    doc = json.loads((tmp_path / "tracks.json").read_text())
    doc["dancers"][1]["boxes"].pop()
    (tmp_path / "short.json").write_text(json.dumps(doc))
    (tmp_path / "other.json").write_text(json.dumps({"format": "something-else"}))
    (tmp_path / "bad.json").write_text("{not json")
    for name, message in {"short.json": "dancer 1 has 1 boxes", "other.json": "expected 'hdvr-tracks-1'",
                          "bad.json": "cannot read tracks file", "missing.json": "tracks file not found"}.items():
        with pytest.raises(HDVRError, match=message):
            read_tracks_json(tmp_path / name)


def test_boxes_outside_frame():
    check_boxes_in_frame([(0, 0, 10, 10)], (100, 100))
    with pytest.raises(HDVRError, match="outside"):
        check_boxes_in_frame([(95, 95, 10, 10)], (100, 100))


def test_start_boxes_with_frames(tmp_path):
    """Start frames (0-based) per dancer, sorted by frame: MOT text starts each id at its first row, JSON 'starts'
    names them; the first-frame formats start everyone at frame 0; bad entries get a one-line error."""
    (tmp_path / "t.txt").write_text("1,1,1,2,3,4,1,-1,-1,-1\n2,1,2,2,3,4,1,-1,-1,-1\n8,2,9,9,9,9,1,-1,-1,-1\n")
    assert read_start_boxes(tmp_path / "t.txt") == [(0, (1, 2, 3, 4)), (7, (9, 9, 9, 9))]
    (tmp_path / "s.json").write_text(json.dumps({"starts": [{"frame": 40, "box": [5, 6, 7, 8]},
                                                           {"frame": 0, "box": [1, 2, 3, 4]}]}))
    assert read_start_boxes(tmp_path / "s.json") == [(0, (1, 2, 3, 4)), (40, (5, 6, 7, 8))]
    (tmp_path / "b.json").write_text(json.dumps([[1, 2, 3, 4], [5, 6, 7, 8]]))
    assert read_start_boxes(tmp_path / "b.json") == [(0, (1, 2, 3, 4)), (0, (5, 6, 7, 8))]
    for bad, message in (({"starts": [{"frame": -1, "box": [1, 2, 3, 4]}]}, "whole number"),
                         ({"starts": [{"frame": 2.5, "box": [1, 2, 3, 4]}]}, "whole number"),
                         ({"starts": [{"frame": 2}]}, "list of"),
                         ({"starts": [{"frame": 2, "box": [1, 2, 0, 4]}]}, "positive"),
                         ({"starts": []}, "no box")):
        (tmp_path / "bad.json").write_text(json.dumps(bad))
        with pytest.raises(HDVRError, match=message):
            read_start_boxes(tmp_path / "bad.json")


def test_read_corrections_and_parse_correction(tmp_path):
    """Corrections come as JSON (a list or under "corrections") or as DANCER@FRAME:x,y,w,h; a boxes file without
    them gives none where they are optional, and malformed ones are refused naming the problem."""
    from hdvr.tracking.boxes import parse_correction, read_corrections

    items = [{"frame": 30, "dancer": 0, "box": [1, 2, 3, 4]}, {"frame": 12, "dancer": 1, "box": [5, 6, 7, 8]}]
    (tmp_path / "list.json").write_text(json.dumps(items))
    (tmp_path / "doc.json").write_text(json.dumps({"starts": [{"frame": 0, "box": [1, 2, 3, 4]}],
                                                   "corrections": items}))
    expected = [(12, 1, (5.0, 6.0, 7.0, 8.0)), (30, 0, (1.0, 2.0, 3.0, 4.0))]
    assert read_corrections(tmp_path / "list.json") == expected
    assert read_corrections(tmp_path / "doc.json") == expected
    (tmp_path / "boxes.json").write_text(json.dumps([[1, 2, 3, 4]]))
    (tmp_path / "boxes.txt").write_text("1,2,3,4\n")
    assert read_corrections(tmp_path / "boxes.json", required=False) == []
    assert read_corrections(tmp_path / "boxes.txt", required=False) == []
    with pytest.raises(HDVRError, match="expected JSON"):
        read_corrections(tmp_path / "boxes.txt")
    (tmp_path / "bad.json").write_text(json.dumps({"corrections": [{"frame": -1, "dancer": 0, "box": [1, 2, 3, 4]}]}))
    with pytest.raises(HDVRError, match="frame -1 is not a whole number"):
        read_corrections(tmp_path / "bad.json")
    (tmp_path / "bad.json").write_text(json.dumps({"corrections": [{"frame": 1, "box": [1, 2, 3, 4]}]}))
    with pytest.raises(HDVRError, match="expected each correction"):
        read_corrections(tmp_path / "bad.json")
    assert parse_correction("1@120:300,80,90,260") == (120, 1, (300.0, 80.0, 90.0, 260.0))
    for text in ("1:300,80,90,260", "a@1:1,2,3,4", "1@2"):
        with pytest.raises(HDVRError, match="DANCER@FRAME"):
            parse_correction(text)


def test_read_swaps_and_parse_swap(tmp_path):
    from hdvr.tracking.boxes import parse_swap, read_swaps

    (tmp_path / "fix.json").write_text(json.dumps({"swaps": [{"frame": 40, "dancers": [2, 0]},
                                                             {"frame": 10, "dancers": [0, 1]}]}))
    assert read_swaps(tmp_path / "fix.json") == [(10, 0, 1), (40, 2, 0)]
    (tmp_path / "none.json").write_text(json.dumps({"corrections": []}))
    (tmp_path / "boxes.txt").write_text("1,2,3,4\n")
    assert read_swaps(tmp_path / "none.json") == [] and read_swaps(tmp_path / "boxes.txt") == []
    (tmp_path / "bad.json").write_text(json.dumps({"swaps": [{"frame": 4, "dancers": [1]}]}))
    with pytest.raises(HDVRError, match="expected each swap"):
        read_swaps(tmp_path / "bad.json")
    assert parse_swap("0,1@240") == (240, 0, 1)
    for text in ("0,1", "0@3", "a,b@3", "0,1,2@3"):
        with pytest.raises(HDVRError, match="A,B@FRAME"):
            parse_swap(text)
    with pytest.raises(HDVRError, match="counted from 0"):
        parse_swap("0,-1@3")


def test_a_correction_may_give_a_point_instead_of_a_box(tmp_path):
    from hdvr.tracking.boxes import parse_correction, read_corrections

    assert parse_correction("1@120:300,80") == (120, 1, (300.0, 80.0))
    (tmp_path / "fix.json").write_text(json.dumps({"corrections": [{"frame": 5, "dancer": 0, "point": [10, 20]}]}))
    assert read_corrections(tmp_path / "fix.json") == [(5, 0, (10.0, 20.0))]
    (tmp_path / "both.json").write_text(json.dumps({"corrections": [{"frame": 5, "dancer": 0, "point": [10, 20],
                                                                     "box": [1, 2, 3, 4]}]}))
    assert read_corrections(tmp_path / "both.json") == [(5, 0, (1.0, 2.0, 3.0, 4.0))]  # as tracks.json lists a
    # point's correction: with the box found there, which is what the run used
    (tmp_path / "unfound.json").write_text(json.dumps({"corrections": [{"frame": 5, "dancer": 0, "point": [10, 20],
                                                                        "box": None}]}))
    assert read_corrections(tmp_path / "unfound.json") == [(5, 0, (10.0, 20.0))]  # stopped before it was found
    (tmp_path / "neither.json").write_text(json.dumps({"corrections": [{"frame": 5, "dancer": 0}]}))
    with pytest.raises(HDVRError, match="expected each correction"):
        read_corrections(tmp_path / "neither.json")
    (tmp_path / "bad.json").write_text(json.dumps({"corrections": [{"frame": 5, "dancer": 0, "point": [10]}]}))
    with pytest.raises(HDVRError, match="expected a point x,y"):
        read_corrections(tmp_path / "bad.json")
