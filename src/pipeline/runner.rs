//! The experiment runner: owns the order of work. Per map it loads the map once and computes
//! the shared data once (row moments, the probe's SH); per case (surface orientation × effect
//! parameters) the visible SH and the exact reference on each output grid; then fits and scores
//! every encoder through the one trait. It never names an encoder.
//!
//! Only declared effects are simulated: with no effect the reference has no caps and the
//! visible SH is the probe SH (no masked projection is computed).

use crate::encoders::encoder::{Encoder, Fitted};
use crate::envmap::search::{OpenError, SearchPath};
use crate::envmap::EnvMap;
use crate::io::progress::Progress;
use crate::math::colour::Rgb;
use crate::pipeline::experiment::Experiment;
use crate::pipeline::reuse::{cap_bits, ReferenceCache};
use crate::pipeline::settings::RunSettings;
use crate::pipeline::table::Row;
use crate::pipeline::timing;
use crate::reference::domain::{Domain, OutputGrid};
use crate::reference::metrics::{score, Metric, Scores};
use crate::reference::radiance::MapLight;
use anyhow::{bail, Result};
use glam::DVec3;
use rayon::prelude::*;
use std::path::PathBuf;

use super::cases::references_together;
pub use super::cases::{cases, Case, CaseData, CaseInputs, MapData};

/// Identity of a map used in a run (for provenance).
#[derive(Clone, Debug)]
pub struct MapInfo {
    /// The name or path the experiment asked for, as written.
    pub given: String,
    /// The map's name.
    pub name: String,
    /// The file it was loaded from; None for a generated map.
    pub path: Option<PathBuf>,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// The file's sha256.
    pub sha256: String,
    /// The pixel sha256 (`envmap::identity`): the map's identity whatever file holds it.
    pub pixel_sha256: String,
    /// The product of the `.hdr` file's `EXPOSURE=` values its pixels were divided by (1 for
    /// every other map; `EnvMap::exposure`).
    pub exposure: f64,
    /// What was done to the file's colour beyond the exposure (`EnvMap::colour`; empty when
    /// nothing).
    pub colour: String,
}

/// What a run produced.
pub struct RunReport {
    /// The scored rows, in table order.
    pub rows: Vec<Row>,
    /// Identity of every map that was run.
    pub maps: Vec<MapInfo>,
    /// Maps not found on the search path (their rows are absent), in the experiment's order.
    pub missing: Vec<String>,
    /// Why each of `missing` is missing (same order): `envmap::search::SearchError::reason`.
    pub missing_why: Vec<String>,
}

/// The profile phase of setting up a case under caps (hemisphere and cone effects): its masked
/// SH projection and its capped reference ([`CaseData::new`]). A case with no declared effect is
/// the phase "case setup" and computes neither.
pub const CAPPED_CASE_SETUP: &str = "case setup (masked SH, capped reference)";

