"""Maps as arrays and the exact reference: the orientation convention (docs/conventions.md
section 1: row 0 the zenith, +Y up, the centre column looking along -Z, +X a quarter turn to
the right of it) checked on constructed maps, the reference against closed forms, and an
encoder's reconstruction against its score."""

from __future__ import annotations

import numpy as np
import pytest

import probelab
from conftest import CC0_MAPS

H, W = 64, 128


def directions(width: int, height: int) -> np.ndarray:
    """The unit direction of every texel centre of a width x height lat-long map, (H, W, 3),
    written from docs/conventions.md section 1."""
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    theta = 2 * np.pi * ((i + 0.5) / width - 0.5)
    phi = np.pi * (j + 0.5) / height
    return np.stack([np.sin(phi) * np.sin(theta), np.cos(phi), -np.sin(phi) * np.cos(theta)], axis=-1)


def test_load_map_is_float32_h_w_3_and_writable():
    m = probelab.load_map(CC0_MAPS[0])
    assert m.shape == (128, 256, 3) and m.dtype == np.float32 and m.flags.writeable
    assert np.isfinite(m).all() and (m >= 0).all()
    assert np.array_equal(probelab.load_map(CC0_MAPS[0].stem, root=CC0_MAPS[0].parent.parent), m)


#: The reference integrates each row exactly in azimuth and by a Gauss-Legendre rule in the polar
#: angle (2 nodes per row piece by default): exact to ~1e-8 on these maps, not to rounding.
QUADRATURE = 1e-7


def test_a_constant_map_gives_one_everywhere():
    normals = np.array([[0, 1, 0], [0, -1, 0], [1, 0, 0], [0.3, -0.2, 0.9], [-5, 0, 0]], dtype=float)
    e = probelab.reference(np.ones((H, W, 3), np.float32), normals)
    assert e.shape == (5, 3) and e.dtype == np.float64
    np.testing.assert_allclose(e, 1.0, rtol=QUADRATURE)


def test_the_upper_half_is_the_sky():
    """Radiance 1 in rows 0..H/2 (the upper hemisphere, if row 0 is the zenith): E/pi(n) =
    (1 + n_y) / 2 exactly (the clamped-cosine integral of a hemisphere)."""
    m = np.zeros((H, W, 3), np.float32)
    m[: H // 2] = 1.0
    normals = np.array([[0, 1, 0], [0, -1, 0], [1, 0, 0], [0, 0.6, 0.8], [0.6, -0.8, 0]])
    e = probelab.reference(m, normals)
    np.testing.assert_allclose(e[:, 0], (1 + normals[:, 1]) / 2, atol=QUADRATURE)
    # The same light seen by a surface facing down: only what is above its horizon (nothing).
    assert np.abs(probelab.reference(m, [[0, -1, 0]], normal=(0, -1, 0))).max() < QUADRATURE


@pytest.mark.parametrize("column, toward", [(W // 2, (0, 0, -1)), (3 * W // 4, (1, 0, 0)), (W // 4, (-1, 0, 0)), (0, (0, 0, 1))])
def test_columns_look_where_the_convention_says(column, toward):
    """A bright strip around one column at the horizon lights most the normal the convention
    gives that column's direction."""
    m = np.full((H, W, 3), 0.01, np.float32)
    m[H // 2 - 2 : H // 2 + 2, column - 1 : column + 1] = 100.0
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    e = probelab.reference(m, axes)[:, 0]
    assert tuple(axes[np.argmax(e)]) == toward
    d = directions(W, H)[H // 2, column]
    assert np.allclose(d, toward, atol=0.05)


def test_reference_of_a_real_map_is_its_own_integral():
    """The exact reference against a brute-force sum over texel centres (solid-angle weights,
    written here): close, not equal (the reference integrates cells exactly)."""
    m = probelab.load_map(CC0_MAPS[1]).astype(np.float64)
    h, w, _ = m.shape
    d = directions(w, h).reshape(-1, 3)
    rows = np.arange(h)
    omega = (2 * np.pi / w) * (np.cos(np.pi * rows / h) - np.cos(np.pi * (rows + 1) / h))
    weights = np.repeat(omega, w)
    normals = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1], [0.5, -0.5, 0.7]])
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    cos = np.clip(d @ normals.T, 0, None)
    brute = (cos * weights[:, None]).T @ m.reshape(-1, 3) / np.pi
    np.testing.assert_allclose(probelab.reference(m.astype(np.float32), normals), brute, rtol=2e-3)


def test_an_encoders_reconstruction_gives_its_score():
    """eval's rmse, rebuilt from irradiance() and reference() on the output grid with the
    solid-angle weights (docs/tables.md, the exact metric): the same figure."""
    path = str(CC0_MAPS[2])
    w, h = 64, 32
    (row,) = probelab.eval(path, ["sh2"], resolution=(w, h))
    d = directions(w, h).reshape(-1, 3)
    err = probelab.irradiance(path, "sh2", d) - probelab.reference(path, d)
    rows = np.arange(h)
    omega = np.repeat(np.cos(np.pi * rows / h) - np.cos(np.pi * (rows + 1) / h), w)
    per_channel = (omega[:, None] * err**2).sum(axis=0) / omega.sum()
    assert np.sqrt(per_channel.mean()) == pytest.approx(row["rmse"], rel=1e-9)
    assert np.sqrt(per_channel) == pytest.approx([row["rmse_r"], row["rmse_g"], row["rmse_b"]], rel=1e-9)
