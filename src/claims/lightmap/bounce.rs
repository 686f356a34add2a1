//! Self-bounce against an independent quadrature (hemispherical-lighting talk, "surface
//! self-bounce"; claim H10).
//!
//! The `self_bounce` effect's reference adds ρ·I_z·(1 − H(n′)) with H(n′) = (1 + n′·N)/2 and
//! I_z the exact E/π at N from the row moments (`runner::CaseData`); `with_self_bounce` adds the
//! same term with its inner fit's own value at N. For HHD, whose I_z is exact, the two agree
//! by construction, so the table of errors alone cannot tell whether the reference's bounce is
//! right. This module computes the bounce on a path that shares nothing with either: I_z as a
//! direct quadrature of the map's texels,
//!
//! I_z = (1/π) Σ_texels L_texel ∫_cell max(0, ω·N) dω,
//!
//! each cell integrated by a [`NODES`]×[`NODES`] Gauss–Legendre product rule in azimuth and
//! polar angle (with the sin φ of the solid angle), then ρ·I_z·(1 − H(n′)) at every normal of
//! the case's grid. Where N's horizon runs along texel edges (the six axes of a lat-long map
//! whose width is a multiple of 4) the integrand is smooth on every cell and the rule is exact
//! to ~1e-12; elsewhere the kink of max(0, ·) in a cell costs more.
//!
//! Per map, case and source of the term (the reference, and each encoder of the experiment
//! whose term is not zero): `iz_rel_err` = max over channels of |I_z used − I_z by texels| /
//! the largest channel of I_z by texels; `bounce_max_rel_err` = max over normals and channels
//! of |term added − ρ·I_z·(1 − H)| / (ρ × the largest channel of I_z by texels), the
//! reference's over every [`REFERENCE_STRIDE`]-th normal of the grid, an encoder's over all.

use crate::claims::measure::Measure;
use crate::envmap::search::SearchPath;
use crate::envmap::EnvMap;
use crate::math::colour::Rgb;
use crate::math::convention::direction;
use crate::math::quadrature::gauss_legendre;
use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::{cases, evaluate, Case, CaseData, MapData};
use anyhow::{Context, Result};
use glam::DVec3;
use rayon::prelude::*;

/// The `self_bounce_quadrature` table: the self-bounce experiment `exp` on each of its maps
/// (loaded through `search`, in its order), per orientation, albedo and term.
pub fn measure(search: &SearchPath, exp: &Experiment) -> Result<Measure> {
    let (w, h) = exp.resolution;
    let mut m = Measure::new(
        "self_bounce_quadrature",
        &format!(
            "claim H10, the self-bounce term against an independent quadrature of the bounce \
             (src/claims/lightmap/bounce.rs): per map, N (domain), albedo (effects) and source of the term (encoder: \
             reference = what the self_bounce effect adds to the exact reference; otherwise a with_self_bounce encoder \
             of experiments/{}.toml), against rho*I_z*(1 - H(n')) with I_z = (1/pi) sum over texels of L times the \
             cell integral of max(0, w.N) ({NODES}x{NODES} Gauss-Legendre per texel), over the hemisphere about N \
             ({w}x{} normals; the reference's term on every {REFERENCE_STRIDE}th); iz_quadrature, iz_used (E/pi, channels' mean); iz_rel_err, bounce_max_rel_err: largest \
             errors relative to I_z by texels (times rho)",
            exp.name,
            h / 2
        ),
        &[
            "map",
            "encoder",
            "domain",
            "effects",
            "metric",
            "albedo",
            "iz_quadrature",
            "iz_used",
            "iz_rel_err",
            "bounce_max_rel_err",
            "reference",
            "resolution",
            "units",
        ],
    );
    for name in &exp.maps {
        let map = search.load(name).with_context(|| format!("claims self_bounce_quadrature ({})", exp.name))?;
        for r in map_bounces(exp, &map) {
            m.row(vec![
                name.into(),
                r.source.into(),
                r.domain.into(),
                r.effects.into(),
                "bounce_quadrature".into(),
                r.albedo.into(),
                r.iz_quadrature.into(),
                r.iz_used.into(),
                r.iz_rel_err.into(),
                r.bounce_max_rel_err.into(),
                format!("I_z by texel quadrature ({NODES}x{NODES} GL per texel)").into(),
                format!("{w}x{}", h / 2).into(),
                "E/pi (iz_quadrature, iz_used); relative (iz_rel_err, bounce_max_rel_err)".into(),
            ]);
        }
    }
    Ok(m)
}

/// Gauss–Legendre nodes per texel side of the texel quadrature.
pub const NODES: usize = 4;

/// The reference's term is compared on every `REFERENCE_STRIDE`-th normal of the grid (its two
/// evaluations under the caps are what the table costs; the term is linear in n′).
pub const REFERENCE_STRIDE: usize = 16;

