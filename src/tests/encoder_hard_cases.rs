//! The catalogue of hard cases: named scenes that push encoders to divide by d_z, by
//! L00 and by |L1|, take square roots of discriminants and normalise vectors that can be zero.
//! Every encoder of `encoders::REGISTRY` (default settings) and every encoder
//! configuration declared in `experiments/*.toml` runs on every case; an encoder added to the
//! registry or a variant added to an experiment joins automatically (this file names none).
//!
//! Each case is built analytically (closed-form SH of ambient, delta and cap lights, visible
//! under the surface's effects, and closed-form E/π; `reference::lighting`, with the
//! surfaces of `common.rs`), and fitted through
//! `FitInput` with or without a surface normal and cone, as the case says. A second test feeds
//! tiny maps with the same kind of trouble through the whole pipeline (projection, reference,
//! metrics, CSV).
//!
//! # What every encoder must satisfy (the contract; also in `Encoder`'s docs)
//!
//! On every case, for every encoder:
//! 1. **Finite.** Every output on the sphere of normals and every diagnostic is finite.
//! 2. **Black in, black out.** If the probe is black, the output is exactly zero everywhere.
//! 3. **Sanity bound.** On the case's domain (the sphere for a probe, the hemisphere about N
//!    for a surface), rmse ≤ RMS(E_vis) + RMS(E_probe): no worse than the worse of the two
//!    trivial answers, black (error RMS(E_vis)) and the unoccluded irradiance (error at most
//!    RMS(E_probe − E_vis) ≤ RMS(E_probe) + RMS(E_vis), triangle inequality). E_vis is the
//!    irradiance of the light that reaches the surface, E_probe of all of it. This is loose: it
//!    catches a fit that blows up, not a merely poor one.
//! 4. **Degenerate cases fall back to pure ambient.** Where the lighting has no usable
//!    direction (black, constant, L1 = 0, |L1| = 1e-300 that squares to zero), the documented
//!    fallback is pure ambient: the mean radiance, i.e. the band-0 answer. So the sphere rmse is
//!    no worse than that of the band-0 SH projection; an encoder that keeps more (an L2 band, a
//!    zonal term fitted by least squares from that start) is no worse either.
//!
//! And where the encoder promises it (`Encoder` promise methods):
//! 5. `sphere_error_at_most_sh() == Some(l)`: sphere rmse against E_vis ≤ that of the SH
//!    projection of the visible radiance through band l (computed from its definition here,
//!    `Sh9::truncate` + `convolve_cosine`, not through any encoder).
//! 6. `is_scale_covariant()`: fit(k·input) = k·fit(input) at every third normal of the grid
//!    (`SCALE_STRIDE`: every output is smooth on a far larger scale), k = 1e-30, 0.37,
//!    3.7e5, 1e30 (each where k times the input's smallest and largest non-zero coefficient
//!    stays a normal f64), to 1e-7 of the largest output.
//! 7. `promises_non_negative()`: every output on the sphere of normals is ≥ 0.
//!
//! # Tolerances
//!
//! Errors are computed on the 128×64 lat-long output grid (pixel centres, exact cell solid
//! angles), on values divided by the case's scale so nothing under- or overflows when squared.
//! Bounds 4 and 5 compare two least-squares answers on a discrete grid: if f minimises the
//! continuous error over a family containing g, its grid error can exceed g's only through the
//! grid's quadrature error ε in the cross term, by at most about 4ε² relative in the squared
//! error (see `least_squares_on_a_grid_tolerance`). With ε ≈ 1e-3 at this resolution, 1e-5
//! relative is a generous bound, and 1e-9 (of the scale) absolute covers answers that are
//! exact to rounding.

use super::common::*;
use super::hard_case_catalogue::*;
use crate::encoders::encoder::{Encoder, Fitted};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::reference::domain::{Domain, OutputGrid};
use glam::DVec3;
use std::f64::consts::PI;