/// Runs an experiment over the maps the search path finds. Maps that are not found (or, for a
/// known map, found only in files with other pixels: `SearchPath::open`) are listed in
/// `missing`; a map that is found but cannot be read is an error. References are kept in and
/// read from `cache` (the workflow's: experiments of one workflow share their cases').
pub fn run(exp: &Experiment, search: &SearchPath, settings: &RunSettings, cache: &ReferenceCache) -> Result<RunReport> {
    let mut rows = Vec::new();
    let mut maps = Vec::new();
    let mut missing: Vec<(usize, String, String)> = Vec::new();
    // Every map is located before any is loaded. Rows are keyed by the map's table name (its
    // file stem, or the known map's name): two entries with one table name would give rows
    // with identical keys, so that is refused before any work, naming the experiment file's
    // line of the second.
    let mut stems = std::collections::HashMap::new();
    let mut found = Vec::new();
    for (k, name) in exp.maps.iter().enumerate() {
        let path = match search.resolve(name) {
            Ok(p) => p,
            Err(e) => {
                missing.push((k, name.clone(), e.reason()));
                continue;
            }
        };
        let stem = crate::envmap::search::table_name(name, &path);
        if let Some(first) = stems.insert(stem.clone(), name) {
            let at = match (&exp.source, exp.source_lines(std::slice::from_ref(name))[0]) {
                (Some(file), Some(line)) => format!("{}:{line}: maps ", file.display()),
                (Some(file), None) => format!("{}: maps ", file.display()),
                (None, _) => "maps ".to_string(),
            };
            bail!(
                "{at}'{first}' and '{name}' are both the map '{stem}' (rows are keyed by the file stem); list it once"
            );
        }
        found.push((k, name));
    }
    let progress = Progress::new(found.len() as u64, &format!("{}: maps", exp.name));
    for (k, name) in found {
        progress.message(name.clone());
        // Load first: the loader refuses what is not a regular file (reading a FIFO would block).
        let map = {
            let _s = settings.span("decode");
            match search.open(name) {
                Ok(m) => m,
                Err(OpenError::NotFound(e)) => {
                    missing.push((k, name.clone(), e.reason()));
                    progress.inc();
                    continue;
                }
                Err(OpenError::Load(e)) => return Err(e.into()),
            }
        };
        maps.push(MapInfo {
            given: name.clone(),
            name: map.name.clone(),
            path: map.path.clone(),
            width: map.width(),
            height: map.height(),
            sha256: map.sha256.clone().unwrap_or_default(),
            pixel_sha256: map.pixel_sha256.clone().unwrap_or_default(),
            exposure: map.exposure,
            colour: map.colour.clone(),
        });
        rows.extend(run_map_reusing(exp, &map, settings, cache));
        settings.check_cancelled()?;
        progress.inc();
    }
    progress.finish();
    missing.sort_by_key(|m| m.0);
    let (missing, missing_why) = missing.into_iter().map(|(_, n, w)| (n, w)).unzip();
    Ok(RunReport { rows, maps, missing, missing_why })
}

/// Scores every encoder of the experiment on one in-memory map. With `settings.cancel` set
/// while it runs, the work stops early and the rows mean nothing: the caller checks
/// [`RunSettings::check_cancelled`] before using them.
pub fn run_map(exp: &Experiment, map: &EnvMap, settings: &RunSettings) -> Vec<Row> {
    run_map_reusing(exp, map, settings, &ReferenceCache::new(settings.profile))
}

/// [`run_map`], its references kept in and read from `cache`. Cases whose caps are the same
/// (the `self_bounce` albedos of one orientation, an orientation listed twice) share their
/// reference: they run one after another, the first computing it, while different caps run in
/// parallel.
pub fn run_map_reusing(exp: &Experiment, map: &EnvMap, settings: &RunSettings, cache: &ReferenceCache) -> Vec<Row> {
    let data = {
        let _s = settings.span("row moments + SH projection");
        MapData::new(map)
    };
    if settings.cancelled() {
        return Vec::new();
    }
    let all = cases(exp);
    references_together(exp, &data, &all, cache);
    // Per case, so that a map of many cases shows its progress and the time left.
    let progress = (all.len() > 1).then(|| Progress::new(all.len() as u64, &format!("{}: cases", map.name)));
    let mut done: Vec<(usize, CaseRun)> = same_caps(&all)
        .par_iter()
        .flat_map_iter(|group| {
            let runs: Vec<(usize, CaseRun)> = group
                .iter()
                .map(|&i| {
                    let run = run_case(exp, &data, &all[i], settings, cache);
                    progress.iter().for_each(Progress::inc);
                    (i, run)
                })
                .collect();
            runs
        })
        .collect();
    drop(progress);
    done.sort_by_key(|(i, _)| *i);
    let (mut per_case, inputs): (Vec<Vec<Row>>, Vec<(CaseInputs, MapLight)>) = done.into_iter().map(|(_, r)| r).unzip();
    fill_timing(exp, &all, &inputs, &mut per_case, settings);
    per_case.into_iter().flatten().collect()
}

