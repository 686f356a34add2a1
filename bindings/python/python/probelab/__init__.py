"""probelab from Python: compact diffuse-lighting encodings scored against an exact reference.

The same Rust core as the ``probelab`` command line, with the same numbers: :func:`eval` gives
the rows ``probelab eval --format json`` prints, :func:`eval_csv` the very text of the CSV
``probelab eval`` prints (and :func:`concat_csv` joins such tables), :func:`fit` the document ``probelab fit``
prints, :func:`reference` the exact irradiance at any normals, :func:`load_map` a map's texels.

Units and directions (``docs/conventions.md`` section 1): every irradiance is **E/pi** (a
constant environment of radiance 1 gives 1); directions are world-space unit vectors with
**+Y up**. A map is a lat-long, 2:1 array of shape (H, W, 3) (W = 2H) of linear RGB radiance:
row 0 is the zenith (+Y), the last row the nadir, and the direction of pixel (row j, column i)
is (sin(phi) sin(theta), cos(phi), -sin(phi) cos(theta)) with theta = 2 pi ((i + 1/2)/W - 1/2)
and phi = pi (j + 1/2)/H, so the centre column looks along -Z. This is the layout of the files
the command line reads, so ``eval(load_map(path))`` scores exactly what ``eval(path)`` scores.

Errors are :class:`Error` (a :class:`ValueError`) carrying the command line's message; option
names in messages (``--encoders``, ``--domain``, ``--metric``, ``--resolution``, ``--normal``)
are the keyword arguments of the same names. Long work releases the GIL, so threads and Dask
workers run in parallel; Ctrl-C stops a running :func:`eval` or :func:`eval_csv` within a
fraction of a second (``KeyboardInterrupt``), on the main thread, where Python handles signals.
"""

from __future__ import annotations

import json
from collections import abc
import numbers
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core
from ._core import Error

__all__ = [
    "Error",
    "load_map",
    "eval",
    "eval_csv",
    "concat_csv",
    "fit",
    "encoders",
    "reference",
    "irradiance",
    "set_timing",
    "COLUMNS",
]
__version__ = "0.1.0"

#: The columns of a result row, in the CSV's order (``docs/tables.md``).
COLUMNS: Tuple[str, ...] = tuple(_core.COLUMNS)

MapLike = Union[str, "os.PathLike[str]", np.ndarray]
"""A map: a file path or a name on the search path (``str`` or path-like), or an (H, W, 3) array."""


def _source(map: MapLike, name: Optional[str]) -> Union[str, Tuple[str, int, int, bytes]]:
    """What ``_core`` takes for ``map``: the path or name, or (name, W, H, float32 texel bytes)."""
    if isinstance(map, (str, os.PathLike)):
        if name is not None:
            raise Error("name= names an array; a map read from a file is named after its file")
        return os.fspath(map)
    if not isinstance(map, np.ndarray):
        raise Error(f"map: expected a file path, a map name or an (H, W, 3) numpy array, not {type(map).__name__}")
    if map.ndim != 3 or map.shape[2] != 3:
        raise Error(f"map array: shape {map.shape}; expected (H, W, 3), linear RGB with W = 2 H")
    if map.dtype.kind not in "fiu":
        raise Error(f"map array: dtype {map.dtype}; expected real numbers (float32 is the map's own type)")
    if map.dtype.kind == "f" and map.dtype.itemsize > 4:
        big = np.abs(map[np.isfinite(map)]) > np.finfo(np.float32).max
        if big.any():
            raise Error(f"map array: {int(big.sum())} value(s) beyond float32's range (maps are held as float32)")
    height, width = map.shape[0], map.shape[1]
    texels = np.ascontiguousarray(map, dtype="<f4").tobytes()
    return (name if name is not None else "array", width, height, texels)


