//! Light leaks of the SH probe occlusion operators (hemispherical-lighting talk, the light-probe
//! half: "most of the objectionable light leakage on the normal maps is gone"; claim H8).
//!
//! **The leak.** A case is a surface normal N under the hemisphere effect: light from below N's
//! horizon is occluded. Split the map's light by linearity into its visible part (under the
//! hemisphere about N) and its occluded part, L = L_vis + L_occ, and the probe's L2 SH with it,
//! f = f_vis + f_occ (`runner::CaseData`: `visible_sh` is the exact projection of L_vis). The
//! exact occluded irradiance does not depend on L_occ at all, so the light an operator lets
//! through from occluded directions is what L_occ changes in its output:
//!
//! leak(n′) = O(f)(n′) − O(f_vis)(n′), E/π at each normal n′ of the hemisphere about N,
//!
//! the fit from the whole probe minus the fit from the probe of the visible light alone (both
//! with the same N). For an operator linear in the probe (every one but `probe_hhd_lum`, whose
//! luminance HHD solve is not) this is O(f_occ)(n′), the output the occluded light alone
//! produces. The exact answer is 0. Unlike the RMSE against the occluded reference, the leak
//! does not count the probe's L2 truncation of the visible light: by RMSE the full multiply
//! (an L2 output of the occluded L2 radiance) is worse than the unoccluded probe on 102 of the
//! 741 cases of `probe_occlusion`, which says nothing about what leaks.
//!
//! Per case and encoder, over the output grid of the hemisphere about N with its solid-angle
//! weights, channels counted equally: `leak` = the mean of |leak| (E/π), `leak_mean` its
//! signed mean, `leak_rms` its RMS, and `visible_mean` = the mean over the hemisphere of the
//! exact E/π of the visible light, in closed form from the bands 0–1 of `visible_sh` (the
//! hemisphere mean of every band ≥ 2 of an irradiance is 0: ∫₀¹ P_l = 0 for even l ≥ 2 and
//! Â_l = 0 for odd l ≥ 3), so `leak_rel` = `leak` / `visible_mean`.

use crate::claims::measure::{Cell, Measure};
use crate::encoders::encoder::Fitted;
use crate::envmap::search::SearchPath;
use crate::envmap::EnvMap;
use crate::math::colour::Rgb;
use crate::math::sh::{k, Sh9};
use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::{cases, evaluate, Case, CaseData, CaseInputs, MapData};
use crate::reference::domain::OutputGrid;
use anyhow::{Context, Result};
use glam::DVec3;
use rayon::prelude::*;

/// The `probe_leak` table: every encoder of the probe-occlusion experiment `exp` on each of its
/// maps (loaded through `search`, in its order), per orientation.
pub fn measure(search: &SearchPath, exp: &Experiment) -> Result<Measure> {
    let (w, h) = exp.resolution;
    let mut m = Measure::new(
        "probe_leak",
        &format!(
            "claim H8, the light the SH probe occlusion operators of experiments/{}.toml let through from occluded \
             directions (src/claims/lightmap/leak.rs): per map, N (domain) and encoder, leak(n') = the operator's E/pi \
             fitted from the whole probe minus fitted from the L2 SH of the light visible under the hemisphere about \
             N (exact answer 0); leak = solid-angle mean of |leak| over the hemisphere about N ({w}x{} normals), \
             leak_mean its signed mean, leak_rms its RMS (channels counted equally, E/pi); visible_mean = the exact \
             hemisphere mean of the visible light's E/pi (closed form, bands 0-1); leak_rel = leak / visible_mean",
            exp.name,
            h / 2
        ),
        &[
            "map",
            "encoder",
            "domain",
            "orientation_set",
            "effects",
            "metric",
            "leak",
            "leak_mean",
            "leak_rms",
            "visible_mean",
            "leak_rel",
            "reference",
            "weighting",
            "resolution",
            "units",
        ],
    );
    for name in &exp.maps {
        let map = search.load(name).with_context(|| format!("claims probe_leak ({})", exp.name))?;
        for r in map_leaks(exp, &map) {
            let rel = if r.visible_mean > 0.0 { Cell::Num(r.stats.abs_mean / r.visible_mean) } else { "".into() };
            m.row(vec![
                name.into(),
                r.encoder.into(),
                r.domain.into(),
                r.orientation_set.into(),
                r.effects.into(),
                "leak".into(),
                r.stats.abs_mean.into(),
                r.stats.mean.into(),
                r.stats.rms.into(),
                r.visible_mean.into(),
                rel,
                "0 (no light from below the horizon of N)".into(),
                "solid_angle".into(),
                format!("{w}x{}", h / 2).into(),
                "E/pi".into(),
            ]);
        }
    }
    Ok(m)
}