/// Output grid of the checks.
const RES: (usize, usize) = (128, 64);
/// Relative and absolute (in units of the case's scale) slack of least-squares bounds.
const LSQ_REL: f64 = 1e-5;
const LSQ_ABS: f64 = 1e-9;
/// Scale covariance: relative to the largest output.
const SCALE_TOL: f64 = 1e-7;
/// Scale covariance is compared at every third normal of the output grid (2731 of 8192: every
/// row, every third column, the columns shifting by one each row since 128 = 3·42 + 2), about
/// 8.4° apart in azimuth and 2.8° in polar angle. The identity is pointwise between two fits of
/// the same encoder, and every output is smooth on a far larger scale (the sharpest lobes are
/// the spherical Gaussians' λ = 6 radiance lobes, about 23° wide, and irradiance is their
/// cosine-convolved, smoother form), so a scale-dependent branch, offset or lobe shows at these
/// normals as it does at all of them; the maximum it is measured against stays that of the
/// whole grid. Comparing 4 scales at every normal was about a third of this test's CPU time.
const SCALE_STRIDE: usize = 3;

/// Whether k times the input keeps every non-zero coefficient a normal f64 (with room for a
/// few products).
fn scale_in_range(sh: &Sh9, k: f64) -> bool {
    let vals = sh.0.iter().flat_map(|c| c.to_array()).filter(|v| *v != 0.0).map(f64::abs);
    vals.clone().all(|v| v * k > 1e-250) && vals.clone().all(|v| v * k < 1e250)
}

/// What every encoder's check of one case shares, computed once per case: the case's input
/// (after its tweak), its grids and scale, and the closed-form E/π on them. Each is a function
/// of the case alone (the same calls on the same case), so sharing it moves no number a check
/// compares; it only saves recomputing them for each of the encoders.
struct Prepared<'a> {
    case: &'a Case,
    /// The case's input, after its tweak.
    input: Input,
    sphere: OutputGrid,
    /// The case's domain: the sphere for a probe, the hemisphere about N for a surface.
    domain: OutputGrid,
    /// Whether the domain is the sphere (a probe): the fit's values on it are then those on
    /// `sphere`.
    domain_is_sphere: bool,
    /// The case's scale: the largest unoccluded E/π on the sphere (1 for black).
    scale: f64,
    /// E/π of the visible light on the sphere, and of the visible and of all the light on the
    /// domain.
    e_vis_sphere: Vec<Rgb>,
    e_vis_domain: Vec<Rgb>,
    e_probe_domain: Vec<Rgb>,
}

impl<'a> Prepared<'a> {
    fn new(case: &'a Case) -> Self {
        let mut input = Input::new(&case.lighting, case.surface.as_ref());
        if let Some(t) = case.tweak {
            t(&mut input);
        }
        let sphere = Domain::Sphere.output_grid(RES);
        let domain_is_sphere = input.domain() == Domain::Sphere;
        let domain = input.domain().output_grid(RES);
        let on = |grid: &OutputGrid, l: &crate::reference::lighting::Lighting| -> Vec<Rgb> {
            grid.normals.iter().map(|&n| l.irradiance(n)).collect()
        };
        let scale = match max_abs(&on(&sphere, &input.probe)) {
            s if s > 0.0 => s,
            _ => 1.0,
        };
        let e_vis_sphere = on(&sphere, &input.visible);
        let (e_vis_domain, e_probe_domain) = (on(&domain, &input.visible), on(&domain, &input.probe));
        Prepared { case, input, sphere, domain, domain_is_sphere, scale, e_vis_sphere, e_vis_domain, e_probe_domain }
    }
}

/// One case fitted by one encoder: what the rules of the contract look at.
struct FittedCase<'a> {
    /// The case, prepared once for every encoder.
    p: &'a Prepared<'a>,
    enc: &'a dyn Encoder,
    fit: Box<dyn Fitted>,
    /// The fit on the sphere of normals.
    out_sphere: Vec<Rgb>,
}

impl<'a> FittedCase<'a> {
    fn new(p: &'a Prepared<'a>, enc: &'a dyn Encoder) -> Self {
        let fit = enc.fit(&p.input.fit_input());
        let out_sphere = eval(fit.as_ref(), &p.sphere);
        FittedCase { p, enc, fit, out_sphere }
    }
}