def load_map(path: Union[str, "os.PathLike[str]"], *, root: Union[str, "os.PathLike[str]"] = ".") -> np.ndarray:
    """Reads a lat-long map (OpenEXR or Radiance .hdr) as an (H, W, 3) float32 array.

    ``path`` is a file path, or a name looked up as ``NAME.exr``/``NAME.hdr`` in
    ``<root>/envmaps`` and then in each folder of ``PROBELAB_ENVMAPS`` (as the command line).
    The array is linear RGB radiance in the module's orientation: row 0 at the zenith (+Y), the
    centre column looking along -Z. Bad files (not found, wrong aspect, NaN, infinite or
    negative texels, truncated) raise :class:`Error` naming the file and the fault.
    """
    _, width, height, texels = _core.load_map(os.fspath(path), os.fspath(root))
    return np.frombuffer(texels, dtype="<f4").reshape(height, width, 3)


def eval(
    map: MapLike,
    encoders: Union[Sequence[str], str] = ("sh1", "sh2"),
    metric: str = "exact",
    domain: str = "sphere",
    resolution: Tuple[int, int] = (256, 128),
    *,
    polar_nodes: int = _core.DEFAULT_POLAR_NODES,
    name: Optional[str] = None,
    root: Union[str, "os.PathLike[str]"] = ".",
) -> List[Dict[str, Any]]:
    """Scores encoders on a map: the rows ``probelab eval --format json`` prints.

    Args:
        map: a file path or map name (as :func:`load_map`), or an (H, W, 3) array of linear RGB
            radiance (W = 2 H, finite and non-negative; converted to float32, the map's type).
        encoders: encoder ids (:func:`encoders`): a list of ``str``, or one ``str`` read as the
            command line's ``--encoders`` (``"sh1"`` is one id, ``"sh1,sh2"`` two).
        metric: ``"exact"`` (solid-angle weighted, against the exact reference) or
            ``"probulator"`` (the peer tool's per-pixel mean).
        domain: ``"sphere"``, or ``"hemisphere:AXIS"`` with AXIS one of +x -x +y -y +z -z (the
            surface normal N).
        resolution: the output lat-long grid (W, H) the scores are estimated on: two whole
            numbers (a float such as 16.9 is refused, never truncated).
        polar_nodes: Gauss-Legendre nodes per row piece of the reference.
        name: the map's name in the rows when ``map`` is an array (default ``"array"``).
        root: the folder whose ``envmaps/`` is searched first for a map name.

    Returns:
        The ``rows`` of the ``probelab.eval/1`` document (``docs/json.md``): one dict per
        (encoder, orientation) with the CSV's columns (:data:`COLUMNS`, in order,
        ``docs/tables.md``): text columns as ``str``, scores as ``float``, ``stored_scalars``
        as ``int``, ``diagnostics`` as a dict of numbers, and ``None`` where the CSV cell is
        empty (``at_normal_abs_err`` without a surface normal; ``fit_ns``/``eval_ns`` after
        ``set_timing(False)``). These are values, not the CSV's cell texts: for the very text
        ``probelab eval`` prints, use :func:`eval_csv`.
    """
    text = _eval_text("json", map, encoders, metric, domain, resolution, polar_nodes, name, root)
    return [_row(r) for r in json.loads(text)["rows"]]


def eval_csv(
    map: MapLike,
    encoders: Union[Sequence[str], str] = ("sh1", "sh2"),
    metric: str = "exact",
    domain: str = "sphere",
    resolution: Tuple[int, int] = (256, 128),
    *,
    polar_nodes: int = _core.DEFAULT_POLAR_NODES,
    name: Optional[str] = None,
    root: Union[str, "os.PathLike[str]"] = ".",
) -> str:
    """The CSV table ``probelab eval`` prints for the same map and options, as its exact text
    (header line first, ``\n`` line ends): write it with ``open(path, "w", newline="")`` and
    the file is byte for byte the command line's. The arguments are :func:`eval`'s; join the
    tables of several maps with :func:`concat_csv`."""
    return _eval_text("csv", map, encoders, metric, domain, resolution, polar_nodes, name, root)


def concat_csv(tables: Iterable[str]) -> str:
    """One CSV table from several of :func:`eval_csv`'s, in the order given: the header once,
    then every table's rows, as ``probelab eval`` prints them for all those maps at once. Every
    table must have the same header line."""
    out: List[str] = []
    header: Optional[str] = None
    for k, table in enumerate(tables):
        if not isinstance(table, str):
            raise Error(f"concat_csv: table {k} is {type(table).__name__}, not the str eval_csv returns")
        first, _, rows = table.partition("\n")
        if header is None:
            header = first
            out.append(first + "\n")
        elif first != header:
            raise Error(f"concat_csv: table {k}'s header differs from the first table's: {first!r}")
        out.append(rows)
    if header is None:
        raise Error("concat_csv: no tables")
    return "".join(out)