/// One encoder's leak on one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseLeak {
    /// The case's domain label, `hemisphere:<N>`.
    pub domain: String,
    /// The orientation set N came from.
    pub orientation_set: String,
    /// The case's effects label.
    pub effects: String,
    /// The encoder's name in the experiment.
    pub encoder: String,
    /// The leak's statistics over the hemisphere about N.
    pub stats: LeakStats,
    /// The mean over the hemisphere about N of the exact E/π of the visible light (the three
    /// channels' mean).
    pub visible_mean: f64,
}

/// Statistics of a leak over an output grid, solid-angle weighted, channels counted equally.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeakStats {
    /// The mean of |leak| (E/π).
    pub abs_mean: f64,
    /// The signed mean of the leak (E/π).
    pub mean: f64,
    /// The RMS of the leak (E/π).
    pub rms: f64,
}

/// The statistics of `leak` (E/π per normal) with solid-angle weights `w`; sums in index order.
pub fn stats(leak: &[Rgb], w: &[f64]) -> LeakStats {
    let (mut a, mut m, mut s, mut total) = (0.0, 0.0, 0.0, 0.0);
    for (l, &wi) in leak.iter().zip(w) {
        a += wi * l.abs().element_sum() / 3.0;
        m += wi * l.element_sum() / 3.0;
        s += wi * l.length_squared() / 3.0;
        total += wi;
    }
    if total <= 0.0 {
        return LeakStats { abs_mean: 0.0, mean: 0.0, rms: 0.0 };
    }
    LeakStats { abs_mean: a / total, mean: m / total, rms: (s / total).sqrt() }
}

/// The exact mean over the hemisphere about `n` of the E/π of the light whose L2 SH is `sh`
/// (bands 0–1 alone; see the module doc), the channels' mean: f₀₀·Y₀₀ + (2/3)·Y₁·(b·n)/2.
pub fn hemisphere_mean(sh: &Sh9, n: DVec3) -> f64 {
    (0..3).map(|c| sh[0][c] * k::Y00 + k::Y1 / 3.0 * sh.l1_vector(c).dot(n)).sum::<f64>() / 3.0
}

/// The cases of `exp` with a surface normal, each orientation once (an orientation listed in
/// two sets, such as `up` and the +y of `axes6`, is kept where it first appears).
pub fn leak_cases(exp: &Experiment) -> Vec<Case> {
    let mut out: Vec<Case> = Vec::new();
    for c in cases(exp) {
        let seen = out.iter().any(|o| o.domain_label == c.domain_label && o.effects_label == c.effects_label);
        if c.normal.is_some() && !seen {
            out.push(c);
        }
    }
    out
}

/// Every encoder's leak of `exp` on `map`, per case of [`leak_cases`] (in parallel, collected
/// in order).
pub fn map_leaks(exp: &Experiment, map: &EnvMap) -> Vec<CaseLeak> {
    let data = MapData::new(map);
    let all = leak_cases(exp);
    all.par_iter().map(|case| case_leaks(exp, &data, case)).collect::<Vec<_>>().into_iter().flatten().collect()
}

