"""scripts/bench_fit_views.py on a tiny stand-in for the mocap: synthetic dancers as 'salsa' and 'indian' takes."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "bench_fit_views.py"


def test_fits_views_per_style_and_compares_runs(tmp_path, mocap_standin):
    gt = mocap_standin(12)
    out, again = tmp_path / "a.json", tmp_path / "b.json"
    base = [sys.executable, str(SCRIPT), "--gt-npz", str(gt), "--cameras-salsa", "1", "--cameras-indian", "1",
            "--workers", "1"]
    run = subprocess.run(base + ["--out", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    report = json.loads(out.read_text())
    assert set(report["summary"]) == {"salsa", "indian"} and len(report["views"]) == 2
    assert all(np.isfinite(v["p_mpjpe_mm"]) and v["camera"] == 100 for v in report["views"])
    run = subprocess.run(base + ["--pose-prior", "partner", "--compare", str(out), "--out", str(again)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    paired = json.loads(again.read_text())["paired"]
    assert paired["salsa"]["views"] == 1 and "better on" in run.stdout
    run = subprocess.run(base + ["--pose-prior", str(tmp_path / "none.npz")], capture_output=True, text=True)
    assert run.returncode == 2 and "not found" in run.stderr and "Traceback" not in run.stderr