def _eval_text(fmt, map, encoders, metric, domain, resolution, polar_nodes, name, root) -> str:
    """``_core.eval``'s text in format ``fmt`` ("json" or "csv"), the arguments checked."""
    width, height = _resolution(resolution)
    return _core.eval(
        _source(map, name),
        os.fspath(root),
        _encoder_ids(encoders),
        domain,
        metric,
        f"{width}x{height}",
        _whole("polar_nodes", polar_nodes),
        fmt,
    )


def _encoder_ids(encoders: Union[Sequence[str], str]) -> str:
    """The ``--encoders`` value: a ``str`` is taken as the command line takes it (one id, or
    ids separated by commas); a list or tuple must hold only ``str`` ids."""
    if isinstance(encoders, str):
        return encoders
    if isinstance(encoders, (bytes, bytearray)) or not isinstance(encoders, abc.Sequence):
        raise Error(f"encoders: expected a str or a list of str ids, not {type(encoders).__name__}")
    for e in encoders:
        if not isinstance(e, str):
            raise Error(f"encoders: {e!r} is {type(e).__name__}, not a str id")
    return ",".join(encoders)


def _whole(what: str, value: Any) -> int:
    """``value`` as an int when it is a whole number (int or numpy integer, not bool); any
    other value, a float such as 16.9 or 16.0 included, is refused rather than truncated."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise Error(f"{what}: {value!r} is not a whole number (expected an int)")
    return int(value)


def _resolution(resolution: Any) -> Tuple[int, int]:
    """``(W, H)`` as two ints; anything else is refused, naming the value."""
    try:
        width, height = resolution
    except (TypeError, ValueError):
        raise Error(f"resolution: {resolution!r}; expected (W, H), two whole numbers") from None
    return _whole("resolution width", width), _whole("resolution height", height)


def _row(obj: Dict[str, Any]) -> Dict[str, Any]:
    """A JSON row in the CSV's column order, its scores as floats (counts stay ints)."""
    row = {}
    for col in _core.COLUMNS:
        v = obj[col]
        if col in _core.NUMERIC_COLUMNS and col != "stored_scalars" and v is not None:
            v = float(v)
        row[col] = v
    return row


def fit(
    map: MapLike,
    encoders: Union[Sequence[str], str],
    *,
    normal: Optional[Sequence[float]] = None,
    name: Optional[str] = None,
    root: Union[str, "os.PathLike[str]"] = ".",
) -> Dict[str, Any]:
    """Fits encoders to a map: the document ``probelab fit --format json`` prints, with arrays.

    Args:
        map: a file path, map name or (H, W, 3) array, as for :func:`eval`.
        encoders: encoder ids, as for :func:`eval`.
        normal: the surface normal N (x, y, z), world space, +Y up; the fit is then to the
            light above N's horizon. Without it the fit is a probe's, on the whole sphere (the
            encoders that need N are refused).
        name: the map's name when ``map`` is an array (default ``"array"``).
        root: the folder whose ``envmaps/`` is searched first for a map name.

    Returns:
        The ``probelab.fit/1`` document's keys (``docs/json.md``: ``schema``, ``maps`` with the
        map's name, path, size and sha256, ``domain``, ``normal``, ``fitted_on``, ``units``), and
        ``fits``: a dict from encoder id to its fit, in the order asked, each
        with ``encoder``, ``stored_scalars``, ``basis`` (how the entries reconstruct E/pi) and
        ``entries`` (every stored and derived value: ``name``, ``role``, ``unit``, ``value``,
        as in the JSON), plus ``coefficients``, a float64 array of the stored values (the
        entries of role ``stored``, each value's components in order: ``stored_scalars`` of
        them), with ``names`` (``L1_0.g``, ``d.x``, ``ratio``) and ``units`` aligned to it.
    """
    text, flat = _core.fit(_source(map, name), os.fspath(root), _encoder_ids(encoders), _normal(normal))
    doc = json.loads(text)
    fits = {}
    for f, (names, units, values) in zip(doc["fits"], flat):
        f["coefficients"] = np.array(values, dtype=np.float64)
        f["names"] = list(names)
        f["units"] = list(units)
        fits[f["encoder"]] = f
    doc["fits"] = fits
    return doc


