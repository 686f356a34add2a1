"""The notebook example runs headless and draws its figure."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import REPO

EXAMPLE = REPO / "bindings" / "python" / "examples" / "compare_encoders.py"


def test_example_runs_headless_and_writes_its_figure(tmp_path: Path):
    out = tmp_path / "error_spheres.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    run = subprocess.run([sys.executable, str(EXAMPLE), "--out", str(out)], cwd=REPO, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert out.is_file() and out.stat().st_size > 20_000
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # It prints each encoder's score, from eval.
    for enc in ("sh1", "sh2", "zh3_hallucinate"):
        assert enc in run.stdout
