"""Atomic writes (hdvr.io.atomic): the file appears whole or not at all, with a plain open()'s permissions."""

import os
import stat

import numpy as np
import pytest

from hdvr.io.atomic import atomic_path, save_npz_atomic, write_text_atomic


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def _plain_open_mode(tmp_path) -> int:
    reference = tmp_path / "reference.txt"
    reference.write_text("x")
    return _mode(reference)


def test_a_new_file_gets_the_permissions_of_a_plain_open(tmp_path):
    old = os.umask(0o022)
    try:
        write_text_atomic(tmp_path / "out.json", "{}")
        assert _mode(tmp_path / "out.json") == _plain_open_mode(tmp_path) == 0o644
        os.umask(0o077)
        save_npz_atomic(tmp_path / "private.npz", a=np.arange(3))
        assert _mode(tmp_path / "private.npz") == 0o600
    finally:
        os.umask(old)


def test_a_replaced_file_keeps_its_permissions(tmp_path):
    target = tmp_path / "tracks.mot.txt"
    target.write_text("old")
    os.chmod(target, 0o640)
    write_text_atomic(target, "new")
    assert target.read_text() == "new"
    assert _mode(target) == 0o640


def test_an_error_mid_write_leaves_the_old_file_and_no_temporary_one(tmp_path):
    target = tmp_path / "dancer_0.npz"
    save_npz_atomic(target, keypoints=np.ones((2, 25, 3)))
    with pytest.raises(RuntimeError):
        with atomic_path(target, suffix=".npz") as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("interrupted")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dancer_0.npz"]
    with np.load(target) as data:
        assert data["keypoints"].shape == (2, 25, 3)


def test_npz_round_trip_and_folder_created(tmp_path):
    target = tmp_path / "new" / "folder" / "result.npz"
    save_npz_atomic(target, compress=False, x=np.eye(2))
    with np.load(target) as data:
        np.testing.assert_array_equal(data["x"], np.eye(2))
