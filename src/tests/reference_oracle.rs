//! The lat-long reference (each input row a circular convolution, grouped fractional shifts:
//! `reference::row_convolution`) against the per-normal reference as a slow oracle
//! (`Reference::irradiance_many`: every normal integrated on its own, row by row, as the
//! reference always was), to 1e-9 relative, on every committed map, on committed maps
//! resampled to widths that are not multiples of the grid's, on grids finer than the map, and
//! on every shared map when `PROBELAB_ENVMAPS` is set.

use super::repository::shared_envmaps;
use crate::envmap::moments::RowMoments;
use crate::envmap::{load, resample, EnvMap, LatLong};
use crate::math::colour::Rgb;
use crate::reference::exact::{Reference, DEFAULT_POLAR_NODES};
use std::path::{Path, PathBuf};

/// The worst difference between the two paths on `grid`, relative to each value; a value below
/// 1e-6 of the grid's largest (normals that see almost no light, as under the generated cone,
/// where both paths are differences of equal cumulative moments and give rounding noise of
/// the rows' scale, ~1e-16 of the largest value) is compared relative to that floor instead.
fn worst_relative(map: &EnvMap, grid: LatLong) -> f64 {
    let rm = RowMoments::new(map);
    let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
    let fast = r.irradiance_latlong(grid);
    let normals: Vec<_> = (0..grid.height)
        .flat_map(|j| (0..grid.width).map(move |i| (i, j)))
        .map(|(i, j)| grid.direction(i, j))
        .collect();
    let slow = r.irradiance_many(&normals);
    assert_eq!(fast.len(), slow.len());
    let top = slow.iter().map(|v| v.max_element()).fold(0.0, f64::max);
    let floor = 1e-6 * top;
    let rel = |a: &Rgb, b: &Rgb| {
        let d = (*a - *b).abs();
        let s = b.abs().max(Rgb::splat(floor));
        (d / s).max_element()
    };
    assert!(fast.iter().all(|v| v.is_finite()), "{}: a value is not finite", map.name);
    fast.iter().zip(&slow).map(|(a, b)| rel(a, b)).fold(0.0, f64::max)
}

fn exr_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "exr"))
        .collect();
    files.sort();
    files
}

/// Every committed map on a grid whose width does not divide the map's (100x50: 4 classes of
/// 25 columns), three also on the default 256x128 grid and on 96x48; a 64x32 map on a grid
/// wider than it (512x256).
#[test]
fn committed_maps_agree_with_the_per_normal_path() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps");
    let files = exr_files(&dir);
    assert!(files.len() >= 20, "the committed maps are missing from {}", dir.display());
    for path in files {
        let map = load::load(&path).unwrap();
        // The default grid on a few maps (the per-normal oracle is slow), a grid that does not
        // divide the map's width on every one.
        let full = ["gen_cone.exr", "pmndrs_bridge_256x128.exr", "blender_city_256x128.exr"];
        let mut grids = vec![LatLong::new(100, 50)];
        if full.iter().any(|f| path.ends_with(f)) {
            grids.extend([LatLong::new(256, 128), LatLong::new(96, 48)]);
        }
        for grid in grids {
            let worst = worst_relative(&map, grid);
            assert!(worst <= 1e-9, "{} on {grid:?}: {worst:e}", path.display());
        }
    }
    let map = load::load(&dir.join("pmndrs_bridge_256x128.exr")).unwrap();
    let small = resample::downsample(&map, 64, 32).unwrap();
    let worst = worst_relative(&small, LatLong::new(512, 256));
    assert!(worst <= 1e-9, "64x32 map on a 512x256 grid: {worst:e}");
}

/// Committed maps resampled to widths that are not multiples of the grid's (1000x500 as the
/// wells probe; 1002x501 shares only a factor 2 with 256, so its classes of two columns are
/// padded from six values to eight) and to a multiple (1024x512); 1000x500 also on a 63-wide
/// grid (no common factor: one column a class, padded to four values) and on the 256-wide grid
/// the experiments use (32 classes of 8 columns), a few rows of it.
#[test]
fn resampled_maps_agree_with_the_per_normal_path() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps");
    for name in ["pmndrs_bridge_256x128.exr", "blender_sunrise_256x128.exr", "gen_sky_sun.exr"] {
        let map = load::load(&dir.join(name)).unwrap();
        for (w, h, grid) in [
            (1000, 500, LatLong::new(64, 32)),
            (1002, 501, LatLong::new(64, 32)),
            (1000, 500, LatLong::new(63, 32)),
            (1024, 512, LatLong::new(64, 32)),
            (1000, 500, LatLong::new(256, 8)),
        ] {
            let big = resample::nearest(&map, w, h).unwrap();
            let worst = worst_relative(&big, grid);
            assert!(worst <= 1e-9, "{name} at {w}x{h} on {grid:?}: {worst:e}");
        }
    }
}

/// Every map in the shared folders (the papers' probes, the other real maps and their 256x128
/// versions), on a 64x32 grid (and 256x128 for the 256x128 maps).
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the shared maps (not all CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn shared_maps_agree_with_the_per_normal_path() {
    let value = shared_envmaps(&["grace_256x128", "wells"]);
    let mut count = 0;
    for dir in std::env::split_paths(&value).filter(|p| p.is_dir()) {
        for path in exr_files(&dir) {
            let map = load::load(&path).unwrap();
            let mut grids = vec![LatLong::new(64, 32)];
            if map.width() <= 256 {
                grids.push(LatLong::new(256, 128));
            }
            for grid in grids {
                let worst = worst_relative(&map, grid);
                assert!(worst <= 1e-9, "{} on {grid:?}: {worst:e}", path.display());
            }
            count += 1;
        }
    }
    assert!(count >= 19, "only {count} shared maps found");
}