/// Runs every check of the contract for one case and one encoder; returns failure messages.
fn check(p: &Prepared, id: &str, enc: &dyn Encoder) -> Vec<String> {
    let f = FittedCase::new(p, enc);
    let mut fails = Vec::new();
    // 1. Finite: a non-finite output ends the checks (the bounds would compare NaNs).
    if let Some(m) = non_finite_output(&f) {
        fails.push(m);
    } else {
        fails.extend(non_finite_diagnostics(&f));
        fails.extend(black_in_black_out(&f));
        fails.extend(sanity_bound(&f));
        fails.extend(least_squares_bounds(&f));
        fails.extend(scale_covariance(&f));
        fails.extend(non_negative(&f));
    }
    fails.into_iter().map(|m| format!("{id} on {} ({}): {m}", p.case.name, p.case.why)).collect()
}

/// 1. Finite: the first non-finite output on the sphere of normals.
fn non_finite_output(f: &FittedCase) -> Option<String> {
    let (k, v) = f.out_sphere.iter().enumerate().find(|(_, v)| !v.is_finite())?;
    Some(format!("non-finite output {v} at normal {}", f.p.sphere.normals[k]))
}

/// 1. Finite: every non-finite diagnostic.
fn non_finite_diagnostics(f: &FittedCase) -> Vec<String> {
    f.fit
        .diagnostics()
        .into_iter()
        .filter(|(_, v)| !v.is_finite())
        .map(|(name, v)| format!("non-finite diagnostic {name} = {v}"))
        .collect()
}

/// 2. Black in, black out.
fn black_in_black_out(f: &FittedCase) -> Option<String> {
    let input = &f.p.input;
    if input.probe_sh == Sh9::ZERO && input.exact_at_normal.is_none_or(|v| v == Rgb::ZERO) {
        let m = max_abs(&f.out_sphere);
        if m != 0.0 {
            return Some(format!("black input gives output up to {m:e}"));
        }
    }
    None
}

/// 3. Sanity bound on the case's domain.
fn sanity_bound(f: &FittedCase) -> Option<String> {
    let (p, domain, scale) = (f.p, &f.p.domain, f.p.scale);
    let evaluated;
    let out_domain = if p.domain_is_sphere {
        &f.out_sphere
    } else {
        evaluated = eval(f.fit.as_ref(), domain);
        &evaluated
    };
    let rmse = rmse_scaled(&p.e_vis_domain, out_domain, domain, scale);
    let sanity = rms_scaled(&p.e_vis_domain, domain, scale) + rms_scaled(&p.e_probe_domain, domain, scale);
    (rmse > sanity * (1.0 + LSQ_REL) + LSQ_ABS).then(|| {
        format!("rmse {rmse:e} above the sanity bound {sanity:e} (RMS of E_vis + E_probe), in units of {scale:e}")
    })
}

/// 4 and 5: the sphere error against the visible irradiance, bounded by the SH projections'
/// errors: for a degenerate case by the pure-ambient (band 0) answer, and where promised by the
/// projection through band l.
fn least_squares_bounds(f: &FittedCase) -> Vec<String> {
    let (input, sphere, scale) = (&f.p.input, &f.p.sphere, f.p.scale);
    let mut fails = Vec::new();
    let e_vis_sphere = &f.p.e_vis_sphere;
    let sphere_rmse = rmse_scaled(e_vis_sphere, &f.out_sphere, sphere, scale);
    let sh_rmse = |l: usize| {
        let p = sh_projection(input, l);
        let v: Vec<Rgb> = sphere.normals.iter().map(|&n| p.eval(n)).collect();
        rmse_scaled(e_vis_sphere, &v, sphere, scale)
    };

    // 4. Degenerate cases: no worse than pure ambient.
    if f.p.case.degenerate && !f.enc.degrades_input() {
        let ambient = sh_rmse(0);
        if sphere_rmse > ambient * (1.0 + LSQ_REL) + LSQ_ABS {
            fails.push(format!(
                "no usable direction, yet sphere rmse {sphere_rmse:e} exceeds the pure-ambient fallback's {ambient:e}"
            ));
        }
    }

    // 5. Promised: no worse than the SH projection through band l.
    if let Some(l) = f.enc.sphere_error_at_most_sh() {
        let bound = sh_rmse(l);
        if sphere_rmse > bound * (1.0 + LSQ_REL) + LSQ_ABS {
            fails.push(format!("promises sphere rmse <= SH L{l} ({bound:e}) but has {sphere_rmse:e}"));
        }
    }
    fails
}

