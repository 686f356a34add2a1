"""Bad input raises ``probelab.Error`` (a ``ValueError``) with the command line's message; bad
arrays (wrong shape, type or aspect; NaN, infinite or negative values) are refused, naming
what is wrong and where. Nothing panics."""

from __future__ import annotations

import numpy as np
import pytest

import probelab
from conftest import CC0_MAPS, ENVMAPS, cli_error

GOOD = np.ones((8, 16, 3), dtype=np.float32)


def raises(fn, *args, **kwargs) -> str:
    with pytest.raises(probelab.Error) as e:
        fn(*args, **kwargs)
    assert isinstance(e.value, ValueError)
    return str(e.value)


def test_error_is_a_value_error():
    assert issubclass(probelab.Error, ValueError)


@pytest.mark.parametrize(
    "cli_args, call",
    [
        (["eval", "no_such_map_anywhere"], lambda: probelab.eval("no_such_map_anywhere")),
        (["eval", "envmaps/missing.exr"], lambda: probelab.eval("envmaps/missing.exr")),
        (["eval", "blender_city_256x128", "--encoders", "sh1,nope"], lambda: probelab.eval("blender_city_256x128", ["sh1", "nope"])),
        (["eval", "blender_city_256x128", "--encoders", "sh1,sh1"], lambda: probelab.eval("blender_city_256x128", ["sh1", "sh1"])),
        (["eval", "blender_city_256x128", "--domain", "cube"], lambda: probelab.eval("blender_city_256x128", domain="cube")),
        (["eval", "blender_city_256x128", "--metric", "psnr"], lambda: probelab.eval("blender_city_256x128", metric="psnr")),
        (["eval", "blender_city_256x128", "--resolution", "7x3"], lambda: probelab.eval("blender_city_256x128", resolution=(7, 3))),
        (["eval", "blender_city_256x128", "--encoders", "hhd_search_hemi"], lambda: probelab.eval("blender_city_256x128", ["hhd_search_hemi"])),
        (["fit", "blender_city_256x128", "--encoders", "hlsh"], lambda: probelab.fit("blender_city_256x128", ["hlsh"])),
        (["fit", "envmaps/README.md", "--encoders", "sh1"], lambda: probelab.fit("envmaps/README.md", ["sh1"])),
    ],
    ids=["map-not-found", "file-not-found", "unknown-encoder", "encoder-twice", "bad-domain", "bad-metric", "bad-resolution", "needs-normal-eval", "needs-normal-fit", "not-a-map"],
)
def test_messages_are_the_command_lines(cli_args, call, monkeypatch):
    monkeypatch.chdir(ENVMAPS.parent)
    assert raises(call) == cli_error(*cli_args)


def test_a_bad_file_names_the_file(tmp_path):
    bad = tmp_path / "truncated.exr"
    bad.write_bytes(CC0_MAPS[0].read_bytes()[:300])
    message = raises(probelab.load_map, bad)
    assert str(bad) in message
    assert raises(probelab.eval, str(bad)) == cli_error("eval", str(bad))


@pytest.mark.parametrize(
    "array, words",
    [
        (np.ones((8, 16), np.float32), "shape (8, 16); expected (H, W, 3)"),
        (np.ones((8, 16, 4), np.float32), "shape (8, 16, 4); expected (H, W, 3)"),
        (np.ones((8, 8, 3), np.float32), "size 8x8 is not a 2:1 lat-long map"),
        (np.ones((0, 0, 3), np.float32), "size 0x0 is not a 2:1 lat-long map"),
        (np.ones((8, 16, 3), np.complex64), "dtype complex64; expected real numbers"),
        (np.array([[["a"] * 3] * 16] * 8), "expected real numbers"),
        (np.full((8, 16, 3), 1e300), "beyond float32's range"),
    ],
    ids=["2d", "4-channels", "square", "empty", "complex", "strings", "too-large"],
)
def test_bad_array_shapes_and_types_are_refused(array, words):
    for call in (lambda: probelab.eval(array, ["sh1"]), lambda: probelab.fit(array, ["sh1"]), lambda: probelab.reference(array, [[0, 1, 0]])):
        assert words in raises(call)


