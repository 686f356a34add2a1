//! Lat-long resampling. Downsampling as the shared `_256x128` maps were made (`SOURCES.md`, "Conventions":
//! "a solid-angle-weighted area average ... separable box filter with fractional overlaps; each
//! source row weighted by its solid angle cos(φ0) − cos(φ1)").
//!
//! Target texel (I, J) of a w×h grid from a W×H source covers source columns [I·W/w, (I+1)·W/w)
//! and rows [J·H/h, (J+1)·H/h). A source texel overlapping that box by a fraction f_x of its
//! width and f_y of its height gets the weight f_x · f_y · (cos φ_j − cos φ_{j+1}), φ_j = πj/H
//! (the fraction of the row times the *whole* row's solid angle), and the target is the
//! weighted mean, summed in f64: first across the columns of each source row (the box in
//! azimuth, where every texel of a row has the same solid angle), then down the rows.
//!
//! Weighting a partly covered row by the exact solid angle of its covered part instead (the
//! integral of sin φ over the overlap) is the other reading of that sentence; it does not
//! reproduce the shared `wells_256x128.exr` (6921 of its 98304 half values differ, by up to 47
//! half steps), while the rule above reproduces it and every CC0 `_256x128` map exactly
//! (docs/decisions.md). For 1024×512 and 512×256 sources the boxes are whole texels and the two
//! readings agree.

use super::{EnvMap, LatLong, Texel};

/// The source cells [0, n) overlapping target cell t of m equal cells on the same interval,
/// with the fraction of each source cell covered.
fn overlaps(n: usize, m: usize, t: usize) -> Vec<(usize, f64)> {
    // Cell edges in source units: t·n/m, exact in f64 for the sizes a map may have.
    let (a, b) = ((t * n) as f64 / m as f64, ((t + 1) * n) as f64 / m as f64);
    let first = (t * n) / m;
    let last = ((t + 1) * n).div_ceil(m).min(n);
    (first..last)
        .filter_map(|i| {
            let lo = a.max(i as f64);
            let hi = b.min(i as f64 + 1.0);
            (hi > lo).then_some((i, hi - lo))
        })
        .collect()
}

/// `map` averaged down to `width`×`height` by the module's rule; the name, path and file
/// sha256 are kept. Fails when the target is larger than the map in either direction (no
/// upsampling) or not 2:1.
pub fn downsample(map: &EnvMap, width: usize, height: usize) -> Result<EnvMap, String> {
    let (sw, sh) = (map.width(), map.height());
    if height == 0 || width != 2 * height {
        return Err(format!("target {width}x{height} is not a 2:1 lat-long size"));
    }
    if width > sw || height > sh {
        return Err(format!("{sw}x{sh} is smaller than {width}x{height}: maps are averaged down, never up"));
    }
    if (width, height) == (sw, sh) {
        return Ok(map.clone());
    }
    let src = LatLong::new(sw, sh);
    // Across the columns of every source row: the mean over each target column's box.
    let cols: Vec<Vec<(usize, f64)>> = (0..width).map(|i| overlaps(sw, width, i)).collect();
    let mut across = vec![[0f64; 3]; width * sh];
    for j in 0..sh {
        let row = map.row(j);
        for (i, ov) in cols.iter().enumerate() {
            let (mut s, mut wsum) = ([0f64; 3], 0f64);
            for &(k, f) in ov {
                for c in 0..3 {
                    s[c] += f * f64::from(row[k][c]);
                }
                wsum += f;
            }
            across[j * width + i] = s.map(|v| v / wsum);
        }
    }
    // Down the rows: each source row's fraction times its solid angle.
    let mut texels: Vec<Texel> = vec![[0.0; 3]; width * height];
    for jt in 0..height {
        let rows: Vec<(usize, f64)> =
            overlaps(sh, height, jt).into_iter().map(|(j, f)| (j, f * src.solid_angle(j))).collect();
        let wsum: f64 = rows.iter().map(|r| r.1).sum();
        for i in 0..width {
            let mut s = [0f64; 3];
            for &(j, w) in &rows {
                for c in 0..3 {
                    s[c] += w * across[j * width + i][c];
                }
            }
            texels[jt * width + i] = s.map(|v| (v / wsum) as f32);
        }
    }
    let mut out = EnvMap::new(map.name.clone(), width, height, texels).map_err(|e| e.to_string())?;
    out.path = map.path.clone();
    out.sha256 = map.sha256.clone();
    Ok(out)
}

/// `map` at `width`×`height` by nearest texel: each target texel takes the source texel that
/// holds its centre. For whole-number factors this is the same piecewise-constant radiance on
/// a finer grid (so the same exact reference); it makes large maps from small committed ones
/// for the size benchmarks. Name, path and file sha256 are kept. Fails when the target is not
/// 2:1.
pub fn nearest(map: &EnvMap, width: usize, height: usize) -> Result<EnvMap, String> {
    if height == 0 || width != 2 * height {
        return Err(format!("target {width}x{height} is not a 2:1 lat-long size"));
    }
    let (sw, sh) = (map.width(), map.height());
    let cols: Vec<usize> = (0..width).map(|i| ((2 * i + 1) * sw / (2 * width)).min(sw - 1)).collect();
    let mut out = EnvMap::from_fn(map.name.clone(), width, height, |i, j| {
        map.texel(cols[i], ((2 * j + 1) * sh / (2 * height)).min(sh - 1))
    })
    .map_err(|e| e.to_string())?;
    out.path = map.path.clone();
    out.sha256 = map.sha256.clone();
    Ok(out)
}

