"""hdvr.progress: tqdm bars with HDVR's defaults, off by HDVR_NO_PROGRESS=1 or by the caller."""

from hdvr.progress import progress


def test_a_bar_can_be_turned_off_by_the_caller_or_the_environment(monkeypatch):
    for env in ("1", ""):
        monkeypatch.setenv("HDVR_NO_PROGRESS", env)
        for asked in (True, False):
            bar = progress(total=3, desc="x", disable=asked)
            assert bar.disable == (asked or env == "1")
            bar.update(3)
            bar.close()
    assert list(progress(range(3))) == [0, 1, 2]
