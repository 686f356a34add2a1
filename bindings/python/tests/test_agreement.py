"""The package's numbers are the command line's: ``eval`` rows from a path and from an array
equal ``probelab eval --format json`` to 1e-12 relative, ``fit`` equals ``probelab fit``, and
``encoders`` equals ``probelab encoders``."""

from __future__ import annotations

import numpy as np
import pytest

import probelab
from conftest import CC0_MAPS, RTOL, assert_rows_agree, cli, cli_json, cli_rows

#: Several families: SH, ZH3 hallucinated and solved (BFGS), Geomerics, the ambient cube, SGs.
ENCODERS = ["sh1", "sh2", "zh3_hallucinate", "zh3_solved_shared", "geomerics", "ambient_cube", "sg_ls"]
#: Two maps of each source.
MAPS = [m for m in CC0_MAPS if m.stem in ("blender_city_256x128", "blender_studio_256x128", "pmndrs_dawn_256x128", "pmndrs_night_256x128")]


def test_the_maps_are_there():
    assert len(MAPS) == 4 and len(CC0_MAPS) >= 10


@pytest.mark.parametrize("path", MAPS, ids=lambda p: p.stem)
def test_eval_from_a_path_and_from_an_array_equals_the_cli(path):
    theirs = cli_rows("--no-timing", "eval", str(path), "--encoders", ",".join(ENCODERS), "--format", "json")
    from_path = probelab.eval(str(path), encoders=ENCODERS)
    assert_rows_agree(from_path, theirs, skip=())
    array = probelab.load_map(path)
    from_array = probelab.eval(array, encoders=ENCODERS, name=path.stem)
    assert_rows_agree(from_array, theirs, skip=())
    # Not merely close: the same code on the same texels gives the same bits.
    assert from_array == from_path


def test_eval_on_the_hemisphere_and_the_peer_metric_equals_the_cli():
    path = str(MAPS[0])
    enc = ["sh2", "hlsh", "hhd_search_hemi", "ahd_linear_hemi"]
    theirs = cli_rows("--no-timing", "eval", path, "--encoders", ",".join(enc), "--domain", "hemisphere:+y", "--format", "json")
    ours = probelab.eval(path, encoders=enc, domain="hemisphere:+y")
    assert_rows_agree(ours, theirs, skip=())
    assert all(r["at_normal_abs_err"] is not None for r in ours)
    theirs = cli_rows("--no-timing", "eval", path, "--encoders", "sh2,sg_nnls", "--metric", "probulator", "--resolution", "128x64", "--format", "json")
    ours = probelab.eval(probelab.load_map(path), ["sh2", "sg_nnls"], metric="probulator", resolution=(128, 64), name=MAPS[0].stem)
    assert_rows_agree(ours, theirs, skip=())


def test_rows_have_the_csv_columns_with_numbers_as_floats():
    (row,) = probelab.eval(str(MAPS[0]), encoders="sh1")
    assert tuple(row) == probelab.COLUMNS
    assert row["map"] == MAPS[0].stem and row["units"] == "E/pi" and row["weighting"] == "solid-angle"
    assert isinstance(row["stored_scalars"], int) and row["stored_scalars"] == 12
    for col in ("rmse_r", "rmse_g", "rmse_b", "rmse", "rel_rmse", "neg_frac", "max_abs_err"):
        assert type(row[col]) is float
    assert row["at_normal_abs_err"] is None and row["fit_ns"] is None


def test_timing_columns_are_filled_when_timing_is_on():
    probelab.set_timing(True)
    try:
        (row,) = probelab.eval(str(MAPS[0]), encoders="sh1")
    finally:
        probelab.set_timing(False)
    assert row["fit_ns"] > 0 and row["eval_ns"] > 0


