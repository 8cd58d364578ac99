"""The process memory setting for long video jobs."""

import sys

import pytest

from hdvr.memory import keep_large_blocks_out_of_heap


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc mallopt is Linux-only")
def test_mmap_threshold_is_fixed_once_and_idempotent():
    assert keep_large_blocks_out_of_heap() is True
    assert keep_large_blocks_out_of_heap() is True
