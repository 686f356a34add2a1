//! How long a command's map × case × encoder work will take, estimated before any map is
//! loaded, so that a setting that would run for hours is refused at once instead of starting
//! silently (`--allow-long` runs it anyway). The model and its constants are documented in
//! docs/robustness.md ("Long runs") and docs/decisions.md; the figures they come from in
//! benches/README.md.
//!
//! The model counts the work the runner does (`runner.rs`) in core-nanoseconds:
//!
//! - per map: decoding, hashing, row moments and the SH projection, [`LOAD_NS_PER_TEXEL`] per
//!   texel of the map (its size read from the file's header, `envmap::load::dimensions`);
//! - per case and output grid: the exact reference, whose cost is the grid's normals × the
//!   map's row pieces (its rows, at least 128: coarser maps are cut into pieces of π/128) × the
//!   polar nodes, [`CONV_NS`] each on the sphere without caps (the row convolution), and
//!   [`CAPPED_NS`] each plus [`CAPPED_NORMAL_NS`] per normal with caps or on a hemisphere; and
//!   [`REF_NS_PER_TEXEL`] per map texel (each row's moments rebuilt);
//! - per case: the visible light some encoders read, the capped reference on
//!   [`CASE_NORMALS`] normals and [`CASE_NS_PER_TEXEL`] per map texel;
//! - per case and encoder: a fit, [`FIT_NS`], and an evaluation per scored normal,
//!   [`EVAL_NS`];
//! - the timing pass (sequential): per case and encoder, [`TIMING_NS`] plus
//!   [`TIMING_REPEATS`] fits and evaluations of up to 1024 normals.
//!
//! Parallel work is divided by the worker threads; the timing pass is not. The constants are
//! the slowest of the calibration runs on the 2-core reference machine, rounded up, so the
//! estimate errs long (by up to about 3× on small runs, where fixed costs dominate) but not
//! absurdly. [`BOUND_S`] is the longest run accepted without `--allow-long`.

use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::{DomainKind, Effect, Experiment};
use crate::pipeline::sweep::{Knob, Sweep};
use crate::reference::metrics::Metric;
use anyhow::{bail, Result};
use std::fmt;

/// The longest estimated run accepted without `--allow-long`: 30 minutes. Every committed
/// experiment, sweep and `reproduce` as a whole stays far below it (the longest, a few
/// minutes); an hour-long run is worth a flag.
pub const BOUND_S: f64 = 30.0 * 60.0;

/// Core-ns per map texel: decode, sha256, row moments, SH projection.
pub const LOAD_NS_PER_TEXEL: f64 = 150.0;
/// Core-ns per output normal × row piece × polar node: the row convolution (sphere, no caps).
pub const CONV_NS: f64 = 8.0;
/// Core-ns per map texel of each reference on an output grid: every input row's moments are
/// rebuilt and regrouped (a 16384×8192 map: about 16 CPU s for 256×128 normals).
pub const REF_NS_PER_TEXEL: f64 = 150.0;
/// Core-ns per output normal × row piece × polar node: the capped reference (per normal).
pub const CAPPED_NS: f64 = 10.0;
/// Core-ns per output normal of the capped reference beyond its rows: the kernel, the caps'
/// arcs, the output grid.
pub const CAPPED_NORMAL_NS: f64 = 6_000.0;
/// Normals of the fixed grids whose exact E/π the visible light caches for the encoders that
/// fit it, per case (at the capped reference's cost).
pub const CASE_NORMALS: f64 = 2_048.0;
/// Core-ns per case × map texel: the visible light's SH through band 4 and the masked
/// projection, which read every texel.
pub const CASE_NS_PER_TEXEL: f64 = 20.0;
/// Core-ns per fit (case × encoder): about twice the mean fit of the committed tables'
/// encoder sets (the multi-start solves and searches dominate).
pub const FIT_NS: f64 = 5.0e5;
/// Core-ns per encoder evaluation at one scored normal, with its scoring: about twice the
/// mean `eval_ns` of the committed tables' encoder sets.
pub const EVAL_NS: f64 = 400.0;
/// Wall ns per case × encoder of the timing pass beyond its fits and evaluations.
pub const TIMING_NS: f64 = 5.0e5;
/// Fits the timing pass makes per case × encoder (warm-up, a batch, at least five repeats),
/// and evaluations per timed normal.
pub const TIMING_REPEATS: f64 = 7.0;
/// The fewest row pieces a map's reference integrates (coarse rows are cut at π/128).
const MIN_ROW_PIECES: usize = 128;
/// Evaluations a sweep's timing makes of what it times (warm-up, a batch, five repeats, the
/// scored one).
const SWEEP_REPEATS: f64 = 8.0;

