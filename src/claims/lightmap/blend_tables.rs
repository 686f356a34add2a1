//! H5 and H7 on real pairs, the blending study's tables ([`crate::claims::lightmap::blend`]):
//! every pair's endpoints baked, blended and studied; `blend` (per pair and method, the RMSE
//! over t and the overshoot at N), `blend_curve` (the same along t) and the blending strips.

use crate::claims::lightmap::blend;
use crate::claims::lightmap::strip;
use crate::claims::measure::Measure;
use crate::envmap::search::SearchPath;
use crate::reference::domain::Domain;
use anyhow::Result;
use glam::DVec3;

/// The columns every blending row ends with: reference, weighting, resolution, units.
const BLEND_CONTEXT: [&str; 4] = ["exact occluded, blended linearly", "solid_angle", "128x32", "E/pi"];

/// The blending methods, as the blending tables' descriptions name them.
const BLEND_METHODS: &str = "ahd_params / hhd_params: the stored AHD / HHD parameters of ahd_search_hemi / \
                             hhd_search_hemi fits blended; ahd_irradz / hhd_irradz: the same fits stored as IrradZ \
                             (C_a, I_z, d_xy) blended; sh1_hhd: the linear SH blended, then HHD solved from it in \
                             closed form; sh2: the L2 SH blended";

/// H5 and H7 on real pairs, the blending study (`blend.rs`): `blend` per pair (`case`) and
/// method (`encoder`), `blend_curve` along t; and the strips.
pub(super) fn blend_measures(search: &SearchPath) -> Result<(Measure, Measure, Vec<strip::BlendStrip>)> {
    let pairs = blend::pairs();
    let (rows, sums, strips) = blend_study(search, &pairs)?;
    Ok((blend_summary(&pairs, &sums), blend_curve(&pairs, &rows), strips))
}

/// Bakes both endpoints of every pair on the scored grid and the strip's normals, blends
/// them, and studies the blend: the rows along t, the per-method summaries and the strips.
fn blend_study(
    search: &SearchPath,
    pairs: &[blend::Pair],
) -> Result<(Vec<blend::BlendRow>, Vec<blend::BlendSummary>, Vec<strip::BlendStrip>)> {
    let (mut rows, mut sums) = (Vec::new(), Vec::new());
    let mut strips = Vec::new();
    for pair in pairs {
        let grid = Domain::Hemisphere { normal: pair.normal }.output_grid(blend::GRID);
        // The scored grid, then the strip's normals (the reference there is drawn, not scored).
        let strip = strip::strip_normals(pair.normal);
        let normals: Vec<DVec3> = grid.normals.iter().chain(&strip).copied().collect();
        let mut a = blend::bake(search, &pair.a, pair.normal, pair.normal_label, &normals)?;
        let mut b = blend::bake(search, &pair.b, pair.normal, pair.normal_label, &normals)?;
        let (strip_a, strip_b) = (a.reference.split_off(grid.normals.len()), b.reference.split_off(grid.normals.len()));
        let bl = blend::Blend::new(pair.normal, a, b);
        let (r, s) = blend::study(pair, &bl, &grid.normals, &grid.weights);
        strips.push(strip::blend_strip(pair, &bl, (&strip_a, &strip_b), &r));
        rows.extend(r);
        sums.extend(s);
    }
    Ok((rows, sums, strips))
}

/// The pair of the study whose id is `id`.
fn pair<'a>(pairs: &'a [blend::Pair], id: &str) -> &'a blend::Pair {
    pairs.iter().find(|p| p.id == id).expect("a pair of the study")
}

/// A pair's `domain` cell: the hemisphere about its N, `hemisphere:<N>`.
fn pair_domain(pairs: &[blend::Pair], id: &str) -> String {
    format!("hemisphere:{}", pair(pairs, id).normal_label)
}

/// The `blend` table: per pair and method, the RMSE over t and the overshoot at N.
fn blend_summary(pairs: &[blend::Pair], sums: &[blend::BlendSummary]) -> Measure {
    let mut summary = Measure::new(
        "blend",
        &format!(
            "claims H5 and H7 (real pairs), blending two bakes of one lightmap texel along t = 0, 0.1, ..., 1 \
             (src/claims/lightmap/blend.rs; case = the pair, encoder = the method: {BLEND_METHODS}). mean_rmse, \
             mean_rmse_interior (t = 0.1, ..., 0.9 only), max_rmse, rmse_t0, rmse_half, rmse_t1: E/pi RMSE against the blended exact reference over t, hemisphere \
             about N (domain), solid-angle weighted, 128x32 normals; overshoot_rel / undershoot_rel: the largest \
             Rec.709 luminance of I(N) over t (101 steps) above the larger endpoint / below the smaller, relative to \
             the larger endpoint"
        ),
        &[
            "case",
            "encoder",
            "description",
            "mean_rmse",
            "mean_rmse_interior",
            "max_rmse",
            "rmse_t0",
            "rmse_half",
            "rmse_t1",
            "overshoot_rel",
            "undershoot_rel",
            "metric",
            "domain",
            "reference",
            "weighting",
            "resolution",
            "units",
        ],
    );
    for s in sums {
        let p = pair(pairs, &s.pair);
        let mut row = vec![
            s.pair.as_str().into(),
            s.method.as_str().into(),
            format!("{} (N = {})", p.description, p.normal_label).into(),
            s.mean_rmse.into(),
            s.mean_rmse_interior.into(),
            s.max_rmse.into(),
            s.rmse_t0.into(),
            s.rmse_half.into(),
            s.rmse_t1.into(),
            s.overshoot.into(),
            s.undershoot.into(),
            "exact".into(),
            pair_domain(pairs, &s.pair).into(),
        ];
        row.extend(BLEND_CONTEXT.iter().map(|&c| c.into()));
        summary.row(row);
    }
    summary
}

/// The `blend_curve` table: per pair and method, RMSE and the luminance at N along t.
fn blend_curve(pairs: &[blend::Pair], rows: &[blend::BlendRow]) -> Measure {
    let mut curve = Measure::new(
        "blend_curve",
        &format!(
            "claims H5 and H7, the blending study along t (the blending charts' data; pair, method: {BLEND_METHODS}). \
             rmse, rel_rmse: E/pi against the blended exact reference, hemisphere about N (domain), solid-angle \
             weighted, 128x32 normals; luma_at_normal / reference_luma_at_normal: Rec.709 luminance of E/pi at N of \
             the method / of the blended reference"
        ),
        &[
            "pair",
            "method",
            "t",
            "rmse",
            "rel_rmse",
            "luma_at_normal",
            "reference_luma_at_normal",
            "domain",
            "reference",
            "weighting",
            "resolution",
            "units",
        ],
    );
    for r in rows {
        let mut row = vec![
            r.pair.as_str().into(),
            r.method.as_str().into(),
            r.t.into(),
            r.rmse.into(),
            r.rel_rmse.into(),
            r.at_normal.into(),
            r.reference_at_normal.into(),
            pair_domain(pairs, &r.pair).into(),
        ];
        row.extend(BLEND_CONTEXT.iter().map(|&c| c.into()));
        curve.row(row);
    }
    curve
}