/// Every encoder's leak on one case: fitted from the whole probe and from the probe of the
/// visible light, evaluated on the case's grid.
fn case_leaks(exp: &Experiment, data: &MapData, case: &Case) -> Vec<CaseLeak> {
    let Some(n) = case.normal else { return Vec::new() };
    let cd = CaseData::new(data, case, exp.polar_nodes);
    let grid = case.domain.output_grid(exp.resolution);
    let visible = CaseInputs { probe_sh: cd.inputs.visible_sh, ..cd.inputs };
    let (whole, seen) = (cd.fit_input(), visible.fit_input(case, Some(&cd.light)));
    let visible_mean = hemisphere_mean(&cd.inputs.visible_sh, n);
    exp.encoders
        .iter()
        .map(|named| {
            let a = named.encoder.fit(&whole);
            let b = named.encoder.fit(&seen);
            CaseLeak {
                domain: case.domain_label.clone(),
                orientation_set: case.orientation_set.clone(),
                effects: case.effects_label.clone(),
                encoder: named.name.clone(),
                stats: leak_on(a.as_ref(), b.as_ref(), &grid),
                visible_mean,
            }
        })
        .collect()
}

/// The statistics of `whole` − `visible` on `grid`.
fn leak_on(whole: &dyn Fitted, visible: &dyn Fitted, grid: &OutputGrid) -> LeakStats {
    let a = evaluate(whole, &grid.normals);
    let b = evaluate(visible, &grid.normals);
    let leak: Vec<Rgb> = a.iter().zip(&b).map(|(x, y)| *x - *y).collect();
    stats(&leak, &grid.weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The radiance below the horizon, L.
    const L: f64 = 0.75;

    /// A map lit only below the horizon: radiance L on every texel of the lower half
    /// (ω·Y < 0), 0 above; the equator is a row edge, so the split is exact.
    fn lower_half(w: usize, h: usize) -> EnvMap {
        let texels = (0..w * h).map(|i| if i / w >= h / 2 { [L as f32; 3] } else { [0.0; 3] }).collect();
        EnvMap::new("lower_half", w, h, texels).unwrap()
    }

    fn experiment() -> Experiment {
        let text = "maps = ['lower_half']\nencoders = ['probe_unoccluded', 'probe_hemi_full', 'probe_hemi_q2l', \
                    'hlsh', { kind = 'sh2', name = 'sh2_of_visible' }]\ndomain = 'hemisphere'\n\
                    orientations = ['up', 'axes6']\neffects = ['hemisphere']\nresolution = [128, 64]\n";
        Experiment::parse(text, Path::new("leak.toml")).unwrap()
    }

    /// The leak of each operator as a function of z′ = n′·N for constant radiance L below the
    /// horizon of N = +y, derived by hand from the band-limited SH (not through the operators'
    /// code). The lower half's zonal SH: f₀ = √π·L, f₁ = −(√(3π)/2)·L, f₂ = 0 (∫₋₁⁰ P₂ = 0),
    /// so its L2 radiance is L(½ − ¾z) and:
    /// - unoccluded: E/π = ½ − ½z′ (the lower hemisphere light, 1 − H);
    /// - full multiply: L(½ − ¾z)·[z > 0] projected to L2 has g₀ = √π/8, g₁ = 0,
    ///   g₂ = 2π·√(5/16π)·(−3/16), so E/π = 1/16 − (15/512)(3z′² − 1);
    /// - quadratic-to-linear: its linear part, 1/16;
    /// - HLSH: I_z = (1/π)∫_{z>0} L(½ − ¾z)z dω = 2(¼ − ¼) = 0, t = 0 by symmetry, and a
    ///   minimises ∫₀¹ (a(1 − z) − T(z))² dz against the full multiply T: a·⅓ = 1/32 + 15/2048,
    ///   a = 237/2048, so E/π = (237/2048)(1 − z′).
    ///
    /// All are ≥ 0 on the hemisphere, so |leak| = leak; the continuous means are ¼, 1/16, 1/16
    /// and 237/4096.
    fn closed_form(encoder: &str, z: f64) -> f64 {
        L * match encoder {
            "probe_unoccluded" => 0.5 * (1.0 - z),
            "probe_hemi_full" => 1.0 / 16.0 - 15.0 / 512.0 * (3.0 * z * z - 1.0),
            "probe_hemi_q2l" => 1.0 / 16.0,
            "hlsh" => 237.0 / 2048.0 * (1.0 - z),
            _ => 0.0,
        }
    }

    #[test]
    fn leaks_of_light_below_the_horizon_match_the_closed_forms() {
        let exp = experiment();
        let map = lower_half(64, 32);
        let rows = map_leaks(&exp, &map);
        // up and the +y of axes6 are one orientation: 6 cases, 5 encoders each.
        assert_eq!(rows.len(), 30);
        let grid = crate::reference::domain::Domain::Hemisphere { normal: DVec3::Y }.output_grid((128, 64));
        let total: f64 = grid.weights.iter().sum();
        for enc in ["probe_unoccluded", "probe_hemi_full", "probe_hemi_q2l", "hlsh", "sh2_of_visible"] {
            let r = rows.iter().find(|r| r.domain == "hemisphere:+y" && r.encoder == enc).unwrap();
            assert_eq!(r.orientation_set, "up");
            // The closed form on the grid's own quadrature (what the measure sums).
            let on_grid = |p: i32| {
                grid.normals.iter().zip(&grid.weights).map(|(m, w)| w * closed_form(enc, m.y).powi(p)).sum::<f64>()
                    / total
            };
            let (mean, rms) = (on_grid(1), on_grid(2).sqrt());
            let s = r.stats;
            assert!((s.mean - mean).abs() < 1e-12 && (s.abs_mean - mean).abs() < 1e-12, "{enc}: {s:?} vs {mean}");
            assert!((s.rms - rms).abs() < 1e-12, "{enc}: {} vs {rms}", s.rms);
            // Nothing is visible from a floor under this light.
            assert!(r.visible_mean.abs() < 1e-15, "{}", r.visible_mean);
        }
        // The continuous means, within the 32-row grid's quadrature.
        let mean =
            |enc: &str| rows.iter().find(|r| r.domain == "hemisphere:+y" && r.encoder == enc).unwrap().stats.mean;
        for (enc, want) in [
            ("probe_unoccluded", 0.25),
            ("probe_hemi_full", 1.0 / 16.0),
            ("probe_hemi_q2l", 1.0 / 16.0),
            ("hlsh", 237.0 / 4096.0),
            ("sh2_of_visible", 0.0),
        ] {
            assert!((mean(enc) - L * want).abs() < 1e-3 * L, "{enc}: {} vs {}", mean(enc), L * want);
        }
        // The unoccluded probe's RMS: L·√(∫₀¹ ((1 − z)/2)² dz) = L/√12.
        let rms = rows.iter().find(|r| r.domain == "hemisphere:+y" && r.encoder == "probe_unoccluded").unwrap();
        assert!((rms.stats.rms - L / 12f64.sqrt()).abs() < 2e-3 * L);
    }

    /// Facing down (N = −y) the same light is all visible: nothing leaks, for every operator
    /// (the occluded light is 0), and the visible mean is L times the hemisphere mean of the
    /// hemisphere light H = (1 + z′)/2, ¾·L.
    #[test]
    fn nothing_leaks_when_the_light_is_all_visible() {
        let rows = map_leaks(&experiment(), &lower_half(64, 32));
        for r in rows.iter().filter(|r| r.domain == "hemisphere:-y") {
            assert!(r.stats.abs_mean < 1e-12 && r.stats.rms < 1e-12, "{}: {:?}", r.encoder, r.stats);
            assert!((r.visible_mean - 0.75 * L).abs() < 1e-12, "{}", r.visible_mean);
        }
    }

    /// The hemisphere mean in closed form against the grid quadrature of the L2 irradiance of
    /// random lighting: equal up to the grid's quadrature of band 2 (which integrates to 0).
    #[test]
    fn hemisphere_mean_is_the_mean_of_the_irradiance() {
        let mut rng = crate::math::test_rng::Rng::new(3);
        for _ in 0..10 {
            let (sh, n) = (rng.sh(), rng.unit());
            let grid = crate::reference::domain::Domain::Hemisphere { normal: n }.output_grid((256, 128));
            let irr = sh.convolve_cosine();
            let total: f64 = grid.weights.iter().sum();
            let q: f64 =
                grid.normals.iter().zip(&grid.weights).map(|(m, w)| w * irr.eval(*m).element_sum() / 3.0).sum();
            assert!((q / total - hemisphere_mean(&sh, n)).abs() < 1e-4, "{} vs {}", q / total, hemisphere_mean(&sh, n));
        }
    }
}
