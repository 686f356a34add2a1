"""docs/scale-out.md's recipes, run as they stand in a scratch folder whose ``maps/`` holds the
committed CC0 maps: the Dask one (``dask.bag`` over ``probelab.eval`` on a LocalCluster of two
worker processes) and the GNU parallel one; their rows equal one ``probelab eval`` over all
the maps."""

from __future__ import annotations

import csv
import io
import os
import shutil
import subprocess

import pytest

import probelab
from conftest import CC0_MAPS, REPO, assert_rows_agree, binary, cli, cli_rows

DOC = REPO / "docs" / "scale-out.md"


def recipe(name: str, fence: str) -> str:
    """The code block between ``<!-- recipe:NAME -->`` and ``<!-- /recipe -->`` of the page."""
    text = DOC.read_text()
    start = text.index(f"<!-- recipe:{name} -->")
    block = text[start : text.index("<!-- /recipe -->", start)]
    return block.split(f"```{fence}\n", 1)[1].rsplit("```", 1)[0]


@pytest.fixture
def maps_folder(tmp_path, monkeypatch):
    """A scratch folder with ``maps/`` holding every committed CC0 map, as the working directory."""
    (tmp_path / "maps").mkdir()
    for m in CC0_MAPS:
        (tmp_path / "maps" / m.name).symlink_to(m)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def by_key(rows):
    return sorted(rows, key=lambda r: (r["map"], r["encoder"]))


def test_the_dask_recipe_on_a_local_cluster_of_two_workers_gives_the_cli_rows(maps_folder):
    pytest.importorskip("distributed", reason="dask[distributed] is a test requirement (pyproject.toml)")
    code = recipe("dask", "python")
    assert "LocalCluster(n_workers=2" in code
    scope: dict = {}
    exec(compile(code, str(DOC), "exec"), scope)
    rows, encoders = scope["rows"], scope["encoders"]
    paths = [str(maps_folder / "maps" / m.name) for m in CC0_MAPS]
    theirs = cli_rows("--no-timing", "eval", *paths, "--encoders", ",".join(encoders), "--format", "json")
    assert len(rows) == len(theirs) == len(CC0_MAPS) * len(encoders)
    # Every number within 1e-12 relative, text equal (the timing columns aside: wall-clock).
    assert_rows_agree(by_key(rows), by_key(theirs), skip=())
    with open("scores.csv", newline="") as f:
        assert [r["rmse"] for r in csv.DictReader(f)] == [str(r["rmse"]) for r in rows]


def test_the_gnu_parallel_recipe_gives_the_cli_rows(maps_folder):
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed (Debian package parallel)")
    env = dict(os.environ, PATH=f"{binary().parent}{os.pathsep}{os.environ['PATH']}")
    run = subprocess.run(["bash", "-euo", "pipefail", "-c", recipe("parallel-eval", "sh")], env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    paths = sorted(str(maps_folder / "maps" / m.name) for m in CC0_MAPS)
    one = cli("--no-timing", "eval", *paths, "--encoders", "sh1,sh2,zh3_hallucinate")
    assert one.returncode == 0, one.stderr
    assert (maps_folder / "scores.csv").read_text() == one.stdout