@pytest.mark.parametrize("value, kind", [(np.nan, "NaN"), (np.inf, "infinite"), (-1.0, "negative")])
def test_bad_texels_are_refused_naming_the_first(value, kind):
    a = GOOD.copy()
    a[3, 5, 1] = value
    a[6, 2, 0] = value
    message = raises(probelab.eval, a, ["sh1"], name="mine")
    assert message == f"map 'mine': 2 texel value(s) are {kind} (first at pixel x=5, y=3, channel G)"
    assert raises(probelab.reference, a, [[0, 1, 0]]).startswith("map 'array': 2 texel value(s)")


def test_texels_above_the_bound_are_refused_as_on_the_command_line():
    """3e38 (below the f32 maximum) once ran and wrote tables no later check could read; the
    bound 1e24 holds for arrays as for files."""
    a = GOOD.copy()
    a[3, 5, 1] = 3e38
    message = raises(probelab.eval, a, ["sh1"], name="mine")
    assert message.startswith("map 'mine': 1 texel value(s) are above the bound 1e24")
    assert message.endswith("(first at pixel x=5, y=3, channel G)")
    b = GOOD.copy()
    b[0, 0, 0] = np.float32(1e24)
    probelab.eval(b, ["sh1"])


def test_not_a_map_at_all():
    assert "not list" in raises(probelab.eval, [[1, 2, 3]])
    assert "name= names an array" in raises(probelab.eval, str(CC0_MAPS[0]), name="x")


@pytest.mark.parametrize(
    "normals, words",
    [
        (np.zeros((2, 3)), "normals: row 0: (0, 0, 0): a normal must be three finite numbers of length at least 1e-6 (its length is 0)"),
        (np.array([[0, 1, 0], [np.nan, 0, 0]]), "normals: row 1: (NaN, 0, 0)"),
        (np.ones((4, 2)), "normals: shape (4, 2)"),
        (np.ones(3), "normals: shape (3,)"),
    ],
)
def test_bad_normals_are_refused(normals, words):
    assert words in raises(probelab.reference, GOOD, normals)
    assert words in raises(probelab.irradiance, GOOD, "sh1", normals)


def test_bad_surface_normals_are_refused():
    assert "normal: 2 component(s)" in raises(probelab.fit, GOOD, ["sh1"], normal=(0, 1))
    assert "surface normal: (0, 0, 0): a normal must be three finite numbers of length at least 1e-6" in raises(probelab.fit, GOOD, ["sh1"], normal=(0, 0, 0))


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"resolution": (16.9, 8.9)}, "resolution width: 16.9 is not a whole number"),
        ({"resolution": (16.0, 8)}, "resolution width: 16.0 is not a whole number"),
        ({"resolution": (16, True)}, "resolution height: True is not a whole number"),
        ({"resolution": 16}, "resolution: 16; expected (W, H)"),
        ({"polar_nodes": 2.5}, "polar_nodes: 2.5 is not a whole number"),
        ({"encoders": [b"sh1"]}, "encoders: b'sh1' is bytes, not a str id"),
        ({"encoders": 1}, "encoders: expected a str or a list of str ids, not int"),
    ],
)
def test_arguments_of_the_wrong_kind_are_refused_not_converted(kwargs, words):
    assert words in raises(probelab.eval, GOOD, **kwargs)
    assert words in raises(probelab.eval_csv, GOOD, **kwargs)


def test_a_numpy_integer_resolution_is_taken():
    (row,) = probelab.eval(GOOD, "sh1", resolution=(np.int64(16), np.int32(8)))
    assert row["resolution"] == "16x8"


@pytest.mark.parametrize("value", ["no", "", 0, 1, None])
def test_set_timing_takes_only_a_bool(value):
    assert "not a bool" in raises(probelab.set_timing, value)


def test_an_explicit_path_that_does_not_exist_lists_no_folder():
    message = raises(probelab.load_map, "envmaps/nope.exr")
    assert "'envmaps/nope.exr' not found (no such file; a path is read as given" in message
    assert "searched" not in message.lower()


def test_concat_csv_refuses_tables_that_do_not_match():
    assert "header differs" in raises(probelab.concat_csv, ["a,b\n1,2\n", "a,c\n1,2\n"])
    assert "no tables" in raises(probelab.concat_csv, [])
