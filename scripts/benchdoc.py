"""What the benchmark scripts share when they write docs/benchmarks.md: the CPU's name and section replacement."""

from __future__ import annotations

import platform
from pathlib import Path

from hdvr.io.atomic import write_text_atomic


def cpu_name() -> str:
    """The CPU model from /proc/cpuinfo (Linux), else what platform reports."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def write_section(path: Path, heading: str, text: str) -> None:
    """Replace the ``heading`` section (up to the next ``## `` heading) of a markdown file, or append it."""
    old = path.read_text() if path.is_file() else "# Benchmarks\n\n"
    if heading in old:
        head, rest = old.split(heading, 1)
        tail = rest.split("\n## ", 1)
        new = head + text.rstrip("\n") + "\n\n" + ("## " + tail[1] if len(tail) > 1 else "")
    else:
        new = old.rstrip("\n") + "\n\n" + text
    write_text_atomic(path, new.rstrip("\n") + "\n")