/// An estimate of a command's run time and what drives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// Estimated wall time in seconds.
    pub seconds: f64,
    /// What drives it, in words ("4096 cases × 12 encoders × 2048×1024 output normals …").
    pub drivers: String,
}

impl Estimate {
    /// Whether the estimate exceeds [`BOUND_S`].
    pub fn is_long(&self) -> bool {
        self.seconds > BOUND_S
    }

    /// The sum of several estimates; the drivers of the largest part are kept.
    pub fn total(parts: &[Estimate]) -> Estimate {
        let seconds = parts.iter().map(|p| p.seconds).sum();
        let drivers =
            parts.iter().max_by(|a, b| a.seconds.total_cmp(&b.seconds)).map(|p| p.drivers.clone()).unwrap_or_default();
        Estimate { seconds, drivers }
    }

    /// Refuses the run when it is estimated above [`BOUND_S`] and `allow_long` is off; the
    /// error names `what` (the experiment file), the estimate, what drives it and the way out.
    pub fn refuse_if_long(&self, what: &str, allow_long: bool) -> Result<()> {
        if allow_long || !self.is_long() {
            return Ok(());
        }
        bail!(
            "{what}: estimated {} on {} worker thread(s): {}; that is above the {} bound for a run \
             (docs/robustness.md, \"Long runs\"). Pass --allow-long to run it anyway, or lower the \
             resolution, orientations, effect parameters, maps or encoders",
            duration(self.seconds),
            threads(),
            self.drivers,
            duration(BOUND_S)
        )
    }
}

impl fmt::Display for Estimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", duration(self.seconds), self.drivers)
    }
}

/// A duration in words: "45 s", "12 min", "3.5 h", "4.1 days".
pub fn duration(seconds: f64) -> String {
    match seconds {
        s if s < 90.0 => format!("{:.0} s", s.max(0.0)),
        s if s < 90.0 * 60.0 => format!("{:.0} min", s / 60.0),
        s if s < 36.0 * 3600.0 => format!("{:.1} h", s / 3600.0),
        s => format!("{:.1} days", s / 86400.0),
    }
}

/// The worker threads parallel work is divided among.
fn threads() -> usize {
    rayon::current_num_threads().max(1)
}

/// The cases an experiment declares (surface normals × effect parameter combinations), counted
/// as `runner::cases` builds them.
pub fn case_count(exp: &Experiment) -> usize {
    if exp.orientations.is_empty() {
        return 1;
    }
    let variants: usize = exp
        .effects
        .iter()
        .map(|e| match e {
            Effect::Hemisphere => 1,
            Effect::SelfBounce { albedo } => albedo.len(),
            Effect::Cone { cos_alpha, tilt_deg } => cos_alpha.len() * tilt_deg.len(),
        })
        .product();
    exp.orientations.len() * variants
}

/// One output grid a case is scored on: its normals and whether the reference on it is the
/// row convolution (sphere, no caps).
struct Grid {
    normals: f64,
    convolution: bool,
}

/// The distinct output grids of an experiment's metrics (as `runner::run_case` builds them).
fn grids(exp: &Experiment, resolution: (usize, usize)) -> Vec<Grid> {
    let capped = !exp.effects.is_empty();
    let mut seen: Vec<((usize, usize), bool)> = Vec::new();
    let mut out = Vec::new();
    for m in &exp.metrics {
        let (res, sphere) = match m {
            Metric::Probulator => ((256, 128), true),
            Metric::Exact => (resolution, exp.domain == DomainKind::Sphere),
        };
        if seen.contains(&(res, sphere)) {
            continue;
        }
        seen.push((res, sphere));
        let rows = if sphere { res.1 } else { res.1 / 2 };
        out.push(Grid { normals: (res.0 * rows) as f64, convolution: sphere && !capped });
    }
    out
}

/// Core-ns of the capped reference at `normals` normals, `pieces` row pieces × nodes each.
fn capped(normals: f64, pieces: f64) -> f64 {
    normals * (CAPPED_NORMAL_NS + pieces * CAPPED_NS)
}