/// `map` at `width`×`height`: averaged down by [`downsample`] when the target is no larger in
/// either direction, otherwise by [`nearest`].
pub fn resized(map: &EnvMap, width: usize, height: usize) -> Result<EnvMap, String> {
    if width <= map.width() && height <= map.height() {
        downsample(map, width, height)
    } else {
        nearest(map, width, height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::test_rng::Rng;

    #[test]
    fn overlaps_cover_each_cell_once() {
        // 5 source cells onto 2: [0, 2.5) and [2.5, 5).
        assert_eq!(overlaps(5, 2, 0), vec![(0, 1.0), (1, 1.0), (2, 0.5)]);
        assert_eq!(overlaps(5, 2, 1), vec![(2, 0.5), (3, 1.0), (4, 1.0)]);
        // 1000 onto 256: every source cell's fractions sum to 1 over the targets.
        let mut total = vec![0f64; 1000];
        for t in 0..256 {
            for (i, f) in overlaps(1000, 256, t) {
                total[i] += f;
            }
        }
        assert!(total.iter().all(|s| (s - 1.0).abs() < 1e-12), "{total:?}");
    }

    /// The average keeps the map's integral over the sphere: Σ L·Ω over the target equals the
    /// source's, because each target texel's solid angle is the sum of its weights (the
    /// weights of one target row add up to its exact solid angle when the boxes are whole
    /// rows). Checked on a 2:1 integer ratio, where that holds exactly, and a constant map is
    /// constant after any ratio.
    #[test]
    fn preserves_the_integral_and_constants() {
        let mut rng = Rng::new(7);
        let src = EnvMap::from_fn("r", 32, 16, |_, _| [rng.uniform01() as f32, rng.uniform01() as f32, 1.0]).unwrap();
        let dst = downsample(&src, 16, 8).unwrap();
        let integral = |m: &EnvMap| {
            let g = m.grid();
            let mut s = 0f64;
            for j in 0..m.height() {
                for i in 0..m.width() {
                    s += f64::from(m.texel(i, j)[0]) * g.solid_angle(j);
                }
            }
            s
        };
        assert!((integral(&src) - integral(&dst)).abs() < 1e-5 * integral(&src), "integral moved");
        let flat = EnvMap::from_fn("c", 1000, 500, |_, _| [0.25, 0.5, 2.0]).unwrap();
        let d = downsample(&flat, 256, 128).unwrap();
        assert!(d.texels().iter().all(|t| (t[0] - 0.25).abs() < 1e-6 && (t[2] - 2.0).abs() < 1e-6));
    }

    /// One target texel by hand: a 10x5 source onto 4x2. Target (0, 0) covers columns
    /// [0, 2.5) and rows [0, 2.5): columns 0 and 1 whole, column 2 half; rows 0 and 1 whole and
    /// row 2 half, each weighted by its solid angle cos(πj/5) − cos(π(j+1)/5).
    #[test]
    fn one_texel_by_hand() {
        let src = EnvMap::from_fn("s", 10, 5, |i, j| [(i + 10 * j) as f32, 0.0, 0.0]).unwrap();
        let d = downsample(&src, 4, 2).unwrap();
        let pi = std::f64::consts::PI;
        let omega = |j: f64| (pi * j / 5.0).cos() - (pi * (j + 1.0) / 5.0).cos();
        let across = |j: f64| (10.0 * j + 10.0 * j + 1.0 + 0.5 * (10.0 * j + 2.0)) / 2.5;
        let w = [omega(0.0), omega(1.0), 0.5 * omega(2.0)];
        let want = (w[0] * across(0.0) + w[1] * across(1.0) + w[2] * across(2.0)) / (w[0] + w[1] + w[2]);
        assert!((f64::from(d.texel(0, 0)[0]) - want).abs() < 1e-5 * want, "{} vs {want}", d.texel(0, 0)[0]);
    }

    #[test]
    fn refuses_upsampling_and_bad_sizes() {
        let m = EnvMap::from_fn("s", 8, 4, |_, _| [1.0; 3]).unwrap();
        assert!(downsample(&m, 16, 8).unwrap_err().contains("never up"));
        assert!(downsample(&m, 6, 2).unwrap_err().contains("2:1"));
        assert_eq!(downsample(&m, 8, 4).unwrap().texels(), m.texels());
    }

    /// Nearest-texel upsampling by a whole factor repeats each texel factor×factor times; a
    /// fractional factor picks the texel under each centre (1000 columns from 256: target
    /// column 999's centre 999.5·256/1000 = 255.87 lies in source column 255).
    #[test]
    fn nearest_repeats_texels() {
        let src = EnvMap::from_fn("s", 8, 4, |i, j| [(i + 10 * j) as f32, 0.0, 1.0]).unwrap();
        let up = nearest(&src, 32, 16).unwrap();
        for j in 0..16 {
            for i in 0..32 {
                assert_eq!(up.texel(i, j), src.texel(i / 4, j / 4));
            }
        }
        let wide = EnvMap::from_fn("w", 256, 128, |i, j| [i as f32, j as f32, 0.0]).unwrap();
        let odd = nearest(&wide, 1000, 500).unwrap();
        assert_eq!(odd.texel(999, 499), [255.0, 127.0, 0.0]);
        assert_eq!(odd.texel(0, 0), [0.0, 0.0, 0.0]);
        assert_eq!(odd.texel(4, 2), [1.0, 0.0, 0.0]);
        assert!(nearest(&src, 6, 2).unwrap_err().contains("2:1"));
        assert_eq!(resized(&wide, 32, 16).unwrap().width(), 32);
    }
}