/// 6. Promised: scale covariance, at every k that keeps the input's coefficients normal.
fn scale_covariance(f: &FittedCase) -> Vec<String> {
    let mut fails = Vec::new();
    if !f.enc.is_scale_covariant() {
        return fails;
    }
    let (input, sphere) = (&f.p.input, &f.p.sphere);
    for k in [1e-30, 0.37, 3.7e5, 1e30] {
        if !scale_in_range(&input.probe_sh, k) || !scale_in_range(&input.visible_sh, k) {
            continue;
        }
        let scaled = input.scaled(k);
        let fk = f.enc.fit(&scaled.fit_input());
        let m = max_abs(&f.out_sphere);
        let worst = sphere
            .normals
            .iter()
            .zip(&f.out_sphere)
            .step_by(SCALE_STRIDE)
            .map(|(&n, v)| ((fk.irradiance(n) / k) - *v).abs().max_element())
            .fold(0.0, f64::max);
        if worst.is_nan() || worst > SCALE_TOL * m {
            fails.push(format!(
                "scale covariance: fit(k x)/k differs from fit(x) by {worst:e} (max output {m:e}) at k = {k:e}"
            ));
        }
    }
    fails
}

/// 7. Promised: non-negative.
fn non_negative(f: &FittedCase) -> Option<String> {
    if !f.enc.promises_non_negative() {
        return None;
    }
    let (k, v) = f.out_sphere.iter().enumerate().find(|(_, v)| v.min_element() < 0.0)?;
    Some(format!("promises non-negative output but gives {v} at normal {}", f.p.sphere.normals[k]))
}

#[test]
fn every_encoder_survives_every_hard_case() {
    let encoders = all_encoders();
    assert!(encoders.len() >= crate::encoders::REGISTRY.len());
    let cases = cases();
    // Cases in parallel (rayon), each prepared once for every encoder; the failures are
    // gathered in the order of the cases, then of the encoders, as a loop would list them.
    use rayon::prelude::*;
    let per_case: Vec<Vec<String>> = cases
        .par_iter()
        .map(|c| {
            let p = Prepared::new(c);
            encoders.iter().flat_map(|(id, e)| check(&p, id, e.as_ref())).collect()
        })
        .collect();
    let fails: Vec<String> = per_case.concat();
    assert!(fails.is_empty(), "{} failure(s):\n{}", fails.len(), fails.join("\n"));
}

/// The tolerance argument above needs the grid's quadrature error ε on products of smooth
/// functions to be ~1e-3: the Gram matrix of the SH basis on the 128×64 grid is the identity to
/// that accuracy (independent check: the basis is orthonormal on the sphere).
#[test]
fn least_squares_on_a_grid_tolerance() {
    let g = Domain::Sphere.output_grid(RES);
    let mut gram = [[0.0f64; 9]; 9];
    for (n, w) in g.normals.iter().zip(&g.weights) {
        let y = crate::math::sh::basis(*n);
        for a in 0..9 {
            for b in 0..9 {
                gram[a][b] += w * y[a] * y[b];
            }
        }
    }
    let eps = (0..81).map(|k| (gram[k / 9][k % 9] - if k / 9 == k % 9 { 1.0 } else { 0.0 }).abs()).fold(0.0, f64::max);
    assert!(eps < 1e-3, "{eps}");
    // 4ε² relative in the squared error is ~2ε² in the rmse: far below LSQ_REL.
    assert!(2.0 * eps * eps < LSQ_REL);
}

