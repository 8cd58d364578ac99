import json

import pytest

from hdvr.errors import HDVRError
from hdvr.movements.taxonomy import TAXONOMY_PATH, load_taxonomy

EXPECTED = {"head": 7, "neck": 5, "left_shoulder": 5, "right_shoulder": 5, "left_upper_arm": 11, "right_upper_arm": 11,
            "left_lower_arm": 11, "right_lower_arm": 11, "torso": 10, "hips": 10, "left_upper_leg": 15,
            "right_upper_leg": 15, "left_lower_leg": 15, "right_lower_leg": 15, "left_foot": 4, "right_foot": 4}


def test_counts_per_part_and_total():
    tax = load_taxonomy()
    assert {p.name: len(p.labels) for p in tax.parts} == EXPECTED
    assert len(tax.labels) == 154
    assert [lab.id for lab in tax.labels] == list(range(154))
    assert len({lab.key for lab in tax.labels}) == 154


def test_paper_examples_present():
    tax = load_taxonomy()
    names = {lab.name for lab in tax.labels} | {lab.paper_name for lab in tax.labels if lab.paper_name}
    for example in ("Head Turning Up", "Head Turning Down", "Head Turning Left", "Head Turning Right", "Head Circling",
                    "Neck Moving Left", "Neck Moving Right", "Neck Circling", "Head Keeping Still", "Unknown",
                    "Left Shoulder Moving Upward", "Left Shoulder Moving Downward", "Left Shoulder Circling",
                    "Left Arm Moving Upward", "Left Arm Moving Downward", "Left Arm Moving Left", "Torso Bending",
                    "Torso Unbending", "Torso Turning Left", "Torso Turning Right", "Torso Swing", "Torso Somersault",
                    "Hips Waving", "Hips Figure 8", "Hips Circling", "Hip Moving Up", "Hip Moving Down",
                    "Hips Keeping Still", "Left Leg Moving Upward", "Left Leg Moving Downward", "Left Leg Moving Left",
                    "Left Foot Extension", "Left Foot Flexion", "Left Foot Relaxed"):
        assert example in names, example


def test_every_label_has_an_operational_definition():
    tax = load_taxonomy()
    for lab in tax.labels:
        assert lab.definition
        if lab.kind == "direction":
            part = tax.part(lab.part)
            assert lab.component in part.motion_components and lab.sign in (-1, 1), lab.key
        if lab.kind == "pattern":
            assert set(lab.pattern.split("|")) <= {"circle", "oscillation", "figure8"}
    for part in tax.parts:
        assert part.label("unknown").name == "Unknown"


def test_bad_taxonomy_files(tmp_path):
    with pytest.raises(HDVRError, match="not found"):
        load_taxonomy(str(tmp_path / "missing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(HDVRError, match="not valid JSON"):
        load_taxonomy(str(bad))
    doc = json.loads(TAXONOMY_PATH.read_text())
    doc["parts"] = doc["parts"][:-1]
    short = tmp_path / "short.json"
    short.write_text(json.dumps(doc))
    with pytest.raises(HDVRError, match="expected 16 / 154"):
        load_taxonomy(str(short))
