//! The ZH3 talk's claims Z1–Z10 (`../shared/papers/CLAIMS.md`), each measured on the five
//! paper probes and on constructed scenes, written as `results/zh3_claims/claims.csv` and
//! `CLAIMS.md` by `probelab claims zh3`.
//!
//! Every figure uses the same machinery as the tables: encoders through the one trait, the
//! exact reference, and [`crate::reference::metrics::score`]. Unless a claim says otherwise the figure is
//! the **exact** metric: E/π over the **sphere**, **solid-angle** weighted, on the 256×128
//! lat-long grid of normals, against the exact cell-integrated reference of the map (2 GL
//! nodes per row piece). Constructed scenes use their closed-form irradiance and SH instead.
//! A claim that does not hold on our data is reported as not holding; percentages the talk
//! measured on its production data are anchors, not tests.

use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::encoders::zh3::solve::{band2, zonal_fit, Curve};
use crate::encoders::zh3::{hallucinate, stored, AxisRule};
use crate::envmap::moments::RowMoments;
use crate::envmap::search::SearchPath;
use crate::envmap::LatLong;
use crate::math::colour::Rgb;
use crate::math::colour::REC709;
use crate::math::sh::{delta_light, Sh9};
use crate::reference::domain::Domain;
use crate::reference::exact::{Reference, DEFAULT_POLAR_NODES};
use crate::reference::lighting::{Light, Lighting};
use crate::reference::metrics::{score, Scores};
use crate::reference::scenes::Scene;
use anyhow::{bail, Context, Result};
use glam::DVec3;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

/// The five paper probes.
pub const MAPS: [&str; 5] = ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

const RES: (usize, usize) = (256, 128);

/// One row of the claims table.
#[derive(Clone, Debug, PartialEq)]
pub struct Claim {
    pub id: &'static str,
    pub claim: &'static str,
    pub paper_figure: String,
    pub our_figure: String,
    pub holds: String,
    pub notes: String,
}

/// The claims and the details behind them (Markdown sections).
pub struct ClaimsReport {
    pub claims: Vec<Claim>,
    pub details: Vec<(String, String)>,
    pub maps: Vec<(String, String)>,
}

/// A set of normals with solid-angle weights and the reference E/π at each.
struct Case {
    name: String,
    /// Radiance SH (exact projection of the map, or closed form).
    sh: Sh9,
    reference: Vec<Rgb>,
}

/// The sphere output grid shared by every case.
struct Grid {
    normals: Vec<DVec3>,
    weights: Vec<f64>,
}

impl Grid {
    fn new() -> Self {
        let g = Domain::Sphere.output_grid(RES);
        Grid { normals: g.normals, weights: g.weights }
    }
}

/// An encoder by kind with TOML settings.
fn enc(kind: &str, settings: &[(&str, toml::Value)]) -> Result<Box<dyn Encoder>> {
    let t: toml::Table = settings.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    Ok(crate::encoders::build(kind, None, t)?.encoder)
}

fn weights_value(w: [f64; 3]) -> toml::Value {
    toml::Value::Array(w.iter().map(|&x| toml::Value::Float(x)).collect())
}

fn fit(e: &dyn Encoder, sh: &Sh9) -> Box<dyn Fitted> {
    e.fit(&FitInput::sphere(sh))
}

fn values(f: &dyn Fitted, grid: &Grid) -> Vec<Rgb> {
    grid.normals.iter().map(|&n| f.irradiance(n)).collect()
}

/// The exact metric of an encoder on a case.
fn exact(e: &dyn Encoder, case: &Case, grid: &Grid) -> Scores {
    score(&case.reference, &values(fit(e, &case.sh).as_ref(), grid), &grid.weights, false)
}

/// The peer-compatible metric (FORMULAS §10): per-pixel mean, clamped unless the encoder says
/// its peer counterpart is not.
fn probulator(e: &dyn Encoder, case: &Case, grid: &Grid) -> Scores {
    let ones = vec![1.0; grid.normals.len()];
    score(&case.reference, &values(fit(e, &case.sh).as_ref(), grid), &ones, e.peer_clamps())
}

fn map_case(search: &SearchPath, name: &str, grid_ll: LatLong) -> Result<(Case, String)> {
    let path = search.resolve(name).map_err(|e| anyhow::anyhow!("claims zh3: {e}"))?;
    let map = crate::envmap::load::load(&path)?;
    let rm = RowMoments::new(&map);
    let reference = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
    let values = reference.irradiance_latlong(grid_ll);
    let case = Case { name: name.to_string(), sh: crate::reference::projection::project(&map), reference: values };
    Ok((case, format!("{} ({}x{}, {})", path.display(), map.width(), map.height(), reference.describe())))
}

fn scene_case(scene: &Scene, grid: &Grid) -> Case {
    Case {
        name: scene.id.clone(),
        sh: scene.sh(),
        reference: grid.normals.iter().map(|&n| scene.irradiance(n)).collect(),
    }
}

fn scene(id: &str, lights: Vec<Light>) -> Scene {
    Scene { id: id.into(), description: String::new(), lighting: Lighting(lights) }
}

fn cap(axis: DVec3, half_angle: f64, radiance: Rgb) -> Light {
    Light::Cap { axis: axis.normalize(), half_angle, radiance }
}

fn pct(x: f64) -> String {
    format!("{:+.1}%", 100.0 * x)
}