/// The cases are what they claim to be, checked from their SH (so the catalogue cannot rot
/// into easy cases).
#[test]
fn cases_have_the_claimed_trouble() {
    let by_name = |n: &str| {
        let c = cases().into_iter().find(|c| c.name == n).unwrap_or_else(|| panic!("no case {n}"));
        let mut i = Input::new(&c.lighting, c.surface.as_ref());
        if let Some(t) = c.tweak {
            t(&mut i);
        }
        i
    };
    let l1 = |sh: &Sh9, c: usize| sh.l1_vector(c);
    // L1 = 0 exactly for the opposite pair; L1 = L2 = 0 for the octahedron (to rounding).
    let two = by_name("two_opposite");
    assert!((0..3).all(|c| l1(&two.probe_sh, c).length() < 1e-16));
    let oct = by_name("octahedron");
    assert!((1..9).all(|i| oct.probe_sh[i].abs().max_element() < 1e-15));
    // Hallucination ratio r = |L1|/L00 (FORMULAS §5) of a single light: √3 (physical maximum);
    // past it by rounding; ~0 for the faint light.
    let r = |i: &Input| l1(&i.probe_sh, 0).length() / i.probe_sh[0].x;
    assert!((r(&by_name("ratio_r_sqrt3")) - 3f64.sqrt()).abs() < 1e-15);
    assert!(r(&by_name("ratio_r_past_sqrt3")) > 3f64.sqrt());
    assert!(r(&by_name("ratio_r_to_0")) < 1e-9);
    // |L1|² underflows to 0 in the 1e-300 cases.
    for n in ["l1_1e-300", "tiny_light_1e-300"] {
        let v = l1(&by_name(n).probe_sh, 0);
        assert!(v != DVec3::ZERO && v.length_squared() == 0.0, "{n}");
    }
    // The horizon light is visible and perpendicular to N: d_z = 0 exactly.
    let hz = by_name("irradz_dz_zero@hemisphere");
    let d = hz.visible.0.iter().find_map(|l| if let Light::Delta { dir, .. } = l { Some(*dir) } else { None });
    assert_eq!(d.map(|d| d.dot(UP)), Some(0.0));
    assert!(by_name("delta_below@hemisphere").visible_sh == Sh9::ZERO);
    assert!(by_name("delta_below@hemisphere").probe_sh != Sh9::ZERO);
    // HHD from linear SH (FORMULAS §8): the discriminant, from the SH and the exact I_z.
    let h = by_name("hhd_negative_discriminant@bare");
    let b_c = 2.0 / PI.sqrt() * h.visible_sh[0].x;
    let b = 2.0 / PI.sqrt() * l1(&h.visible_sh, 0) / 3f64.sqrt();
    let i_z = h.exact_at_normal.unwrap().x;
    assert!((i_z - b.dot(UP) - 1.0).abs() < 1e-12, "I_z exceeds b.N by the ambient");
    let disc = (2.0 * b_c - i_z).powi(2) - 3.0 * (b_c * b_c - b.length_squared());
    assert!((disc + 8.0).abs() < 1e-9, "{disc}");
    // The hemisphere light sits exactly on the discriminant's zero.
    let hl = by_name("constant@hemisphere");
    let (b_c, b) = (2.0 / PI.sqrt() * hl.visible_sh[0].x, 2.0 / PI.sqrt() * l1(&hl.visible_sh, 0) / 3f64.sqrt());
    let i_z = hl.exact_at_normal.unwrap().x;
    assert!(((2.0 * b_c - i_z).powi(2) - 3.0 * (b_c * b_c - b.length_squared())).abs() < 1e-12);
    // The 1e-12 cone lets through only its centre light and a sliver of sky of solid angle
    // 2π(1 − cos α) = 2π·1e-12.
    let cone = by_name("cone_cos_1e-12@cone");
    assert!(
        (cone.visible_sh[0].x - (crate::math::sh::k::Y00 * PI + 2.0 * PI * 1e-12 * crate::math::sh::k::Y00)).abs()
            < 1e-15
    );
    // The scaled cases are the sun and sky scaled.
    let base = Lighting(sun_sky()).sh()[0].x;
    assert!((by_name("scale_1e+30").probe_sh[0].x / (base * 1e30) - 1.0).abs() < 1e-15);
    assert!((by_name("scale_1e-30").probe_sh[0].x / (base * 1e-30) - 1.0).abs() < 1e-15);
}

/// The pure-ambient fallback bound is the error of the mean: for two opposite lights ±x, E/π =
/// |n·x|/π·π = |n_x|, whose mean is ½, so the fallback's sphere rmse is √(⟨n_x²⟩ − ¼) =
/// √(1/3 − 1/4) = √(1/12) (in units of the scale, max E/π = 1).
#[test]
fn fallback_bound_is_the_error_of_the_mean() {
    let c = cases().into_iter().find(|c| c.name == "two_opposite").unwrap();
    let i = Input::new(&c.lighting, None);
    let g = Domain::Sphere.output_grid(RES);
    let truth: Vec<Rgb> = g.normals.iter().map(|&n| i.visible.irradiance(n)).collect();
    let p = sh_projection(&i, 0);
    let amb: Vec<Rgb> = g.normals.iter().map(|&n| p.eval(n)).collect();
    assert!((amb[0].x - 0.5).abs() < 1e-15);
    let e = rmse_scaled(&truth, &amb, &g, 1.0);
    assert!((e - (1.0f64 / 12.0).sqrt()).abs() < 1e-4, "{e}");
}