def encoders() -> Dict[str, str]:
    """Every registered encoder id with its one-line summary, in the order ``probelab encoders`` lists them."""
    return dict(_core.encoders())


def reference(
    map: MapLike,
    normals: np.ndarray,
    *,
    normal: Optional[Sequence[float]] = None,
    name: Optional[str] = None,
    root: Union[str, "os.PathLike[str]"] = ".",
) -> np.ndarray:
    """The exact E/pi at each normal: the map integrated cell by cell against the clamped cosine.

    Args:
        map: a file path, map name or (H, W, 3) array, as for :func:`eval`.
        normals: an (N, 3) array of directions (world space, +Y up), each finite and non-zero;
            they are normalised.
        normal: a surface normal N: only the light above N's horizon counts (the reference of
            ``domain="hemisphere:..."``). Without it, the whole sphere's light.
        name: the map's name when ``map`` is an array.
        root: the folder whose ``envmaps/`` is searched first for a map name.

    Returns:
        An (N, 3) float64 array of RGB E/pi.
    """
    raw, count = _normals(normals)
    out = _core.reference(_source(map, name), os.fspath(root), raw, _normal(normal))
    return np.frombuffer(out, dtype="<f8").reshape(count, 3)


def irradiance(
    map: MapLike,
    encoder: str,
    normals: np.ndarray,
    *,
    normal: Optional[Sequence[float]] = None,
    name: Optional[str] = None,
    root: Union[str, "os.PathLike[str]"] = ".",
) -> np.ndarray:
    """What an encoding reconstructs: encoder ``encoder`` (default settings) fitted to the map,
    evaluated at each normal, in E/pi. Subtract :func:`reference` at the same normals for its
    error.

    Args:
        map: a file path, map name or (H, W, 3) array, as for :func:`eval`.
        encoder: one encoder id (:func:`encoders`).
        normals: an (N, 3) array of directions, as for :func:`reference`.
        normal: the surface normal N to fit about (needed by the encoders defined only about
            one: AHD/HHD, the H-basis, the occlusion operators).
        name: the map's name when ``map`` is an array.
        root: the folder whose ``envmaps/`` is searched first for a map name.

    Returns:
        An (N, 3) float64 array of RGB E/pi.
    """
    raw, count = _normals(normals)
    out = _core.irradiance(_source(map, name), os.fspath(root), encoder, raw, _normal(normal))
    return np.frombuffer(out, dtype="<f8").reshape(count, 3)


def _normals(normals: np.ndarray) -> Tuple[bytes, int]:
    """An (N, 3) array of real numbers as little-endian float64 bytes, and N."""
    arr = np.asarray(normals)
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.dtype.kind not in "fiu":
        raise Error(f"normals: shape {arr.shape}, dtype {arr.dtype}; expected an (N, 3) array of real numbers")
    return np.ascontiguousarray(arr, dtype="<f8").tobytes(), arr.shape[0]


def _normal(normal: Optional[Sequence[float]]) -> Optional[Tuple[float, float, float]]:
    """The surface normal as three floats, or None."""
    if normal is None:
        return None
    n = tuple(float(c) for c in normal)
    if len(n) != 3:
        raise Error(f"normal: {len(n)} component(s); expected x, y, z")
    return (n[0], n[1], n[2])


def set_timing(on: bool) -> None:
    """Whether :func:`eval` measures ``fit_ns`` and ``eval_ns`` (on by default, as the command
    line; ``set_timing(False)`` is its ``--no-timing``). Process-wide. ``on`` must be a bool
    (``True``/``False``; a numpy bool is taken too): ``set_timing("no")`` is refused, not read
    as true."""
    if not isinstance(on, (bool, np.bool_)):
        raise Error(f"set_timing: {on!r} is {type(on).__name__}, not a bool (True or False)")
    _core.set_timing(bool(on))
