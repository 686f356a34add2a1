"""Compare three lighting encodings on one map and plot their error spheres.

Loads a map as a numpy array, scores SH L1, SH L2 and hallucinated ZH3 against the exact
reference (E/pi, solid-angle weighted over the sphere of normals), and draws, for each, the
error on the sphere of normals (the Rec.709-weighted sum of the channels' |fit - reference|, E/pi),
seen from the front (-Z, the map's centre column) and from the back (+Z). Runs headless
(MPLBACKEND=Agg); the figure is written to --out.

    python bindings/python/examples/compare_encoders.py [--map PATH] [--out error_spheres.png]

Needs matplotlib: pip install "./bindings/python[examples]".
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: no display needed
import matplotlib.pyplot as plt
import numpy as np

import probelab

ENCODERS = ["sh1", "sh2", "zh3_hallucinate"]
REC709 = np.array([0.2126, 0.7152, 0.0722])
DEFAULT_MAP = Path(__file__).resolve().parents[3] / "envmaps" / "blender_city_256x128.exr"


def sphere_normals(size: int, facing: float) -> tuple[np.ndarray, np.ndarray]:
    """Normals of a sphere seen from far along (0, 0, facing): an orthographic disc of
    size x size pixels (+Y up). Returns the (N, 3) normals and the disc's mask."""
    u, v = np.meshgrid(np.linspace(-1, 1, size), np.linspace(1, -1, size))
    inside = u**2 + v**2 < 1
    x = u[inside] * facing  # seen from -Z (looking along +Z), +X is on the left; from +Z, on the right
    y = v[inside]
    z = facing * np.sqrt(1 - x**2 - y**2)
    return np.stack([x, y, z], axis=1), inside


def main() -> None:
    args = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    args.add_argument("--map", default=str(DEFAULT_MAP), help="a lat-long EXR/HDR map")
    args.add_argument("--out", default="error_spheres.png", help="the figure to write (PNG)")
    a = args.parse_args()

    light = probelab.load_map(a.map)  # (H, W, 3) float32, row 0 the zenith
    rows = probelab.eval(light, ENCODERS, name=Path(a.map).stem)
    for r in rows:
        print(f"{r['encoder']:18} rmse {r['rmse']:.5f} E/pi  rel_rmse {r['rel_rmse']:.4f}  ({r['stored_scalars']} scalars)")

    size = 160
    views = [("front (-Z)", -1.0), ("back (+Z)", 1.0)]
    errors = {}
    for label, facing in views:
        normals, inside = sphere_normals(size, facing)
        exact = probelab.reference(light, normals)
        for enc in ENCODERS:
            img = np.full((size, size), np.nan)
            img[inside] = np.abs(probelab.irradiance(light, enc, normals) - exact) @ REC709
            errors[(enc, label)] = img
    top = max(np.nanmax(img) for img in errors.values())

    fig, axes = plt.subplots(len(views), len(ENCODERS), figsize=(3.2 * len(ENCODERS), 3.2 * len(views)))
    for r, enc in enumerate(rows):
        for v, (label, _) in enumerate(views):
            ax = axes[v, r]
            im = ax.imshow(errors[(enc["encoder"], label)], vmin=0, vmax=top, cmap="magma")
            ax.set_title(f"{enc['encoder']}, {label}\nrmse {enc['rmse']:.4f}", fontsize=9)
            ax.axis("off")
    fig.colorbar(im, ax=axes, shrink=0.8, label="Rec.709-weighted |error|, E/pi")
    fig.suptitle(f"{Path(a.map).stem}: error against the exact reference (sphere, solid-angle weighted rmse)", fontsize=10)
    fig.savefig(a.out, dpi=100)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