/// Tiny maps with the same trouble, through the whole pipeline (projection, exact reference,
/// metrics, CSV) for every registered encoder, on the sphere (both metrics; every encoder that
/// does not need a surface normal) and on hemispheres about the six axes under the hemisphere
/// and cone effects (cos α up to 1 − 1e-12): every score is finite and the table never says
/// "nonfinite". The brightest texel is the loader's bound ([`MAX_TEXEL`]); one above it is
/// refused when the map is made.
#[test]
fn tiny_hard_maps_score_finite_through_the_pipeline() {
    use crate::envmap::EnvMap;
    use crate::envmap::MAX_TEXEL;
    use crate::pipeline::experiment::Experiment;
    use std::path::Path;
    let quoted = |e: &[(String, Box<dyn crate::encoders::encoder::Encoder>)]| {
        e.iter().map(|(id, _)| format!("'{id}'")).collect::<Vec<_>>().join(", ")
    };
    let all = registry_encoders();
    let sphere: Vec<_> = registry_encoders().into_iter().filter(|(_, e)| !e.needs_surface_normal()).collect();
    let (ids, sphere_ids) = (quoted(&all), quoted(&sphere));
    let exps = [
        format!("maps = ['x']\nencoders = [{sphere_ids}]\nmetrics = ['exact', 'probulator']\nresolution = [16, 8]\n"),
        format!(
            "maps = ['x']\nencoders = [{ids}]\ndomain = 'hemisphere'\norientations = ['axes6']\nresolution = [16, 8]\n\
             effects = ['hemisphere', {{ kind = 'cone', cos_alpha = [0.5, 0.999999999999], tilt_deg = [0, 30] }}]\n"
        ),
    ];
    let map = |name: &str, w: usize, f: &dyn Fn(usize, usize) -> [f32; 3]| EnvMap::from_fn(name, w, w / 2, f).unwrap();
    let maps = [
        map("black", 8, &|_, _| [0.0; 3]),
        map("constant", 8, &|_, _| [0.5, 1.0, 2.0]),
        map("smallest_2x1", 2, &|i, _| [i as f32, 1.0, 0.0]),
        map("green_zero", 16, &|i, j| [(i + j) as f32 * 0.1, 0.0, 0.3]),
        map("sun_1e6", 16, &|i, j| if (i, j) == (5, 2) { [1e6; 3] } else { [1.0; 3] }),
        map("at_the_texel_bound", 16, &|i, j| if (i, j) == (3, 3) { [MAX_TEXEL; 3] } else { [0.0; 3] }),
        map("all_1e-30", 16, &|_, _| [1e-30; 3]),
        map("subnormal", 16, &|i, j| if (i, j) == (9, 6) { [1e-45; 3] } else { [0.0; 3] }),
        map("horizon_row", 16, &|_, j| if j == 3 { [4.0, 2.0, 1.0] } else { [0.0; 3] }),
    ];
    let above = EnvMap::from_fn("near_f32_max", 16, 8, &|i, j| if (i, j) == (3, 3) { [3e38; 3] } else { [0.0; 3] });
    assert!(above.is_err(), "a texel of 3e38 (above the bound {MAX_TEXEL:e}) is refused when the map is made");
    // No timing pass: it runs after scoring and never touches a score (ARCHITECTURE.md,
    // "Timing never touches the numbers"); here it would repeat every fit 5 to 15 times.
    let settings = crate::pipeline::settings::RunSettings { timing: false, ..Default::default() };
    for text in &exps {
        let exp = Experiment::parse(text, Path::new("hard.toml")).unwrap();
        for m in &maps {
            let rows = crate::pipeline::runner::run_map(&exp, m, &settings);
            assert!(!rows.is_empty());
            for r in &rows {
                let s = &r.scores;
                let all = [s.rmse_rgb[0], s.rmse_rgb[1], s.rmse_rgb[2], s.rmse, s.rel_rmse, s.neg_frac, s.max_abs];
                assert!(
                    all.iter().all(|v| v.is_finite()),
                    "{} {} {} {}: {s:?}",
                    m.name,
                    r.encoder,
                    r.domain,
                    r.effects
                );
            }
            let csv = String::from_utf8(crate::pipeline::table::to_csv(&rows).unwrap()).unwrap();
            assert!(!csv.contains("nonfinite"), "{}: {csv}", m.name);
        }
    }
}

