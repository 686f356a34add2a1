//! How the claims engine aggregates ratios: per row (encoder / baseline on the same key), then
//! per map — a map's ratio is the geometric mean of its rows' ratios (its orientations, cases
//! or effects), so every map counts once however many rows it has — then over maps by their
//! median and geometric mean. Never a ratio of pooled means (Σ encoder / Σ baseline): the
//! maps with the largest errors decide that one, whatever the others show.
//!
//! The geometric mean is the natural mean of ratios (the mean of a/b and b/a is 1); the median
//! shows the typical map. A ratio of 0 (an encoder exact where its baseline is not) makes the
//! geometric mean 0, as it should.

/// One map's ratio and the rows behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct MapRatio {
    /// The map (or, in a table without maps, the row's label).
    pub map: String,
    /// The geometric mean of the map's row ratios.
    pub ratio: f64,
    /// How many rows the map has.
    pub rows: usize,
}

/// The per-map ratios and their summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// One entry per map, in first-appearance order.
    pub maps: Vec<MapRatio>,
    /// The median of the per-map ratios.
    pub median: f64,
    /// The geometric mean of the per-map ratios.
    pub geomean: f64,
    /// The smallest per-map ratio.
    pub min: f64,
    /// The largest per-map ratio.
    pub max: f64,
}

/// The median of `v` (the mean of the two middle values for an even count); NaN when empty
/// ([`crate::math::stats::median`]).
pub fn median(v: &[f64]) -> f64 {
    crate::math::stats::median(v).unwrap_or(f64::NAN)
}

/// The geometric mean of non-negative `v`: exp of the mean log (0 if any value is 0); NaN
/// when empty.
pub fn geomean(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    if v.contains(&0.0) {
        return 0.0;
    }
    (v.iter().map(|x| x.ln()).sum::<f64>() / v.len() as f64).exp()
}

/// Groups row ratios `(map, ratio)` by map (first-appearance order) and summarises them.
/// `None` when there are no rows.
pub fn per_map(rows: &[(&str, f64)]) -> Option<Summary> {
    let mut groups: Vec<(String, Vec<f64>)> = Vec::new();
    for (m, r) in rows {
        match groups.iter_mut().find(|(g, _)| g == m) {
            Some((_, v)) => v.push(*r),
            None => groups.push((m.to_string(), vec![*r])),
        }
    }
    if groups.is_empty() {
        return None;
    }
    let maps: Vec<MapRatio> =
        groups.into_iter().map(|(map, v)| MapRatio { map, ratio: geomean(&v), rows: v.len() }).collect();
    let ratios: Vec<f64> = maps.iter().map(|m| m.ratio).collect();
    let (min, max) = ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    Some(Summary { median: median(&ratios), geomean: geomean(&ratios), min, max, maps })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_geometric_mean_by_hand() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan() && geomean(&[]).is_nan());
        // (1/4 · 4)^(1/2) = 1; (1 · 2 · 4)^(1/3) = 2.
        assert!((geomean(&[0.25, 4.0]) - 1.0).abs() < 1e-15);
        assert!((geomean(&[1.0, 2.0, 4.0]) - 2.0).abs() < 1e-15);
        assert_eq!(geomean(&[0.0, 5.0]), 0.0);
    }

    /// A map with many rows counts once: m1's four rows (ratios 0.5, 2, 0.5, 2) make one
    /// per-map ratio of 1, beside m2 (0.25) and m3 (4).
    #[test]
    fn every_map_counts_once() {
        let rows = [("m1", 0.5), ("m1", 2.0), ("m2", 0.25), ("m1", 0.5), ("m1", 2.0), ("m3", 4.0)];
        let s = per_map(&rows).unwrap();
        let got: Vec<(&str, f64, usize)> = s.maps.iter().map(|m| (m.map.as_str(), m.ratio, m.rows)).collect();
        assert_eq!(got.len(), 3);
        assert_eq!((got[0].0, got[0].2), ("m1", 4));
        assert!((got[0].1 - 1.0).abs() < 1e-15);
        assert!((s.median - 1.0).abs() < 1e-15);
        // (1 · 0.25 · 4)^(1/3) = 1.
        assert!((s.geomean - 1.0).abs() < 1e-15);
        assert_eq!((s.min, s.max), (0.25, 4.0));
        assert!(per_map(&[]).is_none());
    }
}