/// Relative reduction of `b` against `a`: 1 − b/a.
fn reduction(a: f64, b: f64) -> f64 {
    if a > 0.0 {
        1.0 - b / a
    } else {
        0.0
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Chromaticity of a displayed colour: max(E, 0)/Σ max(E, 0); black is grey (⅓, ⅓, ⅓).
fn chroma(e: Rgb) -> Rgb {
    let c = e.max(Rgb::ZERO);
    let s = c.element_sum();
    if s > 0.0 {
        c / s
    } else {
        Rgb::splat(1.0 / 3.0)
    }
}

/// The chroma error (our definition for claim Z2): solid-angle RMS over the sphere of the
/// Euclidean distance between the chromaticities rgb/(r+g+b) of the test (clamped at 0, as
/// displayed) and of the reference.
fn chroma_error(test: &[Rgb], reference: &[Rgb], w: &[f64]) -> f64 {
    let (mut s, mut ws) = (0.0, 0.0);
    for ((t, r), &wi) in test.iter().zip(reference).zip(w) {
        s += wi * (chroma(*t) - chroma(*r)).length_squared();
        ws += wi;
    }
    (s / ws).sqrt()
}

/// The same, with each normal weighted by its solid angle times the reference luminance (mean
/// of RGB): chroma errors where the surface is lit, which is where fringing shows.
fn chroma_error_lit(test: &[Rgb], reference: &[Rgb], w: &[f64]) -> f64 {
    let lw: Vec<f64> = reference.iter().zip(w).map(|(r, w)| w * (r.element_sum() / 3.0).max(0.0)).collect();
    chroma_error(test, reference, &lw)
}

fn yes(b: bool) -> String {
    if b { "yes" } else { "no" }.to_string()
}

/// Measures every claim. Needs the five paper probes on the search path.
pub fn run(search: &SearchPath) -> Result<ClaimsReport> {
    let grid = Grid::new();
    let ll = LatLong::new(RES.0, RES.1);
    let mut maps = Vec::new();
    let mut cases = Vec::new();
    for name in MAPS {
        let (c, desc) = map_case(search, name, ll).with_context(|| {
            format!("claims zh3 needs the five paper probes ({}); set PROBELAB_ENVMAPS", MAPS.join(", "))
        })?;
        maps.push((name.to_string(), desc));
        cases.push(c);
    }
    let mut claims = Vec::new();
    let mut details = Vec::new();
    let mut add = |c: Claim, d: String| {
        details.push((format!("{} — {}", c.id, c.claim), d));
        claims.push(c);
    };
    let (c, d) = z1(&grid)?;
    add(c, d);
    let (c, d) = z2(&grid, &cases)?;
    add(c, d);
    let (c, d) = z3(&grid, &cases)?;
    add(c, d);
    let (c, d) = z4(&grid, &cases)?;
    add(c, d);
    let (c, d) = z5(&grid, &cases)?;
    add(c, d);
    let (c, d) = z6(&grid, &cases)?;
    add(c, d);
    let (c, d) = z7(&grid, &cases)?;
    add(c, d);
    let (c, d) = z8(&grid, &cases)?;
    add(c, d);
    let (c, d) = z9(&grid)?;
    add(c, d);
    let (c, d) = z10(&grid, &cases)?;
    add(c, d);
    Ok(ClaimsReport { claims, details, maps })
}

const STORED: [&str; 4] = ["zh3_stored_channel", "zh3_stored_shared", "zh3_solved_channel", "zh3_solved_shared"];

/// Z1: zonal lights are represented exactly by stored ZH3.
fn z1(grid: &Grid) -> Result<(Claim, String)> {
    let a = DVec3::new(0.35, 0.8, -0.49).normalize();
    let deg = PI / 180.0;
    let lights: Vec<(&str, Scene)> = vec![
        ("directional (delta) light, coloured", scene("delta", vec![])),
        ("cone light 5 deg", scene("cone5", vec![cap(a, 5.0 * deg, Rgb::new(200.0, 150.0, 100.0))])),
        ("cone light 30 deg", scene("cone30", vec![cap(-a, 30.0 * deg, Rgb::new(2.0, 3.0, 4.0))])),
        ("sphere light 60 deg over a constant sky", {
            scene("sphere60", vec![cap(a, 60.0 * deg, Rgb::ONE), Light::Ambient(Rgb::splat(0.2))])
        }),
    ];
    let mut worst_field = 0.0f64;
    let mut worst_rmse = 0.0f64;
    let mut table = String::from(
        "| light | encoder | max abs(ZH3 − SH3) / peak | RMSE ZH3 | RMSE SH3 | abs difference |\n|---|---|---|---|---|---|\n",
    );
    let sh2 = enc("sh2", &[])?;
    for (label, s) in &lights {
        // The delta light has no map or closed-form irradiance in `scenes`; its SH3 is the
        // reference there (the claim is ZH3 = SH3).
        let (sh, reference): (Sh9, Vec<Rgb>) = if s.id == "delta" {
            let sh = delta_light(a, Rgb::new(3.0, 2.0, 1.0));
            let r = grid.normals.iter().map(|&n| sh.convolve_cosine().eval(n)).collect();
            (sh, r)
        } else {
            (s.sh(), grid.normals.iter().map(|&n| s.irradiance(n)).collect())
        };
        let case = Case { name: s.id.clone(), sh, reference };
        let v2 = values(fit(sh2.as_ref(), &case.sh).as_ref(), grid);
        let peak = v2.iter().map(|v| v.max_element()).fold(0.0, f64::max);
        let e2 = score(&case.reference, &v2, &grid.weights, false).rmse;
        for id in STORED {
            let e = enc(id, &[])?;
            let v = values(fit(e.as_ref(), &case.sh).as_ref(), grid);
            let field = v.iter().zip(&v2).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f64::max) / peak;
            let ez = score(&case.reference, &v, &grid.weights, false).rmse;
            worst_field = worst_field.max(field);
            worst_rmse = worst_rmse.max((ez - e2).abs());
            let _ = writeln!(table, "| {label} | {id} | {field:.2e} | {ez:.6e} | {e2:.6e} | {:.1e} |", (ez - e2).abs());
        }
    }
    let holds = worst_field <= 1e-6 && worst_rmse <= 1e-6;
    Ok((
        Claim {
            id: "Z1",
            claim: "ZH3 represents every zonal light (directional, point, cone, sphere) exactly: the same irradiance as SH3",
            paper_figure: "exact (same accuracy as SH3)".into(),
            our_figure: format!(
                "max abs(ZH3 − SH3)/peak = {worst_field:.1e}; max abs(RMSE_ZH3 − RMSE_SH3) = {worst_rmse:.1e} (E/π)"
            ),
            holds: yes(holds),
            notes: "4 zonal lights (delta, 5° and 30° cones, 60° sphere light over a constant; closed-form SH and \
                    irradiance; a point light at a distance is the delta light) × the 4 stored ZH3 encoders; \
                    tolerance 1e-6"
                .into(),
        },
        format!("Closed-form SH and irradiance, sphere, solid-angle weighted, 256x128 normals.\n\n{table}"),
    ))
}

/// A scene with two coloured lights 90° apart, whose channels have different L1 axes.
fn two_colour_scene() -> Scene {
    scene(
        "constructed_two_colours",
        vec![
            cap(DVec3::X, 0.3, Rgb::new(8.0, 5.0, 1.0)),
            cap(DVec3::Y, 0.3, Rgb::new(1.0, 3.0, 9.0)),
            Light::Ambient(Rgb::splat(0.05)),
        ],
    )
}

/// Z2: colour fringing of per-channel axes, measured as a chroma error.
fn z2(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let pairs = [
        ("stored", "zh3_stored_channel", "zh3_stored_shared"),
        ("solved", "zh3_solved_channel", "zh3_solved_shared"),
        ("hallucinated", "zh3_hallucinate_channel", "zh3_hallucinate"),
    ];
    let constructed = scene_case(&two_colour_scene(), grid);
    let mut table = String::from(
        "| case | pair | chroma err channel | chroma err shared | lit chroma err channel | lit chroma err shared | RMSE channel | RMSE shared |\n|---|---|---|---|---|---|---|---|\n",
    );
    let sh2 = enc("sh2", &[])?;
    let sh1 = enc("sh1", &[])?;
    let mut ref_rows = String::from("| case | chroma err sh1 | chroma err sh2 |\n|---|---|---|\n");
    let (mut shared_better, mut total, mut rmse_up, mut lit_better) = (0, 0, 0, 0);
    let mut ch_all = Vec::new();
    let mut sh_all = Vec::new();
    for case in cases.iter().chain(std::iter::once(&constructed)) {
        let ce =
            |e: &dyn Encoder| chroma_error(&values(fit(e, &case.sh).as_ref(), grid), &case.reference, &grid.weights);
        let cl = |e: &dyn Encoder| {
            chroma_error_lit(&values(fit(e, &case.sh).as_ref(), grid), &case.reference, &grid.weights)
        };
        let _ = writeln!(ref_rows, "| {} | {:.4} | {:.4} |", case.name, ce(sh1.as_ref()), ce(sh2.as_ref()));
        for (label, ch, shd) in pairs {
            let (ec, es) = (enc(ch, &[])?, enc(shd, &[])?);
            let (cc, cs) = (ce(ec.as_ref()), ce(es.as_ref()));
            let (lc, ls) = (cl(ec.as_ref()), cl(es.as_ref()));
            let (rc, rs) = (exact(ec.as_ref(), case, grid).rmse, exact(es.as_ref(), case, grid).rmse);
            total += 1;
            shared_better += (cs < cc) as usize;
            lit_better += (ls < lc) as usize;
            rmse_up += (rs > rc) as usize;
            ch_all.push(cc);
            sh_all.push(cs);
            let _ = writeln!(
                table,
                "| {} | {label} | {cc:.4} | {cs:.4} | {lc:.4} | {ls:.4} | {rc:.5} | {rs:.5} |",
                case.name
            );
        }
    }
    let holds = shared_better * 4 >= total * 3;
    Ok((
        Claim {
            id: "Z2",
            claim: "Per-channel zonal axes can fringe colour; one shared axis removes the fringing, and RMSE may go up or down",
            paper_figure: "qualitative (images)".into(),
            our_figure: format!(
                "shared axis has the lower chroma error in {shared_better}/{total} (map, variant) pairs ({lit_better}/{total} \
                 luminance-weighted); mean chroma error channel {:.4} vs shared {:.4}; shared RMSE higher in {rmse_up}/{total}",
                mean(&ch_all),
                mean(&sh_all)
            ),
            holds: yes(holds),
            notes: "chroma error = solid-angle RMS over the sphere of |χ(test) − χ(ref)|, χ = max(E,0)/Σmax(E,0) \
                    (black = grey); five probes + a constructed two-colour scene (warm light +x, blue light +y); \
                    variants stored/solved/hallucinated; holds if shared is better in ≥ 3/4 of pairs"
                .into(),
        },
        format!("{table}\nFor scale, the chroma error of SH L1 and L2:\n\n{ref_rows}"),
    ))
}

/// The constructed scene of Z3: two equal lights along ±x (strong L2 about x, no L1 along x)
/// and a weak light along +y (the L1 points along y).
fn z3_scene() -> Scene {
    scene(
        "constructed_l2_off_axis",
        vec![
            cap(DVec3::X, 0.15, Rgb::splat(20.0)),
            cap(DVec3::NEG_X, 0.15, Rgb::splat(20.0)),
            cap(DVec3::Y, 0.15, Rgb::splat(4.0)),
            Light::Ambient(Rgb::splat(0.1)),
        ],
    )
}

/// Z3: a case where the solved axis beats the L1 axis dramatically.
fn z3(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let c = scene_case(&z3_scene(), grid);
    let ids = ["sh1", "zh3_stored_shared", "zh3_solved_shared", "sh2"];
    let mut r = Vec::new();
    let mut table =
        String::from("| case | sh1 | zh3_stored_shared (L1 axis) | zh3_solved_shared | sh2 |\n|---|---|---|---|---|\n");
    for case in std::iter::once(&c).chain(cases.iter()) {
        let e: Vec<f64> =
            ids.iter().map(|id| Ok(exact(enc(id, &[])?.as_ref(), case, grid).rmse)).collect::<Result<_>>()?;
        let _ = writeln!(table, "| {} | {:.5} | {:.5} | {:.5} | {:.5} |", case.name, e[0], e[1], e[2], e[3]);
        r.push(e);
    }
    let ratio = r[0][2] / r[0][1];
    let maps_gain: Vec<f64> = r[1..].iter().map(|e| reduction(e[1], e[2])).collect();
    Ok((
        Claim {
            id: "Z3",
            claim: "Solving for the zonal axis can give dramatically lower error than the L1 axis when the L2 energy lies in another direction",
            paper_figure: "qualitative (\"dramatically better\", one example)".into(),
            our_figure: format!(
                "constructed scene: RMSE solved/L1-axis = {ratio:.3} ({:.4} vs {:.4}; SH3 {:.4}); five probes: mean {} (range {} to {})",
                r[0][2],
                r[0][1],
                r[0][3],
                pct(-mean(&maps_gain)),
                pct(-maps_gain.iter().cloned().fold(f64::NEG_INFINITY, f64::max)),
                pct(-maps_gain.iter().cloned().fold(f64::INFINITY, f64::min))
            ),
            holds: yes(ratio < 0.5),
            notes: "CONSTRUCTED scene: two equal 8.6° lights along ±x (radiance 20) and a weaker one along +y (4), sky 0.1; \
                    closed-form reference; holds if the solved RMSE is below half the L1-axis RMSE; on the real probes the gain \
                    is small"
                .into(),
        },
        format!("Exact metric (sphere, solid-angle, 256x128). Constructed scene first.\n\n{table}"),
    ))
}

/// Z4: axis weights must match error weights.
fn z4(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let rec = REC709.to_array();
    let blue_heavy = [0.1, 0.1, 0.8];
    let matched =
        enc("zh3_solved_shared", &[("axis_weights", weights_value(rec)), ("error_weights", weights_value(rec))])?;
    let mismatched = enc(
        "zh3_solved_shared",
        &[("axis_weights", weights_value(blue_heavy)), ("error_weights", weights_value(rec))],
    )?;
    let constructed = scene_case(&two_colour_scene(), grid);
    // The Z3 geometry in colour: white lights along ±x carry the L2, a blue light along +y the L1.
    let off_axis = scene_case(
        &scene(
            "constructed_l2_off_axis_blue",
            vec![
                cap(DVec3::X, 0.15, Rgb::splat(20.0)),
                cap(DVec3::NEG_X, 0.15, Rgb::splat(20.0)),
                cap(DVec3::Y, 0.15, Rgb::new(0.5, 1.0, 8.0)),
                Light::Ambient(Rgb::splat(0.1)),
            ],
        ),
        grid,
    );
    let mut table = String::from(
        "| case | matched R/G/B RMSE | mismatched R/G/B RMSE | blue ratio | red+green ratio |\n|---|---|---|---|---|\n",
    );
    let (mut blue_up, mut pushed, mut total) = (0, 0, 0);
    let mut blue_ratios = Vec::new();
    let mut rg_ratios = Vec::new();
    for case in [&off_axis, &constructed].into_iter().chain(cases.iter()) {
        let m = exact(matched.as_ref(), case, grid).rmse_rgb;
        let x = exact(mismatched.as_ref(), case, grid).rmse_rgb;
        let b = x[2] / m[2];
        let rg = (x[0] + x[1]) / (m[0] + m[1]);
        total += 1;
        blue_up += (b > 1.0 + 1e-9) as usize;
        pushed += (b > rg) as usize;
        blue_ratios.push(b);
        rg_ratios.push(rg);
        let _ = writeln!(
            table,
            "| {} | {:.5} / {:.5} / {:.5} | {:.5} / {:.5} / {:.5} | {b:.3} | {rg:.3} |",
            case.name, m[0], m[1], m[2], x[0], x[1], x[2]
        );
    }
    let holds = if blue_up * 4 >= total * 3 && pushed * 4 >= total * 3 {
        "yes".to_string()
    } else if pushed * 2 > total || blue_up * 2 > total {
        format!("partly: blue error up in {blue_up}/{total}, error moved towards blue in {pushed}/{total}")
    } else {
        "no".to_string()
    };
    Ok((
        Claim {
            id: "Z4",
            claim: "The axis weights must match the error weights; otherwise the solver pushes error into the channel with the low weight",
            paper_figure: "qualitative (\"very obvious visually\")".into(),
            our_figure: format!(
                "axis weights (0.1, 0.1, 0.8) with Rec.709 error weights vs both Rec.709: blue RMSE up in {blue_up}/{total} cases, \
                 blue ratio above the red+green ratio in {pushed}/{total}; off-axis scene: blue ×{:.2}, red+green ×{:.2}; \
                 mean over the 5 probes: blue ×{:.3}, red+green ×{:.3}",
                blue_ratios[0],
                rg_ratios[0],
                mean(&blue_ratios[2..]),
                mean(&rg_ratios[2..])
            ),
            holds,
            notes: "zh3_solved_shared; blue has a high axis weight and a low (0.0722) error weight; CONSTRUCTED scenes (the Z3 \
                    geometry with a blue L1 light; the two-colour scene) + five probes; ratio = mismatched/matched RMSE per \
                    channel; holds if blue error rises, and rises more than red+green, in at least 3/4 of the cases (partly: in \
                    most of them). The mismatched solve \
                    can rotate the axis by moving only the cheap blue L1, so it can also lower every channel's error"
                .into(),
        },
        format!("Exact metric per channel (sphere, solid-angle, 256x128).\n\n{table}"),
    ))
}

/// Z5: Geomerics is non-negative and keeps DC but not the linear moment, so it over-brightens.
fn z5(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let g = enc("geomerics", &[])?;
    let sh1 = enc("sh1", &[])?;
    let mut table = String::from(
        "| map | min value | DC rel. error | linear moment geo/ref | dark-side mean error / ref mean | RMSE geomerics | RMSE sh1 |\n|---|---|---|---|---|---|---|\n",
    );
    let wsum: f64 = grid.weights.iter().sum();
    let (mut nonneg, mut dc_ok, mut moment_low, mut bright) = (true, true, 0, 0);
    let mut sh1_dev = 0.0f64;
    let mut moments = Vec::new();
    let mut darks = Vec::new();
    for case in cases {
        let v = values(fit(g.as_ref(), &case.sh).as_ref(), grid);
        let lum = |e: Rgb| e.element_sum() / 3.0;
        let min = v.iter().map(|x| x.min_element()).fold(f64::INFINITY, f64::min);
        let mean_of = |f: &[Rgb]| f.iter().zip(&grid.weights).map(|(x, w)| lum(*x) * w).sum::<f64>() / wsum;
        let moment_of = |f: &[Rgb]| -> DVec3 {
            f.iter().zip(&grid.normals).zip(&grid.weights).map(|((x, n), w)| *n * (lum(*x) * w)).sum::<DVec3>() / wsum
        };
        let (mg, mr) = (mean_of(&v), mean_of(&case.reference));
        let dc = (mg - mr) / mr;
        let (lg, lr) = (moment_of(&v), moment_of(&case.reference));
        let ratio = lg.length() / lr.length();
        // SH L1 keeps the linear moment exactly; its measured ratio shows the quadrature error.
        let v1 = values(fit(sh1.as_ref(), &case.sh).as_ref(), grid);
        let r1 = moment_of(&v1).length() / lr.length();
        sh1_dev = sh1_dev.max((r1 - 1.0).abs());
        // The side facing away from the light: n·(linear moment) < 0.
        let d = lr.normalize_or_zero();
        let (mut se, mut sw) = (0.0, 0.0);
        for ((x, r), (n, w)) in v.iter().zip(&case.reference).zip(grid.normals.iter().zip(&grid.weights)) {
            if n.dot(d) < 0.0 {
                se += (lum(*x) - lum(*r)) * w;
                sw += w;
            }
        }
        let dark = se / sw / mr;
        nonneg &= min >= 0.0;
        dc_ok &= dc.abs() < 1e-3;
        moment_low += (ratio < 1.0 - 10.0 * (r1 - 1.0).abs().max(1e-6)) as usize;
        bright += (dark > 0.0) as usize;
        moments.push(ratio);
        darks.push(dark);
        let (eg, e1) = (exact(g.as_ref(), case, grid).rmse, exact(sh1.as_ref(), case, grid).rmse);
        let _ = writeln!(
            table,
            "| {} | {min:.4} | {dc:.1e} | {ratio:.4} (sh1 {r1:.4}) | {} | {eg:.5} | {e1:.5} |",
            case.name,
            pct(dark)
        );
    }
    let peer = enc("geomerics_peer", &[])?;
    let constant = fit(peer.as_ref(), &crate::math::sh::constant(Rgb::ONE)).irradiance(DVec3::Y).x;
    let ours = fit(g.as_ref(), &crate::math::sh::constant(Rgb::ONE)).irradiance(DVec3::Y).x;
    let holds = nonneg && dc_ok && moment_low == cases.len() && bright * 2 > cases.len();
    Ok((
        Claim {
            id: "Z5",
            claim: "Geomerics is non-negative and keeps the DC term but not the linear moment, so it over-brightens",
            paper_figure: "qualitative".into(),
            our_figure: format!(
                "non-negative on all 5 probes: {}; DC kept to < 1e-3: {}; linear moment geo/ref {:.3}–{:.3} (sh1 within {sh1_dev:.0e}), \
                 reduced on {moment_low}/5; dark side too bright on {bright}/5 (mean {})",
                yes(nonneg),
                yes(dc_ok),
                moments.iter().cloned().fold(f64::INFINITY, f64::min),
                moments.iter().cloned().fold(0.0, f64::max),
                pct(mean(&darks))
            ),
            holds: yes(holds),
            notes: format!(
                "normalised geomerics (FORMULAS §6): constant environment gives {ours}; the peer's variant gives {constant:.4} \
                 (2/√π); moments of the luminance (mean of RGB) over the sphere; dark side = normals facing away from the \
                 reference's linear moment"
            ),
        },
        format!("Exact reference, sphere, solid-angle weights, 256x128 normals.\n\n{table}"),
    ))
}

/// Relative RMSE reductions of `ids` against `base` per map, exact and probulator metrics.
/// Per encoder, per map: relative RMSE reductions (exact, probulator), and the table.
type Reductions = (Vec<Vec<f64>>, Vec<Vec<f64>>, String);

fn reductions(grid: &Grid, cases: &[Case], base: &str, ids: &[&str]) -> Result<Reductions> {
    let b = enc(base, &[])?;
    let es: Vec<Box<dyn Encoder>> = ids.iter().map(|id| enc(id, &[])).collect::<Result<_>>()?;
    let mut ex = vec![Vec::new(); ids.len()];
    let mut pr = vec![Vec::new(); ids.len()];
    let mut table = format!("| map | metric | {base} |");
    for id in ids {
        let _ = write!(table, " {id} |");
    }
    table += "\n|---|---|---|";
    table += &"---|".repeat(ids.len());
    table += "\n";
    for case in cases {
        for (metric, f) in [("exact", exact as fn(&dyn Encoder, &Case, &Grid) -> Scores), ("probulator", probulator)] {
            let rb = f(b.as_ref(), case, grid).rmse;
            let _ = write!(table, "| {} | {metric} | {rb:.5} |", case.name);
            for (i, e) in es.iter().enumerate() {
                let r = f(e.as_ref(), case, grid).rmse;
                let red = reduction(rb, r);
                let dest = if metric == "exact" { &mut ex } else { &mut pr };
                dest[i].push(red);
                let _ = write!(table, " {r:.5} ({}) |", pct(-red));
            }
            table += "\n";
        }
    }
    Ok((ex, pr, table))
}

/// Z6: hallucination models against L1 SH.
fn z6(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let ids = ["zh3_hallucinate_ambdir", "zh3_hallucinate_sphere", "zh3_hallucinate"];
    let (ex, pr, table) = reductions(grid, cases, "sh1", &ids)?;
    let m: Vec<f64> = ex.iter().map(|v| mean(v)).collect();
    let p: Vec<f64> = pr.iter().map(|v| mean(v)).collect();
    let curve_best = m[2] >= m[0] && m[2] >= m[1];
    let both_reduce = m[2] > 0.0 && m[0] > 0.0;
    let sphere_zero = m[1].abs() < 0.05;
    let holds = if curve_best && both_reduce && sphere_zero {
        "yes".to_string()
    } else if curve_best && both_reduce {
        "partly: curve best and ambdir helps, but the sphere-light model is not ~0%".to_string()
    } else {
        "no".to_string()
    };
    Ok((
        Claim {
            id: "Z6",
            claim: "Hallucination against L1 SH: ambient+directional ~17% lower RMSE, sphere light ~0%, quadratic curve fit 23% (prod)",
            paper_figure: "17% / 0% / 23% lower RMSE than SH L1 (production set, ~3M probes)".into(),
            our_figure: format!(
                "mean over 5 probes, exact: {} / {} / {}; probulator: {} / {} / {}",
                pct(m[0]),
                pct(m[1]),
                pct(m[2]),
                pct(p[0]),
                pct(p[1]),
                pct(p[2])
            ),
            holds,
            notes: "reductions (positive = lower RMSE than sh1) for ambdir / sphere / curve, Rec.709 shared axis; the paper's \
                    percentages are production anchors (about 3M game probes; ours are five HDR photographs); holds if curve and ambdir both reduce the error, the curve \
                    most, and the sphere model within ±5% of sh1"
                .into(),
        },
        format!("RMSE and change against sh1, both metrics (exact: sphere, solid-angle; probulator: per-pixel, clamped; 256x128).\n\n{table}"),
    ))
}

/// Z7: stored against hallucinated ZH3.
fn z7(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let ids = ["zh3_stored_shared", "zh3_solved_shared", "zh3_hallucinate_solved"];
    let (ex, pr, table) = reductions(grid, cases, "zh3_hallucinate", &ids)?;
    let m: Vec<f64> = ex.iter().map(|v| mean(v)).collect();
    let p: Vec<f64> = pr.iter().map(|v| mean(v)).collect();
    Ok((
        Claim {
            id: "Z7",
            claim: "Stored ZH3 has about 27% lower error than hallucinated ZH3 (prod)",
            paper_figure: "~27% lower (production set)".into(),
            our_figure: format!(
                "mean over 5 probes against zh3_hallucinate, exact: stored shared {}, solved shared {}; probulator: {}, {}",
                pct(m[0]),
                pct(m[1]),
                pct(p[0]),
                pct(p[1])
            ),
            holds: yes(m[1] > 0.0 && m[0] > 0.0),
            notes: format!(
                "positive = stored has lower RMSE; also the hallucinated solve (L1 solved for its hallucinated ZH3): exact {}; \
                 holds if stored beats hallucinated on average (the 27% is a production anchor)",
                pct(m[2])
            ),
        },
        format!("RMSE and change against zh3_hallucinate.\n\n{table}"),
    ))
}

/// Z8: ZH3 on the five probes.
fn z8(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let ids = ["sh1", "zh3_hallucinate", "zh3_hallucinate_channel", "zh3_stored_shared", "zh3_solved_shared", "sh2"];
    let es: Vec<Box<dyn Encoder>> = ids.iter().map(|id| enc(id, &[])).collect::<Result<_>>()?;
    let mut table = String::from("| map | metric |");
    for id in ids {
        let _ = write!(table, " {id} |");
    }
    table += " gap closed (solved shared) |\n|---|---|";
    table += &"---|".repeat(ids.len() + 1);
    table += "\n";
    let mut all_better = true;
    let mut gap = std::collections::BTreeMap::new();
    let mut wells = (0.0, 0.0, 0.0);
    for case in cases {
        for (metric, f) in [("exact", exact as fn(&dyn Encoder, &Case, &Grid) -> Scores), ("probulator", probulator)] {
            let r: Vec<f64> = es.iter().map(|e| f(e.as_ref(), case, grid).rmse).collect();
            let g = (r[0] - r[4]) / (r[0] - r[5]);
            if metric == "exact" {
                all_better &= r[1] < r[0] && r[3] < r[0] && r[4] < r[0];
            }
            gap.insert((case.name.clone(), metric), g);
            if case.name == "wells_probulator" && metric == "probulator" {
                wells = (r[2], r[3], r[4]);
            }
            let _ = write!(table, "| {} | {metric} |", case.name);
            for x in &r {
                let _ = write!(table, " {x:.5} |");
            }
            let _ = writeln!(table, " {g:.2} |");
        }
    }
    let g = |m: &str, metric: &'static str| gap.get(&(m.to_string(), metric)).copied().unwrap_or(f64::NAN);
    let close = g("grace_256x128", "probulator") >= 0.75 && g("ennis_256x128", "probulator") >= 0.75;
    let wells_beats = wells.0 < wells.1;
    let holds = all_better && close && wells_beats;
    Ok((
        Claim {
            id: "Z8",
            claim: "ZH3 clearly improves on L1 on every map and comes close to SH3 on Grace and Ennis; hallucination with a per-channel axis can beat the stored shared-axis solve (as on Wells)",
            paper_figure: "figure of RMSE per map (Probulator)".into(),
            our_figure: format!(
                "ZH3 (hallucinated, stored, solved) below sh1 on every map: {}; share of the sh1→sh2 gap closed by the solved shared axis \
                 (probulator): grace {:.2}, ennis {:.2} (exact {:.2}, {:.2}); wells (probulator): hallucinate_channel {:.5} vs stored shared {:.5} vs solved shared {:.5}",
                yes(all_better),
                g("grace_256x128", "probulator"),
                g("ennis_256x128", "probulator"),
                g("grace_256x128", "exact"),
                g("ennis_256x128", "exact"),
                wells.0,
                wells.1,
                wells.2
            ),
            holds: if holds { "yes".into() } else { format!("partly: improves {}, close {}, wells {}", yes(all_better), yes(close), yes(wells_beats)) },
            notes: "\"close to SH3\" read as closing at least 75% of the sh1→sh2 RMSE gap; our probulator metric uses the exact \
                    reference (the paper's used Monte Carlo)"
                .into(),
        },
        format!("RMSE per map and metric (exact: sphere, solid-angle; probulator: per-pixel, clamped; 256x128).\n\n{table}"),
    ))
}

/// Z9: blending two probes whose L1 axes are perpendicular.
fn z9(grid: &Grid) -> Result<(Claim, String)> {
    let mk = |axis: DVec3| scene("p", vec![cap(axis, 0.2, Rgb::splat(10.0)), Light::Ambient(Rgb::splat(0.1))]);
    let (a, b) = (mk(DVec3::X), mk(DVec3::Y));
    let blend = scene("blend", a.lighting.0.iter().chain(&b.lighting.0).cloned().collect());
    let half = |s: Sh9| s * 0.5;
    let (sa, sb) = (a.sh().convolve_cosine(), b.sh().convolve_cosine());
    let sh_blend = half(sa + sb); // irradiance SH3 of the blend (exact SH3 interpolation)
    let reference: Vec<Rgb> = grid.normals.iter().map(|&n| blend.irradiance(n) * 0.5).collect();
    let rule = AxisRule::Shared(Rgb::splat(1.0 / 3.0));
    let (za, zb) = (stored(&sa, rule), stored(&sb, rule));
    // (a) blend the stored ZH3 coefficients: L0, L1 and k averaged, axis from the blended L1.
    let mut zc = za;
    zc.l0 = (za.l0 + zb.l0) * 0.5;
    for c in 0..3 {
        zc.l1[c] = (za.l1[c] + zb.l1[c]) * 0.5;
    }
    zc.axes = rule.axes(&zc.l1);
    zc.k = (za.k + zb.k) * 0.5;
    let coeff_blend = zc.to_sh();
    // (b) expand each to SH3, blend: exact for these zonal probes.
    let sh3_blend = half(za.to_sh() + zb.to_sh());
    // (c) hallucinate from the blended L1.
    let hall = hallucinate(&sh_blend, AxisRule::Shared(REC709), Curve::PAPER);
    let hall_a = hallucinate(&sa, AxisRule::Shared(REC709), Curve::PAPER);
    // The zonal coefficient the blend should have: the least-squares fit of its L2 about its axis.
    let axis = zc.axes[0].expect("blended L1 is non-zero");
    let k_true = zonal_fit(axis, &crate::encoders::zh3::solve::l2_band(&sh_blend, 0));
    let k_end = za.k.x;
    let r = |k: f64| k / k_end;
    let rms = |s: &Sh9| {
        let v: Vec<Rgb> = grid.normals.iter().map(|&n| s.eval(n)).collect();
        score(&reference, &v, &grid.weights, false).rmse
    };
    let sh1_blend = sh_blend.truncate(1);
    let rows = [
        ("blend stored ZH3 coefficients", r(zc.k.x), rms(&coeff_blend)),
        (
            "blend expanded SH3",
            r(zonal_fit(axis, &crate::encoders::zh3::solve::l2_band(&sh3_blend, 0))),
            rms(&sh3_blend),
        ),
        ("hallucinate from blended L1", hall.k.x / hall_a.k.x, rms(&hall.to_sh())),
        ("SH L1 of the blend", 0.0, rms(&sh1_blend)),
    ];
    let mut table = String::from("| method | zonal coefficient / endpoint's | RMSE vs exact blend |\n|---|---|---|\n");
    for (m, k, e) in rows {
        let _ = writeln!(table, "| {m} | {k:.4} | {e:.5} |");
    }
    let _ = writeln!(
        table,
        "\nThe blend's own zonal coefficient about its axis / the endpoint's: {:.4} (¼ for two delta lights).",
        r(k_true)
    );
    let holds = (rows[0].1 - 1.0).abs() < 1e-9
        && (rows[1].1 - r(k_true)).abs() < 1e-9
        && rows[2].1 < 1.0
        && rows[0].2 > rows[1].2;
    // Check, for the record, that a delta light pair gives exactly ¼.
    let da = delta_light(DVec3::X, Rgb::ONE);
    let db = delta_light(DVec3::Y, Rgb::ONE);
    let ax = (DVec3::X + DVec3::Y).normalize();
    let k_delta = zonal_fit(ax, &crate::encoders::zh3::solve::l2_band(&half(da + db), 0))
        / zonal_fit(DVec3::X, &crate::encoders::zh3::solve::l2_band(&da, 0));
    let _ = band2(ax);
    Ok((
        Claim {
            id: "Z9",
            claim: "Averaging two linear SH with perpendicular axes should scale the ZH3 coefficient by ¼; interpolating stored ZH3 coefficients does not; hallucinated ZH3 shrinks naturally",
            paper_figure: "¼ (two perpendicular axes)".into(),
            our_figure: format!(
                "zonal coefficient of the 50% blend / endpoint: stored-coefficient blend {:.3}, expanded-SH3 blend {:.3} (the blend's own; two delta lights: {k_delta:.4}), \
                 hallucinated from blended L1 {:.3}; RMSE vs exact blend {:.4} / {:.4} / {:.4}",
                rows[0].1, rows[1].1, rows[2].1, rows[0].2, rows[1].2, rows[2].2
            ),
            holds: yes(holds),
            notes: "CONSTRUCTED probes: a 11.5° light (radiance 10) along +x resp. +y over sky 0.1, blended 50/50; reference = closed-form \
                    irradiance of the blended lighting; stored ZH3 with the equal-weight shared axis"
                .into(),
        },
        format!("Closed-form reference, sphere, solid-angle weights, 256x128 normals.\n\n{table}"),
    ))
}

/// Z10: ratio quantisation to 13 / 16 / 28 bytes.
fn z10(grid: &Grid, cases: &[Case]) -> Result<(Claim, String)> {
    let q = toml::Value::String("ratio8".into());
    type Pair = (&'static str, Box<dyn Encoder>, Box<dyn Encoder>, usize);
    let pairs: Vec<Pair> = vec![
        ("sh1", enc("sh1", &[])?, enc("sh1_q13", &[])?, 13),
        (
            "zh3_solved_shared",
            enc("zh3_solved_shared", &[])?,
            enc("zh3_solved_shared", &[("quantise", q.clone())])?,
            16,
        ),
        ("zh3_hallucinate", enc("zh3_hallucinate", &[])?, enc("zh3_hallucinate", &[("quantise", q)])?, 13),
        ("sh2", enc("sh2", &[])?, enc("sh2_q28", &[])?, 28),
    ];
    let mut table = String::from(
        "| map | encoder | bytes | RMSE | RMSE quantised | quantisation error (RMS of the difference) | / RMSE |\n|---|---|---|---|---|---|---|\n",
    );
    let mut worst = vec![0.0f64; pairs.len()];
    for case in cases {
        for (i, (name, e, eq, bytes)) in pairs.iter().enumerate() {
            let v = values(fit(e.as_ref(), &case.sh).as_ref(), grid);
            let vq = values(fit(eq.as_ref(), &case.sh).as_ref(), grid);
            let r = score(&case.reference, &v, &grid.weights, false).rmse;
            let rq = score(&case.reference, &vq, &grid.weights, false).rmse;
            let dq = score(&v, &vq, &grid.weights, false).rmse;
            worst[i] = worst[i].max(dq / r);
            let _ =
                writeln!(table, "| {} | {name} | {bytes} | {r:.5} | {rq:.5} | {dq:.2e} | {:.3} |", case.name, dq / r);
        }
    }
    // The claim is about sizes, which the layout reaches by construction; the added error is
    // what the issue asks us to report next to it.
    let holds = true;
    Ok((
        Claim {
            id: "Z10",
            claim: "Ratio-based quantisation stores L1 in 13 bytes, ZH3 in 16 and L2 in 28",
            paper_figure: "13 / 16 / 28 bytes".into(),
            our_figure: format!(
                "13 / 16 / 28 bytes (DC RGB9E5 + one signed byte per ratio); quantisation error / encoding RMSE, worst of 5 probes: sh1 {:.3}, zh3 solved {:.3}, zh3 hallucinated {:.3}, sh2 {:.3}",
                worst[0], worst[1], worst[2], worst[3]
            ),
            holds: yes(holds),
            notes: "layout derived (the talk gives sizes only; see src/encoders/quantise.rs); ratio bounds of non-negative radiance \
                    (√3 for L1, √15/2 and √5 for L2, √5 for f/L00); the sizes hold by construction; the figure gives the error \
                    quantisation adds, relative to each encoding's own error against the reference"
                .into(),
        },
        format!("Exact metric (sphere, solid-angle, 256x128). Quantisation error = RMS over the sphere of (quantised − unquantised) E/π.\n\n{table}"),
    ))
}

/// The claims as CSV.
pub fn to_csv(r: &ClaimsReport) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["id", "claim", "paper_figure", "our_figure", "holds", "notes"])?;
    for c in &r.claims {
        w.write_record([c.id, c.claim, &c.paper_figure, &c.our_figure, &c.holds, &c.notes])?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// The Markdown summary.
pub fn to_markdown(r: &ClaimsReport) -> String {
    let mut s = String::from(
        "# ZH3 claims (Z1–Z10), measured\n\n\
         Generated by `probelab claims zh3` (src/zh3_claims.rs); do not edit by hand. Claims from \
         `shared/papers/CLAIMS.md` (ZH3 talk, I3D 2024). Units E/π. Unless a section says otherwise: the exact \
         metric (sphere, solid-angle weighted, 256x128 lat-long normals) against the exact cell-integrated reference \
         (2 GL nodes per row piece); constructed scenes use closed-form irradiance. Percentages marked (prod) in the \
         talk were measured on its production data and are anchors, not tests.\n\n\
         | id | holds | our figure | paper |\n|---|---|---|---|\n",
    );
    for c in &r.claims {
        let _ = writeln!(s, "| {} | {} | {} | {} |", c.id, c.holds, c.our_figure.replace('|', "/"), c.paper_figure);
    }
    s += "\n## Maps\n\n";
    for (n, d) in &r.maps {
        let _ = writeln!(s, "- `{n}`: {d}");
    }
    for (c, (title, body)) in r.claims.iter().zip(&r.details) {
        let _ = write!(s, "\n## {title}\n\n**Holds:** {}. {}\n\n{body}\n", c.holds, c.notes);
    }
    s
}

/// Runs the claims and writes `claims.csv` and `CLAIMS.md` into `dir` (atomically).
pub fn write(r: &ClaimsReport, dir: &Path) -> Result<()> {
    crate::pipeline::atomic::write(&dir.join("claims.csv"), &to_csv(r)?)?;
    crate::pipeline::atomic::write(&dir.join("CLAIMS.md"), to_markdown(r).as_bytes())?;
    Ok(())
}

/// The claim sets `probelab claims` knows.
pub fn check_set(set: &str) -> Result<()> {
    if set != "zh3" {
        bail!("claims: unknown set '{set}' (known: zh3, lightmap)");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chroma_of_black_and_grey() {
        assert_eq!(chroma(Rgb::ZERO), Rgb::splat(1.0 / 3.0));
        assert_eq!(chroma(Rgb::new(2.0, 2.0, 2.0)), Rgb::splat(1.0 / 3.0));
        assert_eq!(chroma(Rgb::new(-1.0, 1.0, 0.0)), Rgb::new(0.0, 1.0, 0.0));
        let e = chroma_error(&[Rgb::new(1.0, 0.0, 0.0)], &[Rgb::new(0.0, 1.0, 0.0)], &[1.0]);
        assert!((e - 2f64.sqrt()).abs() < 1e-15);
    }

    /// Z1 and Z9 need no maps: run them and check the figures that have closed forms.
    #[test]
    fn z1_and_z9_hold() {
        let grid = Grid::new();
        let (c, _) = z1(&grid).unwrap();
        assert_eq!(c.holds, "yes", "{}", c.our_figure);
        let (c, _) = z9(&grid).unwrap();
        assert_eq!(c.holds, "yes", "{}", c.our_figure);
        // Two perpendicular delta lights: P₂(cos 45°) = ¼.
        assert!(c.our_figure.contains("0.2500"), "{}", c.our_figure);
    }

    #[test]
    fn unknown_set() {
        assert!(check_set("hemi").unwrap_err().to_string().contains("known: zh3, lightmap"));
        check_set("zh3").unwrap();
    }
}