/// What one case's run gives: its rows and the inputs they were fitted from.
type CaseRun<'d> = (Vec<Row>, (CaseInputs, MapLight<'d>));

/// The indices of `cases` grouped by their caps (bit for bit), each group in case order, the
/// groups in the order of their first case.
fn same_caps(cases: &[Case]) -> Vec<Vec<usize>> {
    let mut groups: Vec<(Vec<[u64; 4]>, Vec<usize>)> = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        let b = cap_bits(&c.masks);
        match groups.iter_mut().find(|g| g.0 == b) {
            Some(g) => g.1.push(i),
            None => groups.push((b, vec![i])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

/// Fills `fit_ns` and `eval_ns` of the rows of one map, `rows[c]` being the rows of
/// `cases[c]` and `inputs[c]` what scoring fitted them from (with the case's light, whose
/// caches scoring filled): sequentially, after scoring, so timing never touches the numbers
/// ([`crate::pipeline::timing`]).
fn fill_timing(
    exp: &Experiment,
    cases: &[Case],
    inputs: &[(CaseInputs, MapLight)],
    rows: &mut [Vec<Row>],
    settings: &RunSettings,
) {
    if !settings.timing || settings.cancelled() {
        return;
    }
    let _span = settings.span("timing pass");
    let progress = (cases.len() > 1).then(|| Progress::new(cases.len() as u64, "timing pass: cases"));
    for ((case, (inputs, light)), rows) in cases.iter().zip(inputs).zip(rows.iter_mut()) {
        if settings.cancelled() {
            return;
        }
        let input = inputs.fit_input(case, Some(light));
        let normals = timing::subsample(&case.domain.output_grid(exp.resolution).normals, timing::EVAL_NORMALS);
        for named in &exp.encoders {
            let (fit_ns, eval_ns) = timing::measure(named.encoder.as_ref(), &input, &normals);
            for r in rows.iter_mut().filter(|r| r.encoder == named.name) {
                r.fit_ns = Some(fit_ns);
                r.eval_ns = Some(eval_ns);
            }
        }
        progress.iter().for_each(Progress::inc);
    }
}

/// One metric's output grid: its resolution, whether it covers the sphere, the grid, and the
/// reference on it.
type ScoredGrid = ((usize, usize), bool, OutputGrid, Vec<Rgb>);

/// Scores every encoder on one case; returns the rows and the inputs they were fitted from.
fn run_case<'d>(
    exp: &Experiment,
    data: &'d MapData,
    case: &'d Case,
    settings: &RunSettings,
    cache: &'d ReferenceCache,
) -> CaseRun<'d> {
    let map = data.map;
    let cd = {
        let _s = settings.span(if case.masks.is_empty() { "case setup" } else { CAPPED_CASE_SETUP });
        CaseData::new(data, case, exp.polar_nodes).reusing(cache)
    };
    let reference = &cd.reference;
    let input = cd.fit_input();
    let fitted: Vec<_> = {
        let _s = settings.span("fit");
        exp.encoders.iter().map(|e| e.encoder.fit(&input)).collect()
    };
    let (described, exact_at_normal) = (reference.describe(), cd.inputs.exact_at_normal);
    let mut rows = Vec::new();
    // One output grid (and one reference evaluation) per distinct metric grid.
    let mut grids: Vec<ScoredGrid> = Vec::new();
    for metric in &exp.metrics {
        let (res, domain) = match metric.fixed_resolution() {
            Some(r) => (r, Domain::Sphere),
            None => (exp.resolution, case.domain.clone()),
        };
        let sphere = matches!(domain, Domain::Sphere);
        if !grids.iter().any(|g| g.0 == res && g.1 == sphere) {
            let grid = domain.output_grid(res);
            let values = cd.reference_on_until(&grid, &|| settings.cancelled());
            grids.push((res, sphere, grid, values));
        }
        // Cannot fail: the grid was pushed just above when it was not there.
        let (_, _, grid, ref_values) = grids.iter().find(|g| g.0 == res && g.1 == sphere).expect("grid just added");
        // The encoders on the pool (each evaluation is itself parallel over the normals), the
        // rows in the encoders' order.
        let scored: Vec<Row> = exp
            .encoders
            .par_iter()
            .zip(&fitted)
            .map(|(named, fit)| {
                let test = {
                    let _s = settings.span("render (encoder eval)");
                    evaluate(fit.as_ref(), &grid.normals)
                };
                let scores = {
                    let _s = settings.span("score");
                    score_values(named.encoder.as_ref(), &test, grid, ref_values, *metric)
                };
                Row {
                    map: map.name.clone(),
                    encoder: named.name.clone(),
                    domain: case.domain_label.clone(),
                    metric: metric.name().into(),
                    scores,
                    stored_scalars: named.encoder.stored_scalars(),
                    orientation_set: case.orientation_set.clone(),
                    effects: case.effects_label.clone(),
                    weighting: metric.weighting().into(),
                    resolution: format!("{}x{}", grid.resolution.0, grid.resolution.1),
                    units: "E/pi".into(),
                    reference: described.clone(),
                    diagnostics: diagnostics(fit.as_ref()),
                    at_normal_abs_err: case
                        .normal
                        .zip(exact_at_normal)
                        .map(|(n, e)| (fit.irradiance(n) - e).abs().max_element()),
                    fit_ns: None,
                    eval_ns: None,
                }
            })
            .collect();
        rows.extend(scored);
    }
    (rows, (cd.inputs, cd.light))
}

/// A fit's diagnostics as the table's `key=value;…` cell.
fn diagnostics(fit: &dyn Fitted) -> String {
    let cells: Vec<String> =
        fit.diagnostics().iter().map(|(k, v)| format!("{k}={}", crate::pipeline::table::num(*v))).collect();
    cells.join(";")
}

/// Evaluates a fit at every normal: E/π, in parallel, in the normals' order.
pub fn evaluate(fit: &dyn Fitted, normals: &[DVec3]) -> Vec<Rgb> {
    normals.par_iter().with_min_len(256).map(|&n| fit.irradiance(n)).collect()
}

/// The one scoring step every table, sweep, claim and sheet goes through: `fit` (of
/// `encoder`) evaluated on `grid` against the reference values there, under `metric`'s
/// weighting (solid angle for `exact`, one per pixel for `probulator`) and, under
/// `probulator`, the peer's clamp of negative output where the encoder's shader clamps.
pub fn score_fit(
    encoder: &dyn Encoder,
    fit: &dyn Fitted,
    grid: &OutputGrid,
    reference: &[Rgb],
    metric: Metric,
) -> Scores {
    score_values(encoder, &evaluate(fit, &grid.normals), grid, reference, metric)
}

/// [`score_fit`] for a fit already evaluated at every normal of `grid` (`test`, from
/// [`evaluate`]), for a caller that also needs the values.
pub fn score_values(
    encoder: &dyn Encoder,
    test: &[Rgb],
    grid: &OutputGrid,
    reference: &[Rgb],
    metric: Metric,
) -> Scores {
    let clamp = metric == Metric::Probulator && encoder.peer_clamps();
    match metric {
        Metric::Exact => score(reference, test, &grid.weights, clamp),
        Metric::Probulator => score(reference, test, &vec![1.0; grid.normals.len()], clamp),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::cases::cone_centre;
    use crate::reference::domain::expand_orientations;

    /// Self-bounce on a constant map of radiance A (FORMULAS §8; `Effect::SelfBounce`). The
    /// visible light is A over the upper hemisphere about N, so the exact E/π is A·H(n′) with
    /// H(n′) = (1 + n′·N)/2 and I_z = A·H(N) = A; the bounce adds ρ·A·(1 − H(n′)). So the
    /// reference is A·(H + ρ(1 − H)) in closed form. The wrapper around sh2 (whose L2 SH
    /// irradiance of a hemisphere step is exact: its even bands ≥ 2 vanish) is then exact,
    /// and sh2 alone misses exactly ρ·A·(1 − H), whose solid-angle RMS over the hemisphere
    /// about N is ρ·A·√(∫₀¹ ((1 − μ)/2)² dμ) = ρ·A/√12.
    #[test]
    fn self_bounce_on_a_constant_map_is_the_closed_form() {
        let a = Rgb::new(0.7, 1.1, 0.4);
        let (w, h) = (64, 32);
        let map = EnvMap::new("const", w, h, vec![[a.x as f32, a.y as f32, a.z as f32]; w * h]).unwrap();
        let a = Rgb::new(0.7f32 as f64, 1.1f32 as f64, 0.4f32 as f64);
        let text = "maps = ['const']\nencoders = ['sh2', { kind = 'with_self_bounce', inner = 'sh2', name = 'sb' }]\n\
                    domain = 'hemisphere'\norientations = ['axes6']\nresolution = [64, 32]\npolar_nodes = 8\n\
                    effects = ['hemisphere', { kind = 'self_bounce', albedo = [0.0, 0.5, 0.8] }]\n";
        let exp = Experiment::parse(text, std::path::Path::new("t.toml")).unwrap();
        let data = MapData::new(&map);
        let all = cases(&exp);
        assert_eq!(all.len(), 18);
        for case in &all {
            let (n, rho) = (case.normal.unwrap(), case.albedo.unwrap());
            assert_eq!(case.effects_label, format!("hemisphere+self_bounce(albedo={rho})"));
            let cd = CaseData::new(&data, case, exp.polar_nodes);
            let grid = case.domain.output_grid(exp.resolution);
            let plain = cd.reference.irradiance_many(&grid.normals);
            for ((np, got), p) in grid.normals.iter().zip(cd.reference_on(&grid)).zip(plain) {
                let hn = 0.5 * (1.0 + np.dot(n));
                // The added term to rounding; the whole against the closed form within the
                // reference's polar quadrature where a wall's horizon cuts the rows (8 nodes:
                // 1.2e-9; the default 2: 1e-6).
                let bounce = a * (rho * (1.0 - hn));
                assert!((got - p - bounce).abs().max_element() < 1e-14, "N={n} n'={np}");
                let want = a * (hn + rho * (1.0 - hn));
                assert!((got - want).abs().max_element() < 1e-8, "N={n} n'={np}: {got} vs {want}");
            }
        }
        let rows = run_map(&exp, &map, &RunSettings::default());
        assert_eq!(rows.len(), 36);
        for r in &rows {
            let rho: f64 = r.effects.split("albedo=").nth(1).unwrap().trim_end_matches(')').parse().unwrap();
            let case = all.iter().find(|c| c.domain_label == r.domain && c.albedo == Some(rho)).unwrap();
            let grid = case.domain.output_grid(exp.resolution);
            // The missing term's RMS with the grid's own solid-angle weights (the table's
            // quadrature), and its continuous value ρ·|A|/√3/√12 (the 16-row grid is 1.4e-3 off).
            let n = case.normal.unwrap();
            let (mut num, mut den) = (0.0, 0.0);
            for (np, w) in grid.normals.iter().zip(&grid.weights) {
                let miss = rho * 0.5 * (1.0 - np.dot(n));
                num += w * miss * miss;
                den += w;
            }
            let on_grid = (num / den).sqrt() * a.length() / 3f64.sqrt();
            let continuous = rho * a.length() / 3f64.sqrt() / 12f64.sqrt();
            assert!((on_grid - continuous).abs() <= 5e-3 * continuous.max(1e-300) + 1e-15, "{on_grid} vs {continuous}");
            let want = if r.encoder == "sb" { 0.0 } else { on_grid };
            assert!(
                (r.scores.rmse - want).abs() < 1e-8,
                "{} {} {}: {} vs {want}",
                r.encoder,
                r.domain,
                r.effects,
                r.scores.rmse
            );
        }
    }

    #[test]
    fn self_bounce_needs_the_hemisphere_and_a_valid_albedo() {
        let err = |effects: &str| {
            let text = format!(
                "maps = ['a']\nencoders = ['sh2']\norientations = ['up']\ndomain = 'hemisphere'\neffects = {effects}\n"
            );
            format!("{:#}", Experiment::parse(&text, std::path::Path::new("e.toml")).err().expect("must fail"))
        };
        let e = err("[{ kind = 'self_bounce', albedo = 0.5 }]");
        assert!(e.starts_with("e.toml:5:") && e.contains("needs the hemisphere effect"), "{e}");
        assert!(err("['hemisphere', { kind = 'self_bounce', albedo = 1.5 }]").contains("must lie in [0, 1]"));
        assert!(err("['hemisphere', { kind = 'self_bounce' }]").contains("needs 'albedo'"));
        assert!(err("['hemisphere', { kind = 'self_bounce', albedo = [] }]").contains("at least one"));
        assert!(err("['hemisphere', { kind = 'self_bounce', albedo = 0.5, x = 1 }]").contains("unknown key 'x'"));
        assert!(err("['hemisphere', 'self_bounce']").contains("needs an albedo"));
        let twice =
            err("['hemisphere', { kind = 'self_bounce', albedo = 0.5 },\n { kind = 'self_bounce', albedo = 0.2 }]");
        assert!(twice.contains("twice"), "{twice}");
    }

    /// The cone cases of one surface normal, their references evaluated together and kept
    /// (a map with a pixel sha256), score exactly as when each case computes its own (the same
    /// map without one, so nothing is kept): every row equal bit for bit. One computation per
    /// orientation, every case's reference then handed back from the cache.
    #[test]
    fn cones_evaluated_together_score_as_one_by_one() {
        let map =
            EnvMap::from_fn("m", 64, 32, |i, j| [1.0 + ((i * 5 + j * 3) % 7) as f32, 0.5, j as f32 * 0.1]).unwrap();
        let mut kept = map.clone();
        kept.pixel_sha256 = Some("0".repeat(64));
        let text = "maps = ['m']\nencoders = ['sh2', 'cone_multiply']\ndomain = 'hemisphere'\n\
                    orientations = ['+y', '-y', '+x']\nresolution = [32, 16]\n\
                    effects = [{ kind = 'cone', cos_alpha = [0.0, 0.5, 0.9], tilt_deg = [0, 30] }]\n";
        let exp = Experiment::parse(text, std::path::Path::new("t.toml")).unwrap();
        let settings = RunSettings { timing: false, ..RunSettings::default() };
        let cache = ReferenceCache::new(None);
        let together = run_map_reusing(&exp, &kept, &settings, &cache);
        let alone = run_map(&exp, &map, &settings);
        assert_eq!(together.len(), 3 * 6 * 2);
        for (t, a) in together.iter().zip(&alone) {
            assert_eq!(t, a, "{} {} {}", t.domain, t.effects, t.encoder);
        }
        assert_eq!(cache.counts(), (3, 18));
    }

    /// The cone centre is N tilted by exactly `tilt_deg`, for every orientation (including the
    /// poles, where `frame_to` has its degenerate antiparallel case), and unit length.
    #[test]
    fn cone_centre_is_n_tilted_by_the_angle() {
        let mut normals: Vec<DVec3> = expand_orientations("axes6").unwrap().into_iter().map(|o| o.normal).collect();
        normals.extend(expand_orientations("fibonacci32").unwrap().into_iter().map(|o| o.normal));
        for n in normals {
            for t in [0.0f64, 10.0, 30.0, 90.0] {
                let c = cone_centre(n, t);
                assert!((c.length() - 1.0).abs() < 1e-12);
                let angle = c.dot(n).clamp(-1.0, 1.0).acos().to_degrees();
                assert!((angle - t).abs() < 1e-6, "N={n} tilt {t}: {angle}");
            }
        }
    }
}
