"""docs/scale-out.md's recipes, run as they stand in a scratch folder whose ``maps/`` holds the
committed CC0 maps: the Dask one (``dask.bag`` over ``probelab.eval_csv`` on a LocalCluster of
two worker processes), written to a ``.py`` file and run as a script, as a user pastes it; and
the GNU parallel one. Their tables equal one ``probelab eval`` over all the maps."""

from __future__ import annotations

import csv
import json
import io
import os
import shutil
import subprocess
import sys

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


def test_the_dask_recipe_run_as_a_script_gives_the_cli_table(maps_folder):
    pytest.importorskip("distributed", reason="dask[distributed] is a test requirement (pyproject.toml)")
    code = recipe("dask", "python")
    assert "LocalCluster(n_workers=2" in code and 'if __name__ == "__main__":' in code
    # As a user runs it: the block pasted into a file, run by the interpreter (worker processes
    # then import that file again, which only the __main__ guard makes safe).
    script = maps_folder / "score.py"
    script.write_text(code)
    run = subprocess.run([sys.executable, str(script)], cwd=maps_folder, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    encoders = ["sh1", "sh2", "zh3_hallucinate", "geomerics"]
    assert json.dumps(encoders) in code
    paths = sorted(f"maps/{m.name}" for m in CC0_MAPS)
    theirs = subprocess.run([str(binary()), "eval", *paths, "--encoders", ",".join(encoders)], cwd=maps_folder, capture_output=True, text=True)
    assert theirs.returncode == 0, theirs.stderr
    ours = (maps_folder / "scores.csv").read_text()
    # The same header, rows and cells, as text (the timing columns aside: wall-clock).
    table = lambda text: [{k: v for k, v in r.items() if k not in ("fit_ns", "eval_ns")} for r in csv.DictReader(io.StringIO(text))]
    assert ours.split("\n", 1)[0] == theirs.stdout.split("\n", 1)[0]
    assert len(table(ours)) == len(CC0_MAPS) * len(encoders)
    assert table(ours) == table(theirs.stdout)


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