/// The contract can fail: deliberately broken encoders, each breaking one rule, are caught.
mod broken {
    use super::*;
    use crate::encoders::encoder::{Encoder, FitInput, Fitted};

    #[derive(Clone, Copy, PartialEq, Debug)]
    pub enum Flaw {
        /// Normalises L1 without a guard (NaN when L1 = 0).
        NaiveNormalise,
        /// SH L1 plus a constant 1e-3, claiming scale covariance.
        Offset,
        /// SH L1 claiming non-negativity.
        ClaimsNonNegative,
        /// SH L0 claiming to be at least as good as SH L1.
        ClaimsL1Bound,
        /// With no L1 direction, puts all the light along +z instead of falling back to ambient.
        BadFallback,
    }

    pub struct Broken(pub Flaw);
    struct F(Box<dyn Fn(DVec3) -> Rgb + Send + Sync>);
    impl Fitted for F {
        fn irradiance(&self, n: DVec3) -> Rgb {
            (self.0)(n)
        }
        fn stored(&self) -> crate::encoders::stored::Stored {
            crate::encoders::stored::Stored::new("a deliberately broken test encoder: nothing stored")
        }
    }
    impl Encoder for Broken {
        fn id(&self) -> &str {
            "broken"
        }
        fn stored_scalars(&self) -> usize {
            12
        }
        fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
            let sh1 = input.visible_sh.truncate(1).convolve_cosine();
            let sh0 = input.visible_sh.truncate(0).convolve_cosine();
            let l1 = input.visible_sh.l1_vector_weighted(Rgb::splat(1.0 / 3.0));
            match self.0 {
                Flaw::NaiveNormalise => {
                    let d = l1 / l1.length();
                    Box::new(F(Box::new(move |n| sh0.eval(n) + Rgb::splat(l1.length() * n.dot(d).max(0.0)))))
                }
                Flaw::Offset => Box::new(F(Box::new(move |n| sh1.eval(n) + Rgb::splat(1e-3)))),
                Flaw::ClaimsNonNegative | Flaw::ClaimsL1Bound => {
                    let s = if self.0 == Flaw::ClaimsL1Bound { sh0 } else { sh1 };
                    Box::new(F(Box::new(move |n| s.eval(n))))
                }
                Flaw::BadFallback => {
                    let d = if l1.length() > 0.0 { l1.normalize() } else { DVec3::Z };
                    let amb = sh0.eval(DVec3::Z);
                    Box::new(F(Box::new(move |n| amb * (2.0 * n.dot(d).max(0.0)))))
                }
            }
        }
        fn is_scale_covariant(&self) -> bool {
            self.0 == Flaw::Offset
        }
        fn promises_non_negative(&self) -> bool {
            self.0 == Flaw::ClaimsNonNegative
        }
        fn sphere_error_at_most_sh(&self) -> Option<usize> {
            (self.0 == Flaw::ClaimsL1Bound).then_some(1)
        }
    }
}

#[test]
fn the_contract_catches_broken_encoders() {
    use broken::{Broken, Flaw};
    let expect = [
        (Flaw::NaiveNormalise, "non-finite output"),
        (Flaw::Offset, "scale covariance"),
        (Flaw::Offset, "black input gives output"),
        (Flaw::ClaimsNonNegative, "promises non-negative"),
        (Flaw::ClaimsL1Bound, "promises sphere rmse <= SH L1"),
        (Flaw::BadFallback, "pure-ambient fallback"),
    ];
    let cases = cases();
    let prepared: Vec<Prepared> = cases.iter().map(Prepared::new).collect();
    for (flaw, words) in expect {
        let e = Broken(flaw);
        let fails: Vec<String> = prepared.iter().flat_map(|p| check(p, "broken", &e)).collect();
        assert!(fails.iter().any(|f| f.contains(words)), "{flaw:?} not caught ({words}): {fails:#?}");
    }
}
