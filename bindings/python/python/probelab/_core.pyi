"""Type stubs of ``probelab._core``, the Rust extension; use the ``probelab`` package's functions,
which wrap these with numpy arrays and document them."""

from typing import List, Optional, Tuple, Union

class Error(ValueError):
    """A probelab error; the message is the command line's."""

COLUMNS: List[str]
NUMERIC_COLUMNS: List[str]
TIMING_COLUMNS: List[str]
DEFAULT_POLAR_NODES: int

_Source = Union[str, Tuple[str, int, int, bytes]]
_Coefficients = Tuple[List[str], List[str], List[float]]

def load_map(name: str, root: str) -> Tuple[str, int, int, bytearray]:
    """(name, width, height, little-endian float32 RGB texels, row 0 at the zenith)."""

def eval(
    map: _Source, root: str, encoders: str, domain: str, metric: str, resolution: str, polar_nodes: int, format: str
) -> str:
    """``probelab eval --format json``'s text (``format`` "json") or its CSV (``format`` "csv") on one map;
    Ctrl-C stops it."""

def fit(
    map: _Source, root: str, encoders: str, normal: Optional[Tuple[float, float, float]]
) -> Tuple[str, List[_Coefficients]]:
    """``probelab fit``'s JSON text, and each fit's stored coefficients flattened."""

def reference(
    map: _Source, root: str, normals: bytes, normal: Optional[Tuple[float, float, float]]
) -> bytearray:
    """The exact E/pi at float64 normals, as float64 RGB triples."""

def irradiance(
    map: _Source, root: str, id: str, normals: bytes, normal: Optional[Tuple[float, float, float]]
) -> bytearray:
    """Encoder ``id``'s fitted E/pi at float64 normals, as float64 RGB triples."""

def encoders() -> List[Tuple[str, str]]:
    """(id, summary) of every registered encoder."""

def set_timing(on: bool) -> None:
    """Turns the timing pass of ``eval`` on or off, process-wide."""
