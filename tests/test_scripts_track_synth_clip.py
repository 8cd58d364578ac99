"""scripts/track_synth_clip.py: the per-frame table and its bad-input error (tracking itself: bench_track's)."""

import numpy as np
import pytest
from script_loader import load_script


def test_frame_table_names_the_tracked_dancer_on_each_truth():
    """Dancer 0's truth is covered by its own box, dancer 1's by dancer 0's box (its own is elsewhere), dancer 2
    is absent on the second frame."""
    script = load_script("track_synth_clip")
    truth = np.array([[[0, 0, 10, 20], [100, 0, 10, 20], [200, 0, 10, 20]],
                      [[0, 0, 10, 20], [100, 0, 10, 20], [np.nan] * 4]], float)
    tracked = np.array([[[0, 0, 10, 20], [100, 0, 10, 20], [200, 0, 10, 20]],
                        [[100, 0, 10, 20], [300, 0, 10, 20], [np.nan] * 4]], float)
    seen = np.array([[1.0, 0.5, 0.2], [1.0, 0.9, 0.0]])
    lines = script.frame_table(truth, tracked, seen)
    assert lines[0] == "   0  0>0 1.00 v1.0  1>1 1.00 v0.5  2>2 1.00 v0.2"
    assert lines[1] == "   1  0>. 0.00 v1.0  1>0 0.00 v0.9  2>- ---- v0.0"
    assert script.frame_table(truth, tracked, seen, every=2) == lines[:1]


def test_a_folder_that_is_not_a_clip_is_a_one_line_error(tmp_path):
    with pytest.raises(SystemExit, match="is not an hdvr synth clip folder"):
        load_script("track_synth_clip").main([str(tmp_path), str(tmp_path / "out")])