/// The source of a term compared: the reference's bounce or an encoder's.
pub const REFERENCE: &str = "reference";

/// One term against the independent bounce on one case.
#[derive(Clone, Debug, PartialEq)]
pub struct BounceCheck {
    /// The case's domain label, `hemisphere:<N>`.
    pub domain: String,
    /// The case's effects label (with the albedo).
    pub effects: String,
    /// The albedo ρ.
    pub albedo: f64,
    /// [`REFERENCE`] or the encoder's name.
    pub source: String,
    /// I_z by texel quadrature, the channels' mean (E/π).
    pub iz_quadrature: f64,
    /// The I_z the term used, the channels' mean (E/π): the reference's exact I_z, or the
    /// encoder's own value at N.
    pub iz_used: f64,
    /// max over channels |I_z used − I_z by texels| / max channel of I_z by texels.
    pub iz_rel_err: f64,
    /// max over normals and channels |term − ρ·I_z·(1 − H)| / (ρ · max channel of I_z by texels).
    pub bounce_max_rel_err: f64,
}

/// I_z = (1/π)∫ L(ω) max(0, ω·n) dω by a [`NODES`]² Gauss–Legendre rule on every texel cell
/// (azimuth θ, polar angle φ, dω = sin φ dφ dθ), straight from the texels.
pub fn iz_by_texels(map: &EnvMap, n: DVec3) -> Rgb {
    let g = map.grid();
    let rule = gauss_legendre(NODES);
    let nodes = |a: f64, b: f64| -> Vec<(f64, f64)> {
        rule.iter().map(|&(x, w)| (0.5 * (a + b) + 0.5 * (b - a) * x, 0.5 * (b - a) * w)).collect()
    };
    let mut total = Rgb::ZERO;
    for j in 0..g.height {
        let phis = nodes(g.phi_edge(j), g.phi_edge(j + 1));
        let mut row = Rgb::ZERO;
        for i in 0..g.width {
            let mut cell = 0.0;
            for (theta, wt) in nodes(g.theta_edge(i), g.theta_edge(i + 1)) {
                for &(phi, wp) in &phis {
                    cell += wt * wp * phi.sin() * direction(theta, phi).dot(n).max(0.0);
                }
            }
            let t = map.texel(i, j);
            row += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64) * cell;
        }
        total += row;
    }
    total / std::f64::consts::PI
}

/// The cases of `exp` with a surface normal and an albedo (the `self_bounce` effect).
pub fn bounce_cases(exp: &Experiment) -> Vec<Case> {
    cases(exp).into_iter().filter(|c| c.normal.is_some() && c.albedo.is_some()).collect()
}

/// Every term of `exp` on `map` against the independent bounce, per case of [`bounce_cases`]
/// (in parallel, collected in order): the reference's, then each encoder's whose term is not 0.
pub fn map_bounces(exp: &Experiment, map: &EnvMap) -> Vec<BounceCheck> {
    let data = MapData::new(map);
    let all = bounce_cases(exp);
    all.par_iter().map(|case| case_bounces(exp, &data, case)).collect::<Vec<_>>().into_iter().flatten().collect()
}

/// One case: the reference's term (its value with the effect minus without) and each
/// encoder's (its fit with the albedo minus without), against ρ·I_z·(1 − H) with I_z by texels.
fn case_bounces(exp: &Experiment, data: &MapData, case: &Case) -> Vec<BounceCheck> {
    let (Some(n), Some(rho)) = (case.normal, case.albedo) else { return Vec::new() };
    let cd = CaseData::new(data, case, exp.polar_nodes);
    let grid = case.domain.output_grid(exp.resolution);
    let iz = iz_by_texels(data.map, n);
    let want: Vec<Rgb> = grid.normals.iter().map(|m| iz * (rho * 0.5 * (1.0 - m.dot(n)))).collect();
    let check = |source: &str, used: Rgb, term: &[Rgb], want: &[Rgb]| BounceCheck {
        domain: case.domain_label.clone(),
        effects: case.effects_label.clone(),
        albedo: rho,
        source: source.into(),
        iz_quadrature: iz.element_sum() / 3.0,
        iz_used: used.element_sum() / 3.0,
        iz_rel_err: rel((used - iz).abs().max_element(), iz.max_element()),
        bounce_max_rel_err: rel(
            term.iter().zip(want).map(|(t, w)| (*t - *w).abs().max_element()).fold(0.0, f64::max),
            rho * iz.max_element(),
        ),
    };
    // The reference twice under the caps is the cost: every REFERENCE_STRIDE-th normal.
    let sub: Vec<DVec3> = grid.normals.iter().step_by(REFERENCE_STRIDE).copied().collect();
    let want_sub: Vec<Rgb> = want.iter().step_by(REFERENCE_STRIDE).copied().collect();
    let with = cd.reference_many(&sub);
    let plain = cd.reference.irradiance_many(&sub);
    let added: Vec<Rgb> = with.iter().zip(&plain).map(|(a, b)| *a - *b).collect();
    let used = cd.inputs.exact_at_normal.unwrap_or(Rgb::ZERO);
    let mut out = vec![check(REFERENCE, used, &added, &want_sub)];
    let input = cd.fit_input();
    let without = crate::encoders::encoder::FitInput { surface_albedo: None, ..input };
    for named in &exp.encoders {
        let (a, b) = (named.encoder.fit(&input), named.encoder.fit(&without));
        let term: Vec<Rgb> = evaluate(a.as_ref(), &grid.normals)
            .iter()
            .zip(evaluate(b.as_ref(), &grid.normals))
            .map(|(x, y)| *x - y)
            .collect();
        if term.iter().any(|t| *t != Rgb::ZERO) {
            out.push(check(&named.name, b.irradiance(n), &term, &want));
        }
    }
    out
}

