"""What the tests share: the repository, its committed CC0 maps, and the ``probelab`` binary
the package is compared with (``PROBELAB_BIN``, else ``target/release/probelab``)."""

from __future__ import annotations

import json
import math
import os
import subprocess
from pathlib import Path
from typing import Any, Dict, List

import pytest

import probelab

REPO = Path(__file__).resolve().parents[3]
ENVMAPS = REPO / "envmaps"
#: The committed CC0 maps (Poly Haven, 256x128): every one the Dask test scores.
CC0_MAPS = sorted(p for p in ENVMAPS.glob("*_256x128.exr") if p.name.startswith(("blender_", "pmndrs_")))
#: The agreement bound the package promises against the command line (relative).
RTOL = 1e-12


def binary() -> Path:
    """The ``probelab`` binary to compare with."""
    path = Path(os.environ.get("PROBELAB_BIN", REPO / "target" / "release" / "probelab"))
    if not path.is_file():
        pytest.fail(f"no probelab binary at {path}: run `cargo build --release` or set PROBELAB_BIN", pytrace=False)
    return path


def cli(*args: str) -> subprocess.CompletedProcess:
    """Runs ``probelab ARGS`` in the repository (its search path: envmaps/, then PROBELAB_ENVMAPS)."""
    return subprocess.run([str(binary()), *args], cwd=REPO, capture_output=True, text=True)


def cli_json(*args: str) -> Any:
    """The JSON ``probelab ARGS`` prints; fails the test with its stderr if it fails."""
    out = cli(*args)
    assert out.returncode == 0, f"probelab {' '.join(args)}: {out.stderr}"
    return json.loads(out.stdout)


def cli_rows(*args: str) -> List[Dict[str, Any]]:
    """The rows of the ``probelab eval ARGS --format json`` document (``probelab.eval/1``, docs/json.md)."""
    doc = cli_json(*args)
    assert doc["schema"] == "probelab.eval/1", doc.get("schema")
    return doc["rows"]


def cli_error(*args: str) -> str:
    """The message ``probelab ARGS`` fails with (stderr without ``error: ``); exit code 2."""
    out = cli(*args)
    assert out.returncode == 2, f"probelab {' '.join(args)} exited {out.returncode}: {out.stdout}{out.stderr}"
    assert out.stderr.startswith("error: "), out.stderr
    return out.stderr[len("error: ") :].rstrip("\n")


def assert_rows_agree(ours: List[Dict[str, Any]], theirs: List[Dict[str, Any]], skip=("map",)) -> int:
    """Row by row, column by column: text equal, numbers within RTOL relative (timing columns and
    ``skip`` aside). Returns how many numbers were compared."""
    assert len(ours) == len(theirs) > 0
    compared = 0
    for a, b in zip(ours, theirs):
        assert list(a) == list(probelab.COLUMNS)
        for col in probelab.COLUMNS:
            if col in ("fit_ns", "eval_ns") or col in skip:
                continue
            x, y = a[col], b[col]
            if isinstance(y, (int, float)) and not isinstance(y, bool):
                assert isinstance(x, (int, float)), (col, x, y)
                assert math.isclose(x, y, rel_tol=RTOL, abs_tol=0.0), f"{a['map']} {a['encoder']} {col}: {x} vs {y}"
                compared += 1
            else:
                assert x == y, f"{a['map']} {a['encoder']} {col}: {x!r} vs {y!r}"
    return compared


@pytest.fixture(autouse=True, scope="session")
def no_timing():
    """Timing columns are wall-clock and never compared; the pass is skipped to save time."""
    probelab.set_timing(False)
    yield
    probelab.set_timing(True)


def pytest_sessionstart(session):
    """Refuses to test an installed package older than the sources it is built from (a stale
    wheel would test old code): reinstall with ``pip install ./bindings/python``."""
    installed = Path(probelab._core.__file__).stat().st_mtime
    sources = [REPO / "src", REPO / "bindings" / "python" / "src", REPO / "bindings" / "python" / "python"]
    newer = [p for d in sources if d.is_dir() for p in d.rglob("*") if p.suffix in (".rs", ".py") and p.stat().st_mtime > installed]
    if newer:
        pytest.exit(
            f"the installed probelab package ({probelab._core.__file__}) is older than {newer[0]}: "
            "reinstall it (pip install ./bindings/python)",
            returncode=3,
        )
