//! The blending strip of one pair of `blend.rs`, as data: lit hemispheres along
//! t = 0, 0.1, …, 1, one row per reconstruction — the blended exact reference first, then each
//! of [`blend::METHODS`] — each row holding E/π at the strip's normals ([`strip_normals`]: a
//! disc looking down N, [`STRIP_DISC`] pixels across). The claims layer measures it; the
//! report layer draws it (`report::strip`), and `probelab claims lightmap` writes the picture
//! as `results/claims/blend_strip_<pair>.png`.

use super::blend;
use crate::math::colour::Rgb;
use crate::reference::view::{Disc, View};
use glam::DVec3;

/// Disc diameter of a blending strip, in pixels (one normal per covered pixel).
pub const STRIP_DISC: usize = 72;

/// The disc every cell of a strip shows: `view` (looking down N), [`STRIP_DISC`] pixels across.
pub fn strip_disc(view: &View) -> Disc {
    Disc::new(view, STRIP_DISC)
}

/// The normals of a strip's discs (looking down `n`), in the order [`StripRow::values`] uses:
/// every reconstruction, and the blended reference, is evaluated at these.
pub fn strip_normals(n: DVec3) -> Vec<DVec3> {
    strip_disc(&View::down(n, "")).normals
}

/// One method's reconstructions along t: E/π at the strip's normals, one vector per t.
#[derive(Clone, Debug)]
pub struct StripRow {
    /// `reference` for the blended exact reference, else one of [`blend::METHODS`].
    pub method: String,
    /// E/π per t (outer, as [`BlendStrip::ts`]) and per normal of [`strip_normals`] (inner).
    pub values: Vec<Vec<Rgb>>,
    /// Per t, the method's RMSE (E/π) against the blended exact reference over the scored
    /// hemisphere grid (the `blend_curve` measure's), printed under its disc; `None` for the
    /// reference row.
    pub rmse: Vec<Option<f64>>,
}

/// Everything a blending strip shows.
#[derive(Clone, Debug)]
pub struct BlendStrip {
    /// The pair's id (`blend::Pair::id`).
    pub pair: String,
    /// The strip's title: `blending <pair>: <description>`.
    pub title: String,
    /// Looking down the pair's N (its caption names N).
    pub view: View,
    /// The disc of every cell; its normals are those of [`strip_normals`].
    pub disc: Disc,
    /// The blend weights, one cell per t.
    pub ts: Vec<f64>,
    /// The blended reference first, then each method.
    pub rows: Vec<StripRow>,
}

impl BlendStrip {
    /// The picture's file name: `blend_strip_<pair>.png`.
    pub fn file_name(&self) -> String {
        format!("blend_strip_{}.png", self.pair)
    }
}

/// The strip of one pair: `ref_a` and `ref_b` are the two bakes' exact references at
/// [`strip_normals`] of the pair's N, blended linearly; each method of [`blend::METHODS`] is
/// reconstructed from `bl` at every t and evaluated at the same normals, with its RMSE at that t
/// from `scored` (the pair's rows of [`blend::study`]).
pub fn blend_strip(
    pair: &blend::Pair,
    bl: &blend::Blend,
    (ref_a, ref_b): (&[Rgb], &[Rgb]),
    scored: &[blend::BlendRow],
) -> BlendStrip {
    let view = View::down(pair.normal, pair.normal_label);
    let disc = strip_disc(&view);
    let ts: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    let mut rows = vec![StripRow {
        method: "reference".into(),
        values: ts.iter().map(|&t| ref_a.iter().zip(ref_b).map(|(x, y)| *x * (1.0 - t) + *y * t).collect()).collect(),
        rmse: vec![None; ts.len()],
    }];
    // The study scores t = i/10 exactly as the strip's ts are made, so they match bit for bit.
    let rmse_at = |m: &str, t: f64| scored.iter().find(|r| r.method == m && r.t == t).map(|r| r.rmse);
    for m in blend::METHODS {
        rows.push(StripRow {
            method: m.into(),
            values: ts
                .iter()
                .map(|&t| {
                    let f = bl.method(m, t);
                    disc.normals.iter().map(|&n| f(n)).collect()
                })
                .collect(),
            rmse: ts.iter().map(|&t| rmse_at(m, t)).collect(),
        });
    }
    BlendStrip {
        pair: pair.id.to_string(),
        title: format!("blending {}: {}", pair.id, pair.description),
        view,
        disc,
        ts,
        rows,
    }
}