/// `err / scale`, or `err` itself where the scale is 0 (a dark map: the bounce is 0).
fn rel(err: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        err / scale
    } else {
        err
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The texel quadrature against closed forms: a constant map A gives I_z = A (the
    /// hemisphere's (1/π)∫ cos = 1) at any N; a map lit only above the horizon of +y (radiance
    /// A on the upper half) gives A facing up, 0 facing down and A/2 facing sideways.
    #[test]
    fn texel_quadrature_matches_closed_forms() {
        let (w, h) = (64, 32);
        let a = 0.625f32;
        let constant = EnvMap::new("c", w, h, vec![[a; 3]; w * h]).unwrap();
        let upper = EnvMap::new("u", w, h, (0..w * h).map(|i| if i / w < h / 2 { [a; 3] } else { [0.0; 3] }).collect())
            .unwrap();
        let a = a as f64;
        for n in [DVec3::X, DVec3::Y, -DVec3::Z, DVec3::new(0.3, -0.5, 0.8).normalize()] {
            let got = iz_by_texels(&constant, n);
            // Off the axes N's horizon crosses cells, where the kink costs ~1e-5.
            let tol = if n.abs().max_element() == 1.0 { 1e-12 } else { 1e-4 };
            assert!((got - Rgb::splat(a)).abs().max_element() < tol, "{n}: {got}");
        }
        for (n, want) in [(DVec3::Y, a), (-DVec3::Y, 0.0), (DVec3::X, 0.5 * a), (DVec3::Z, 0.5 * a)] {
            let got = iz_by_texels(&upper, n);
            assert!((got - Rgb::splat(want)).abs().max_element() < 1e-12, "{n}: {got} vs {want}");
        }
    }

    /// On a map with structure (a bright patch over a gradient), the reference's bounce and
    /// the HHD wrapper's term agree with the independent bounce to the reference's quadrature,
    /// and an SH L2 term (whose value at N carries band 2, so is not I_z) does not.
    #[test]
    fn reference_and_hhd_terms_match_the_independent_bounce() {
        let (w, h) = (64, 32);
        let map = EnvMap::from_fn("patch", w, h, |i, j| {
            let base = 0.1 + 0.02 * j as f32;
            if (10..16).contains(&i) && (6..10).contains(&j) {
                [8.0, 6.0, 4.0]
            } else {
                [base, base * 0.8, 0.3]
            }
        })
        .unwrap();
        let text = "maps = ['patch']\nencoders = ['hhd_search_hemi', { kind = 'with_self_bounce', name = 'hhd+b', \
                    inner = 'hhd_search_hemi' }, { kind = 'with_self_bounce', name = 'sh2+b', inner = 'sh2' }]\n\
                    domain = 'hemisphere'\norientations = ['axes6']\nresolution = [32, 16]\npolar_nodes = 8\n\
                    effects = ['hemisphere', { kind = 'self_bounce', albedo = [0.8] }]\n";
        let exp = Experiment::parse(text, Path::new("b.toml")).unwrap();
        let rows = map_bounces(&exp, &map);
        assert_eq!(rows.len(), 6 * 3, "{rows:#?}");
        for r in &rows {
            match r.source.as_str() {
                REFERENCE | "hhd+b" => {
                    assert!(r.iz_rel_err < 1e-8 && r.bounce_max_rel_err < 1e-8, "{r:?}");
                }
                "sh2+b" => {}
                s => panic!("unexpected source {s}"),
            }
        }
        let sh2 = rows.iter().filter(|r| r.source == "sh2+b").map(|r| r.bounce_max_rel_err).fold(0.0, f64::max);
        assert!(sh2 > 1e-3, "{sh2}");
    }
}