/// Core-ns (parallel) and wall ns (the sequential timing pass) of one map's work in `exp` at
/// `resolution`, with `polar_nodes`; the timing pass counts only when it runs (`timing`).
fn map_work(
    exp: &Experiment,
    size: (usize, usize),
    resolution: (usize, usize),
    polar_nodes: usize,
    timing: bool,
) -> (f64, f64) {
    let texels = (size.0 * size.1) as f64;
    let pieces = (size.1.max(MIN_ROW_PIECES) * polar_nodes) as f64;
    let cases = case_count(exp) as f64;
    let encoders = exp.encoders.len() as f64;
    let grids = grids(exp, resolution);
    let reference: f64 = grids
        .iter()
        .map(|g| {
            let per_normal = if g.convolution { g.normals * pieces * CONV_NS } else { capped(g.normals, pieces) };
            REF_NS_PER_TEXEL * texels + per_normal
        })
        .sum();
    let largest = grids.iter().map(|g| g.normals).fold(0.0, f64::max);
    let scored = exp.metrics.len() as f64 * largest;
    let light = capped(CASE_NORMALS, pieces) + CASE_NS_PER_TEXEL * texels;
    let per_case = reference + light + encoders * (FIT_NS + EVAL_NS * scored);
    let parallel = LOAD_NS_PER_TEXEL * texels + cases * per_case;
    let timed = largest.min(crate::pipeline::timing::EVAL_NORMALS as f64);
    let timing = match timing {
        true => cases * encoders * (TIMING_NS + TIMING_REPEATS * (FIT_NS + EVAL_NS * timed)),
        false => 0.0,
    };
    (parallel, timing)
}

/// The estimate of running `exp` on maps of the given sizes (width, height), with the timing
/// pass.
#[cfg(test)]
pub fn experiment_on(exp: &Experiment, sizes: &[(usize, usize)]) -> Estimate {
    experiment_timed(exp, sizes, true)
}

/// [`experiment_on`], with the timing pass only if `timing` (`RunSettings::timing`).
pub fn experiment_timed(exp: &Experiment, sizes: &[(usize, usize)], timing: bool) -> Estimate {
    let (mut parallel, mut sequential) = (0.0, 0.0);
    for &size in sizes {
        let (p, s) = map_work(exp, size, exp.resolution, exp.polar_nodes, timing);
        parallel += p;
        sequential += s;
    }
    Estimate { seconds: (parallel / threads() as f64 + sequential) * 1e-9, drivers: drivers(exp, sizes) }
}

/// What drives an experiment's estimate, in words.
fn drivers(exp: &Experiment, sizes: &[(usize, usize)]) -> String {
    let cases = case_count(exp);
    let what = if exp.orientations.is_empty() {
        "1 case".to_string()
    } else if cases == exp.orientations.len() {
        format!("{cases} orientation(s)")
    } else {
        format!(
            "{cases} cases ({} orientation(s) × {} effect setting(s))",
            exp.orientations.len(),
            cases / exp.orientations.len().max(1)
        )
    };
    let (w, h) = exp.resolution;
    let out = match exp.domain {
        DomainKind::Sphere => format!("{w}×{h} output normals"),
        DomainKind::Hemisphere => format!("{w}×{} output normals (hemisphere of {w}×{h})", h / 2),
    };
    let largest = sizes.iter().max_by_key(|s| s.0 * s.1).map(|(w, h)| format!(", up to {w}×{h}")).unwrap_or_default();
    format!(
        "{what} × {} encoder(s) × {out} on {} map(s){largest}, {} polar node(s)",
        exp.encoders.len(),
        sizes.len(),
        exp.polar_nodes
    )
}

/// The sizes of an experiment's maps found on the search path, read from their headers (no
/// pixel is decoded); a map not found or whose header cannot be read is left out (the run
/// reports it).
pub fn map_sizes(exp: &Experiment, search: &SearchPath) -> Vec<(usize, usize)> {
    exp.maps
        .iter()
        .filter_map(|name| search.resolve(name).ok())
        .filter_map(|path| crate::envmap::load::dimensions(&path).ok())
        .collect()
}

/// The estimate of running `exp` on the maps the search path finds, with the timing pass only
/// if `timing`.
pub fn experiment(exp: &Experiment, search: &SearchPath, timing: bool) -> Estimate {
    experiment_timed(exp, &map_sizes(exp, search), timing)
}

/// The estimate of a sweep on maps of the given sizes: at each value, the reference (and for
/// `out_resolution` every encoder's evaluation) about [`SWEEP_REPEATS`] times over for its
/// timing, the encoders' fits and scores, and the converged reference once per case.
pub fn sweep_on(sweep: &Sweep, sizes: &[(usize, usize)]) -> Estimate {
    let exp = &sweep.exp;
    let mut parallel = 0.0;
    for &size in sizes {
        for v in &sweep.values {
            let (res, nodes) = match (&sweep.knob, v) {
                (Knob::OutResolution, toml::Value::String(s)) => {
                    (crate::pipeline::experiment::parse_resolution(s).unwrap_or(exp.resolution), exp.polar_nodes)
                }
                (Knob::PolarNodes, toml::Value::Integer(q)) => (exp.resolution, (*q).clamp(1, 16) as usize),
                _ => (exp.resolution, exp.polar_nodes),
            };
            parallel += SWEEP_REPEATS * map_work(exp, size, res, nodes, false).0;
        }
        parallel += map_work(exp, size, exp.resolution, sweep.converged_polar_nodes, false).0;
    }
    let mut drivers = drivers(exp, sizes);
    drivers.push_str(&format!(", {} value(s) of {}", sweep.values.len(), sweep.knob.name()));
    // A sweep runs sequentially (each value timed in turn): no division by the threads.
    Estimate { seconds: parallel * 1e-9, drivers }
}