@pytest.mark.parametrize("normal", [None, (0.0, 1.0, 0.0)])
def test_fit_equals_the_cli_document(normal):
    path = str(MAPS[1])
    enc = ["sh2", "zh3_solved_shared", "geomerics"] + ([] if normal is None else ["hhd_search_hemi"])
    args = ["fit", path, "--encoders", ",".join(enc)] + ([] if normal is None else ["--normal", "0,1,0"])
    theirs = cli_json(*args)
    assert theirs["schema"] == "probelab.fit/1"
    from_path = probelab.fit(path, enc, normal=normal)
    from_array = probelab.fit(probelab.load_map(path), enc, normal=normal, name=MAPS[1].stem)
    assert from_path["maps"] == theirs["maps"]
    # An array has no file: no path, no file sha256; the same pixels, so the same pixel sha256.
    (array_map,) = from_array["maps"]
    assert array_map["path"] is None and array_map["sha256"] is None and array_map["given"] == MAPS[1].stem
    assert array_map["pixel_sha256"] == theirs["maps"][0]["pixel_sha256"]
    for ours in (from_path, from_array):
        assert {k: v for k, v in ours.items() if k not in ("fits", "maps")} == {k: v for k, v in theirs.items() if k not in ("fits", "maps")}
        assert list(ours["fits"]) == enc
        for f, g in zip(ours["fits"].values(), theirs["fits"]):
            assert {k: f[k] for k in g} == g  # encoder, stored_scalars, basis, entries: exactly the JSON
            stored = [e for e in g["entries"] if e["role"] == "stored"]
            flat = [c for e in stored for c in (e["value"] if isinstance(e["value"], list) else [e["value"]])]
            assert f["coefficients"].dtype == np.float64
            assert f["coefficients"].tolist() == flat
            assert len(flat) == g["stored_scalars"] == len(f["names"]) == len(f["units"])
            assert all(n.split(".")[0] in {e["name"] for e in stored} for n in f["names"])


def test_fit_names_the_components():
    f = probelab.fit(str(MAPS[0]), "sh1")["fits"]["sh1"]
    assert f["names"][:4] == ["L0_0.r", "L0_0.g", "L0_0.b", "L1_-1.r"]
    assert set(f["units"]) == {"E/pi"}


def test_encoders_lists_what_the_cli_lists():
    out = cli("encoders")
    assert out.returncode == 0
    theirs = [line.split(None, 1) for line in out.stdout.splitlines()]
    ours = probelab.encoders()
    assert [[k, v] for k, v in ours.items()] == [[k, v.strip()] for k, v in theirs]
    assert "zh3_hallucinate" in ours and len(ours) > 40



def test_eval_csv_is_the_cli_csv_byte_for_byte(tmp_path):
    probelab.set_timing(False)
    paths = [str(m) for m in MAPS[:2]]
    theirs = cli("--no-timing", "eval", paths[0], "--encoders", "sh1,sh2,hhd_search_hemi", "--domain", "hemisphere:+y")
    assert theirs.returncode == 0, theirs.stderr
    ours = probelab.eval_csv(paths[0], ["sh1", "sh2", "hhd_search_hemi"], domain="hemisphere:+y")
    assert ours == theirs.stdout
    # Written as a user would, the file is the command line's bytes (diagnostics and all).
    out = tmp_path / "scores.csv"
    with open(out, "w", newline="") as f:
        f.write(ours)
    assert out.read_bytes() == theirs.stdout.encode()
    # From an array named as the file's stem: the same text.
    assert probelab.eval_csv(probelab.load_map(paths[0]), "sh1,sh2,hhd_search_hemi", domain="hemisphere:+y", name=MAPS[0].stem) == ours
    # Several maps: one table, as one eval over them.
    both = cli("--no-timing", "eval", *paths, "--encoders", "sh1")
    assert probelab.concat_csv(probelab.eval_csv(p, "sh1") for p in paths) == both.stdout


def test_a_string_of_encoders_is_read_as_the_command_line_reads_it():
    one = probelab.eval(str(MAPS[0]), encoders="sh1")
    assert [r["encoder"] for r in one] == ["sh1"]
    two = probelab.eval(str(MAPS[0]), encoders="sh1,sh2")
    assert [r["encoder"] for r in two] == ["sh1", "sh2"]