/// The estimate of a sweep on the maps the search path finds.
pub fn sweep(sweep: &Sweep, search: &SearchPath) -> Estimate {
    sweep_on(sweep, &map_sizes(&sweep.exp, search))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn exp(text: &str) -> Experiment {
        Experiment::parse(text, Path::new("e.toml")).unwrap()
    }

    const SPHERE: &str = "maps = ['a']\nencoders = ['sh1', 'sh2']\n";
    const HEMI: &str = "maps = ['a']\nencoders = ['sh1', 'sh2']\ndomain = 'hemisphere'\neffects = ['hemisphere']\n";

    /// More of anything the work scales with never shortens the estimate, and the big knobs
    /// lengthen it about in proportion.
    #[test]
    fn more_work_is_estimated_longer() {
        let maps = [(256, 128)];
        let at = |text: &str| experiment_on(&exp(text), &maps).seconds;
        let base = at(&format!("{SPHERE}resolution = [512, 256]\n"));
        let double = at(&format!("{SPHERE}resolution = [1024, 512]\n"));
        assert!(double > 3.0 * base, "{double} vs {base}");
        let hemi = |o: &str| at(&format!("{HEMI}orientations = ['{o}']\n"));
        assert!(hemi("fibonacci64") > 1.9 * hemi("fibonacci32"));
        assert!(hemi("axes6") > hemi("up"));
        let e = exp(SPHERE);
        assert!(experiment_on(&e, &[(1024, 512)]).seconds > experiment_on(&e, &[(256, 128)]).seconds);
        assert!(experiment_on(&e, &[(256, 128), (256, 128)]).seconds > experiment_on(&e, &maps).seconds);
        let more = exp("maps = ['a']\nencoders = ['sh1', 'sh2', 'sh0']\n");
        assert!(experiment_on(&more, &maps).seconds > experiment_on(&e, &maps).seconds);
        let nodes = exp(&format!("{SPHERE}polar_nodes = 8\n"));
        assert!(experiment_on(&nodes, &maps).seconds > experiment_on(&e, &maps).seconds);
    }

    /// The largest output grid on a hemisphere about six normals, and 4096 normals, on six
    /// small maps are refused, naming the file, the estimate and what drives it; the defaults
    /// are not.
    #[test]
    fn huge_settings_are_refused_and_defaults_are_not() {
        let maps = [(256, 128); 6];
        let big = experiment_on(&exp(&format!("{HEMI}orientations = ['axes6']\nresolution = [8192, 4096]\n")), &maps);
        let msg = format!("{:#}", big.refuse_if_long("e.toml", false).unwrap_err());
        assert!(msg.starts_with("e.toml: estimated ") && msg.contains("8192×2048 output normals"), "{msg}");
        assert!(msg.contains("--allow-long") && msg.contains("6 orientation(s)"), "{msg}");
        assert!(big.refuse_if_long("e.toml", true).is_ok());
        let many =
            experiment_on(&exp(&format!("{HEMI}orientations = ['fibonacci4096']\nresolution = [512, 256]\n")), &maps);
        assert!(many.is_long() && many.drivers.contains("4096 orientation(s)"), "{many}");
        assert!(!experiment_on(&exp(SPHERE), &maps).is_long());
        assert!(!experiment_on(&exp(&format!("{HEMI}orientations = ['axes6']\n")), &maps).is_long());
    }

    /// The cases are counted as the runner builds them.
    #[test]
    fn case_count_matches_the_runner() {
        for text in [
            SPHERE.to_string(),
            format!("{HEMI}orientations = ['axes6', 'fibonacci32']\n"),
            "maps = ['a']\nencoders = ['sh2']\ndomain = 'hemisphere'\norientations = ['axes6']\neffects = ['hemisphere', \
             { kind = 'self_bounce', albedo = [0.2, 0.5] }, { kind = 'cone', cos_alpha = [0.0, 0.5, 0.9], tilt_deg = [0, 30] }]\n"
                .to_string(),
        ] {
            let e = exp(&text);
            assert_eq!(case_count(&e), crate::pipeline::runner::cases(&e).len(), "{text}");
        }
    }

    #[test]
    fn durations_read_in_words() {
        assert_eq!(duration(12.4), "12 s");
        assert_eq!(duration(1800.0), "30 min");
        assert_eq!(duration(3.5 * 3600.0), "3.5 h");
        assert_eq!(duration(4.1 * 86400.0), "4.1 days");
    }
}
