//! Sweeps: vary one accuracy knob and record error against time (`probelab sweep`).
//!
//! A sweep file (`experiments/sweeps/*.toml`) is an experiment file (maps, encoders, domain,
//! orientations, effects, resolution, polar_nodes; see `experiment.rs`) plus:
//!
//! | key                     | type          | default | meaning |
//! |-------------------------|---------------|---------|---------|
//! | `knob`                  | string        | required| what varies (table below) |
//! | `values`                | array         | required| its values, least to most accurate |
//! | `converged_polar_nodes` | integer       | 16      | GL nodes of the converged reference |
//!
//! | knob             | values            | what varies | `rmse` of `encoder = "reference"` rows | `time_ns` |
//! |------------------|-------------------|-------------|----------------------------------------|-----------|
//! | `ref_resolution` | "WxH" or "full"   | the map is area-averaged to W×H (solid-angle weighted, exact cell energies) before the reference and the encoders' SH are computed | the reduced reference vs the converged reference | reference: row moments + reference on the output grid; encoders: SH projection of the map + fit |
//! | `polar_nodes`    | 1..=16            | Gauss–Legendre nodes per row piece of the reference (and of masked projections) | the reference vs the converged reference | reference: on the output grid; encoders: fit |
//! | `out_resolution` | "WxH"             | the output grid of normals the RMSE is estimated on | (no reference rows) | reference + encoder evaluation + scoring on that grid |
//! | `encoder.KEY`    | any TOML value    | setting KEY of every listed encoder (a `Params` key: golden-section iterations, BFGS tolerance, multi-start count, …) | (no reference rows) | fit (median per probe/texel) |
//!
//! Encoder rows carry the encoder's RMSE against the converged reference (`ref_resolution`,
//! `polar_nodes`) or the exact reference at the experiment's `polar_nodes` (the other knobs).
//! Sweeps score with the exact metric (solid-angle weighted over the domain); values larger than
//! a map (a `ref_resolution` above its size) are skipped for that map.
//!
//! ## Output: `results/sweeps/<name>.csv`
//!
//! `sweep,knob,value,map,encoder,domain,rmse,delta_vs_last,rel_rmse,time_ns,timed,error_of,resolution,weighting,units`
//! - `rmse`, `rel_rmse`: E/π over the domain, solid-angle weighted (as in tables);
//! - `delta_vs_last`: |rmse − rmse at the sweep's last value| for the same map, domain and
//!   encoder (the convergence of the estimate);
//! - `time_ns`: median wall time of what `timed` names (`timing.rs` method); it varies run to run.

use crate::envmap::search::SearchPath;
use crate::envmap::{EnvMap, LatLong};
use crate::io::profile::{self, Profile};
use crate::math::colour::Rgb;
use crate::pipeline::experiment::{Experiment, ExperimentFile};
use crate::pipeline::runner::{cases, score_fit, Case, CaseData, MapData};
use crate::pipeline::timing::median_ns_with;
use crate::reference::domain::OutputGrid;
use crate::reference::exact::Reference;
use crate::reference::metrics::{score, Metric, Scores};
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// The knob a sweep varies.
#[derive(Clone, Debug, PartialEq)]
pub enum Knob {
    /// `ref_resolution`: the map is area-averaged to a coarser grid first.
    RefResolution,
    /// `polar_nodes`: Gauss–Legendre nodes per row piece of the reference.
    PolarNodes,
    /// `out_resolution`: the output grid of normals the RMSE is estimated on.
    OutResolution,
    /// `encoder.KEY`: a setting of every listed encoder (the key name held).
    EncoderKey(String),
}

impl Knob {
    fn parse(s: &str) -> Result<Self> {
        Ok(match s {
            "ref_resolution" => Knob::RefResolution,
            "polar_nodes" => Knob::PolarNodes,
            "out_resolution" => Knob::OutResolution,
            _ => match s.strip_prefix("encoder.") {
                Some(k) if !k.is_empty() => Knob::EncoderKey(k.to_string()),
                _ => bail!(
                    "knob '{s}': expected ref_resolution, polar_nodes, out_resolution or encoder.KEY",
                    s = crate::math::echo::value(s)
                ),
            },
        })
    }
    /// The knob's name as a sweep file writes it.
    pub fn name(&self) -> String {
        match self {
            Knob::RefResolution => "ref_resolution".into(),
            Knob::PolarNodes => "polar_nodes".into(),
            Knob::OutResolution => "out_resolution".into(),
            Knob::EncoderKey(k) => format!("encoder.{k}"),
        }
    }

    /// The knob as a chart's axis, in words with its unit, and whether its values are sizes
    /// (widths in px, drawn on a log2 axis).
    pub fn axis(&self) -> (String, bool) {
        match self {
            Knob::RefResolution => ("width W of the reference map (area-averaged to W×H), px".into(), true),
            Knob::PolarNodes => ("Gauss–Legendre nodes per row piece of the reference".into(), false),
            Knob::OutResolution => ("width W of the output grid (W×H normals scored), px".into(), true),
            Knob::EncoderKey(k) => (format!("encoder setting {k} (every encoder of the sweep)"), false),
        }
    }

    /// [`Knob::axis`] of a knob named as a sweep file writes it; None for another name.
    pub fn axis_of(name: &str) -> Option<(String, bool)> {
        Knob::parse(name).ok().map(|k| k.axis())
    }
}

/// A validated sweep.
pub struct Sweep {
    /// Name of the sweep: its experiment's name (by default the file stem).
    pub name: String,
    /// What the sweep varies.
    pub knob: Knob,
    /// The knob's values, least to most accurate.
    pub values: Vec<toml::Value>,
    /// Gauss–Legendre nodes of the converged reference.
    pub converged_polar_nodes: usize,
    /// The experiment table without the sweep keys (re-validated per value for `encoder.KEY`).
    base: toml::Table,
    /// The experiment at the base settings.
    pub exp: Experiment,
}

/// The text of a value in the CSV ("64x32", "4", "1e-6").
fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Parses "WxH" or "full" (None).
fn parse_res_value(v: &toml::Value, allow_full: bool) -> Result<Option<(usize, usize)>> {
    match v {
        toml::Value::String(s) if allow_full && s == "full" => Ok(None),
        toml::Value::String(s) => crate::pipeline::experiment::parse_resolution(s).map(Some),
        _ => bail!(
            "value {v}: expected \"WxH\"{}",
            if allow_full { " or \"full\"" } else { "" },
            v = crate::math::echo::value(&v.to_string())
        ),
    }
}

impl Sweep {
    /// Reads and validates a sweep file; errors name the file.
    pub fn load(path: &Path) -> Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("{}: cannot read sweep file", path.display()))?;
        let table: toml::Table = crate::pipeline::experiment::parse_toml(&text, path)?;
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("sweep").to_string();
        Self::from_table(table, &stem).with_context(|| format!("{}", path.display()))
    }

    /// Validates a parsed sweep table: the sweep keys and the experiment around them, named
    /// `default_name` unless the table names it. An error names the bad key.
    pub fn from_table(mut t: toml::Table, default_name: &str) -> Result<Self> {
        let knob = match t.remove("knob") {
            Some(toml::Value::String(s)) => Knob::parse(&s)?,
            _ => bail!("knob: required, a string (ref_resolution, polar_nodes, out_resolution or encoder.KEY)"),
        };
        let values = match t.remove("values") {
            Some(toml::Value::Array(a)) if !a.is_empty() => a,
            _ => bail!("values: required, a non-empty array"),
        };
        let converged_polar_nodes = match t.remove("converged_polar_nodes") {
            None => 16,
            Some(toml::Value::Integer(i)) if (1..=16).contains(&i) => i as usize,
            Some(v) => {
                bail!("converged_polar_nodes {v}: expected 1..=16", v = crate::math::echo::value(&v.to_string()))
            }
        };
        if t.contains_key("metrics") {
            bail!("metrics: sweeps always score with the exact metric; remove the key");
        }
        let exp = Self::experiment(&t, default_name)?;
        let sweep = Sweep { name: exp.name.clone(), knob, values, converged_polar_nodes, base: t, exp };
        // Validate every value up front.
        for v in &sweep.values {
            match &sweep.knob {
                Knob::RefResolution => {
                    parse_res_value(v, true)?;
                }
                Knob::OutResolution => {
                    parse_res_value(v, false)?;
                }
                Knob::PolarNodes => match v {
                    toml::Value::Integer(i) if (1..=16).contains(i) => {}
                    _ => bail!(
                        "values: polar_nodes {v}: expected an integer 1..=16",
                        v = crate::math::echo::value(&v.to_string())
                    ),
                },
                Knob::EncoderKey(_) => {
                    sweep.experiment_at(v)?;
                }
            }
        }
        Ok(sweep)
    }

    fn experiment(t: &toml::Table, name: &str) -> Result<Experiment> {
        let file: ExperimentFile = toml::Value::Table(t.clone()).try_into().map_err(|e| anyhow::anyhow!("{e}"))?;
        Experiment::from_file(file, name)
    }

    /// The experiment with encoder setting KEY = v on every encoder (`encoder.KEY` knob).
    pub fn experiment_at(&self, v: &toml::Value) -> Result<Experiment> {
        let Knob::EncoderKey(key) = &self.knob else { unreachable!("encoder knob only") };
        let mut t = self.base.clone();
        if let Some(toml::Value::Array(encs)) = t.get_mut("encoders") {
            for e in encs.iter_mut() {
                let mut table = match e {
                    toml::Value::String(kind) => {
                        let mut m = toml::Table::new();
                        m.insert("kind".into(), toml::Value::String(kind.clone()));
                        m
                    }
                    toml::Value::Table(m) => m.clone(),
                    _ => bail!("encoders: expected strings or tables"),
                };
                table.insert(key.clone(), v.clone());
                *e = toml::Value::Table(table);
            }
        }
        Self::experiment(&t, &self.name).with_context(|| format!("{} = {v}", self.knob.name()))
    }
}

/// One row of a sweep CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The knob's value, as text ("64x32", "4").
    pub value: String,
    /// The map's name.
    pub map: String,
    /// The encoder's name, or "reference" for the reference's own row.
    pub encoder: String,
    /// Domain label, as in result tables.
    pub domain: String,
    /// RMSE of E/π over the domain, solid-angle weighted.
    pub rmse: f64,
    /// `rmse` relative to the RMS of the reference.
    pub rel_rmse: f64,
    /// Median wall time in ns of what `timed` names (varies run to run).
    pub time_ns: f64,
    /// What `time_ns` measured.
    pub timed: String,
    /// Which reference the error is against (converged or exact, with its map size and nodes).
    pub error_of: String,
    /// Output grid the error was estimated on ("WxH").
    pub resolution: String,
}

/// The sweep CSV columns.
pub const COLUMNS: &[&str] = &[
    "sweep",
    "knob",
    "value",
    "map",
    "encoder",
    "domain",
    "rmse",
    "delta_vs_last",
    "rel_rmse",
    "time_ns",
    "timed",
    "error_of",
    "resolution",
    "weighting",
    "units",
];

/// The sweep's rows as CSV.
pub fn to_csv(sweep: &Sweep, rows: &[SweepRow]) -> Result<Vec<u8>> {
    let last_value = sweep.values.last().map(value_text).unwrap_or_default();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS)?;
    let num = crate::pipeline::table::num;
    for r in rows {
        let last = rows
            .iter()
            .find(|o| o.value == last_value && o.map == r.map && o.encoder == r.encoder && o.domain == r.domain);
        w.write_record([
            sweep.name.clone(),
            sweep.knob.name(),
            r.value.clone(),
            r.map.clone(),
            r.encoder.clone(),
            r.domain.clone(),
            num(r.rmse),
            last.map(|l| num((r.rmse - l.rmse).abs())).unwrap_or_default(),
            num(r.rel_rmse),
            format!("{:.1}", r.time_ns),
            r.timed.clone(),
            r.error_of.clone(),
            r.resolution.clone(),
            "solid-angle".into(),
            "E/pi".into(),
        ])?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// The map area-averaged onto a coarser w×h lat-long grid: each output texel is the
/// solid-angle-weighted mean of the input over its cell, with fractional overlaps, so every
/// output cell keeps exactly the input's energy (up to f32 storage).
pub fn area_average(map: &EnvMap, w: usize, h: usize) -> Result<EnvMap> {
    let (wi, hi) = (map.width(), map.height());
    if w > wi || h > hi || w != 2 * h || h == 0 {
        bail!("cannot area-average a {wi}x{hi} map to {w}x{h} (expected 2:1, no larger than the map)");
    }
    if (w, h) == (wi, hi) {
        return Ok(map.clone());
    }
    let (gi, go) = (LatLong::new(wi, hi), LatLong::new(w, h));
    // Column overlaps in units of input columns: output column i covers [i·wi/w, (i+1)·wi/w).
    let col: Vec<Vec<(usize, f64)>> = (0..w)
        .map(|i| {
            let (a, b) = (i as f64 * wi as f64 / w as f64, (i + 1) as f64 * wi as f64 / w as f64);
            (a.floor() as usize..(b.ceil() as usize).min(wi))
                .map(|k| (k, (b.min(k as f64 + 1.0) - a.max(k as f64)).max(0.0)))
                .filter(|x| x.1 > 0.0)
                .collect()
        })
        .collect();
    let texels: Vec<[f32; 3]> = (0..h)
        .into_par_iter()
        .flat_map_iter(|j| {
            let (p0, p1) = (go.phi_edge(j), go.phi_edge(j + 1));
            let rows: Vec<(usize, f64)> = (0..hi)
                .filter_map(|r| {
                    let (a, b) = (gi.phi_edge(r).max(p0), gi.phi_edge(r + 1).min(p1));
                    (b > a).then(|| (r, a.cos() - b.cos()))
                })
                .collect();
            let norm = (wi as f64 / w as f64) * (p0.cos() - p1.cos());
            let col = &col;
            (0..w).map(move |i| {
                let mut acc = Rgb::ZERO;
                for &(r, rw) in &rows {
                    for &(k, cw) in &col[i] {
                        let t = map.texel(k, r);
                        acc += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64) * (rw * cw);
                    }
                }
                let v = acc / norm;
                [v.x as f32, v.y as f32, v.z as f32]
            })
        })
        .collect();
    Ok(EnvMap::new(map.name.clone(), w, h, texels)?)
}

/// The exact reference on an output grid (the fast lat-long path where it applies).
fn reference_on(reference: &Reference, grid: &OutputGrid) -> Vec<Rgb> {
    match grid.latlong {
        Some(ll) => reference.irradiance_latlong(ll),
        None => reference.irradiance_many(&grid.normals),
    }
}

/// Median wall time of a slow operation (batches ≥ 1 ms, about 50 ms of repeats, at least 5).
fn time_slow(mut f: impl FnMut()) -> f64 {
    median_ns_with(&mut f, Duration::from_millis(1), Duration::from_millis(50))
}

/// Runs a sweep on one in-memory map, its phases timed on `profile` if one is given.
pub fn sweep_map(sweep: &Sweep, map: &EnvMap, profile: Option<&Profile>) -> Result<Vec<SweepRow>> {
    sweep_map_with(sweep, map, &|v| Ok(sweep.experiment_at(v)?.encoders), profile)
}

/// [`sweep_map`] with the encoders of an `encoder.KEY` value built by `encoders_at` (the
/// registry, through [`Sweep::experiment_at`], in [`sweep_map`]).
pub fn sweep_map_with(
    sweep: &Sweep,
    map: &EnvMap,
    encoders_at: &dyn Fn(&toml::Value) -> Result<Vec<crate::encoders::NamedEncoder>>,
    profile: Option<&Profile>,
) -> Result<Vec<SweepRow>> {
    let exp = &sweep.exp;
    let full = MapData::new(map);
    let mut rows = Vec::new();
    for case in &cases(exp) {
        let grid = case.domain.output_grid(exp.resolution);
        let mut at = CaseSweep {
            sweep,
            map,
            full: &full,
            case,
            res_label: format!("{}x{}", grid.resolution.0, grid.resolution.1),
            grid,
            rows: &mut rows,
            profile,
        };
        match &sweep.knob {
            Knob::RefResolution | Knob::PolarNodes => at.reference_knob()?,
            Knob::OutResolution => at.out_resolution()?,
            Knob::EncoderKey(_) => at.encoder_key(encoders_at)?,
        }
    }
    Ok(rows)
}

/// One case of a sweep on one map: what every value of the knob is measured against, and the
/// rows it adds.
struct CaseSweep<'a> {
    sweep: &'a Sweep,
    map: &'a EnvMap,
    full: &'a MapData<'a>,
    case: &'a Case,
    grid: OutputGrid,
    res_label: String,
    rows: &'a mut Vec<SweepRow>,
    profile: Option<&'a Profile>,
}

impl CaseSweep<'_> {
    /// The label of the converged reference the reference knobs are scored against.
    fn converged_label(&self) -> String {
        let qc = self.sweep.converged_polar_nodes;
        format!("converged reference ({}x{} map, {qc} GL nodes)", self.map.width(), self.map.height())
    }

    /// The label of the exact reference the other knobs are scored against.
    fn exact_label(&self) -> String {
        let (w, h, q) = (self.map.width(), self.map.height(), self.sweep.exp.polar_nodes);
        format!("exact reference ({w}x{h} map, {q} GL nodes)")
    }

    /// Adds a row for `encoder` at the knob's value `value`.
    fn push(&mut self, value: &toml::Value, encoder: &str, scores: Scores, timing: (f64, String), of: (&str, &str)) {
        self.rows.push(SweepRow {
            value: value_text(value),
            map: self.map.name.clone(),
            encoder: encoder.into(),
            domain: self.case.domain_label.clone(),
            rmse: scores.rmse,
            rel_rmse: scores.rel_rmse,
            time_ns: timing.0,
            timed: timing.1,
            error_of: of.0.into(),
            resolution: of.1.into(),
        })
    }

    /// `ref_resolution` or `polar_nodes`: the reference (and every encoder) at each value,
    /// against the converged reference.
    fn reference_knob(&mut self) -> Result<()> {
        let (sweep, map, exp) = (self.sweep, self.map, &self.sweep.exp);
        let conv = {
            let _s = profile::span(self.profile, "sweep: converged reference");
            CaseData::new(self.full, self.case, sweep.converged_polar_nodes).reference_on(&self.grid)
        };
        let converged_label = self.converged_label();
        for v in &sweep.values {
            let (reduced, q) = match &sweep.knob {
                Knob::RefResolution => match parse_res_value(v, true)? {
                    None => (None, exp.polar_nodes),
                    Some((w, _)) if w > map.width() => continue,
                    Some((w, h)) => (Some(area_average(map, w, h)?), exp.polar_nodes),
                },
                // Cannot fail: `from_table` accepts only integers 1..=16 for polar_nodes.
                _ => (None, v.as_integer().expect("validated") as usize),
            };
            let input = reduced.as_ref().unwrap_or(map);
            let data = MapData::new(input);
            let cd = CaseData::new(&data, self.case, q);
            let values = {
                let _s = profile::span(self.profile, "sweep: swept reference");
                cd.reference_on(&self.grid)
            };
            let s = score(&conv, &values, &self.grid.weights, false);
            let timing = self.time_reference(input, q);
            // The reduced reference against the converged one: the "reference" row.
            let res_label = self.res_label.clone();
            self.push(v, "reference", s, timing, (&converged_label, &res_label));
            for named in &exp.encoders {
                let fit = named.encoder.fit(&cd.fit_input());
                let s = score_fit(named.encoder.as_ref(), fit.as_ref(), &self.grid, &conv, Metric::Exact);
                let timing = self.time_fit(named, &cd, input);
                self.push(v, &named.name, s, timing, (&converged_label, &res_label));
            }
        }
        Ok(())
    }

    /// The time of the reference at a reference knob's value, and what was timed.
    fn time_reference(&self, input: &EnvMap, q: usize) -> (f64, String) {
        let (case, grid, res_label) = (self.case, &self.grid, &self.res_label);
        let _timing = profile::span(self.profile, "sweep: timing repeats");
        if self.sweep.knob == Knob::RefResolution {
            let t = time_slow(|| {
                let m = crate::envmap::moments::RowMoments::new(input);
                black_box(reference_on(&Reference::new(&m, case.masks.clone(), q), grid));
            });
            (t, format!("row moments + reference on {res_label} normals ({}x{} map)", input.width(), input.height()))
        } else {
            let t = time_slow(|| {
                black_box(reference_on(&Reference::new(&self.full.moments, case.masks.clone(), q), grid));
            });
            (t, format!("reference on {res_label} normals ({q} GL nodes)"))
        }
    }

    /// The time of an encoder's fit at a reference knob's value (with the SH projection of the
    /// reduced map for `ref_resolution`), and what was timed.
    fn time_fit(&self, named: &crate::encoders::NamedEncoder, cd: &CaseData, input: &EnvMap) -> (f64, String) {
        if self.sweep.knob == Knob::RefResolution {
            let t = crate::pipeline::timing::median_ns(|| {
                let sh = crate::reference::projection::project(input);
                let inp = crate::encoders::encoder::FitInput { probe_sh: &sh, visible_sh: &sh, ..cd.fit_input() };
                black_box(named.encoder.fit(&inp));
            });
            (t, format!("SH projection of the {}x{} map + fit", input.width(), input.height()))
        } else {
            let inp = cd.fit_input();
            (crate::pipeline::timing::median_ns(|| drop(black_box(named.encoder.fit(&inp)))), "fit".to_string())
        }
    }

    /// `out_resolution`: every encoder scored on each output grid, timed with the reference.
    fn out_resolution(&mut self) -> Result<()> {
        let (sweep, exp) = (self.sweep, &self.sweep.exp);
        let cd = CaseData::new(self.full, self.case, exp.polar_nodes);
        let fits: Vec<_> = exp.encoders.iter().map(|e| e.encoder.fit(&cd.fit_input())).collect();
        let exact_label = self.exact_label();
        for v in &sweep.values {
            // Cannot fail: without "full" allowed, a value parses to Some or is an error.
            let res = parse_res_value(v, false)?.expect("WxH");
            let grid = self.case.domain.output_grid(res);
            let label = format!("{}x{}", grid.resolution.0, grid.resolution.1);
            let values = cd.reference_on(&grid);
            // The reference is shared by every encoder: time it once.
            let t_ref = time_slow(|| drop(black_box(cd.reference_on(&grid))));
            for (named, fit) in exp.encoders.iter().zip(&fits) {
                let scored = || score_fit(named.encoder.as_ref(), fit.as_ref(), &grid, &values, Metric::Exact);
                let s = scored();
                let t = t_ref
                    + time_slow(|| {
                        black_box(scored());
                    });
                let timed = format!("reference + encoder eval + score on {label} normals");
                self.push(v, &named.name, s, (t, timed), (&exact_label, &label));
            }
        }
        Ok(())
    }

    /// `encoder.KEY`: the encoders built at each value, fitted, scored and their fits timed.
    fn encoder_key(
        &mut self,
        encoders_at: &dyn Fn(&toml::Value) -> Result<Vec<crate::encoders::NamedEncoder>>,
    ) -> Result<()> {
        let cd = CaseData::new(self.full, self.case, self.sweep.exp.polar_nodes);
        let values = cd.reference_on(&self.grid);
        let (exact_label, res_label) = (self.exact_label(), self.res_label.clone());
        for v in &self.sweep.values {
            let encoders = encoders_at(v)?;
            let input = cd.fit_input();
            for named in &encoders {
                let fit = named.encoder.fit(&input);
                let s = score_fit(named.encoder.as_ref(), fit.as_ref(), &self.grid, &values, Metric::Exact);
                let t = crate::pipeline::timing::median_ns(|| drop(black_box(named.encoder.fit(&input))));
                self.push(v, &named.name, s, (t, "fit".into()), (&exact_label, &res_label));
            }
        }
        Ok(())
    }
}

/// Runs a sweep over the maps the search path finds, its phases timed on `profile` if one is
/// given; returns rows and the missing maps.
pub fn run(sweep: &Sweep, search: &SearchPath, profile: Option<&Profile>) -> Result<(Vec<SweepRow>, Vec<String>)> {
    let (mut rows, mut missing) = (Vec::new(), Vec::new());
    let progress =
        crate::io::progress::Progress::new(sweep.exp.maps.len() as u64, &format!("sweep {}: maps", sweep.name));
    for name in &sweep.exp.maps {
        progress.message(name.clone());
        let map = match search.open(name) {
            Ok(m) => m,
            Err(crate::envmap::search::OpenError::NotFound(_)) => {
                missing.push(name.clone());
                progress.inc();
                continue;
            }
            Err(crate::envmap::search::OpenError::Load(e)) => return Err(e.into()),
        };
        rows.extend(sweep_map(sweep, &map, profile)?);
        progress.inc();
    }
    progress.finish();
    Ok((rows, missing))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoders::encoder::{Encoder, FitInput, Fitted, Params};
    use crate::encoders::NamedEncoder;
    use crate::reference::scenes::generated;

    fn sweep(text: &str) -> Result<Sweep> {
        Sweep::from_table(toml::from_str(text)?, "t")
    }

    #[test]
    fn area_average_conserves_energy_and_is_identity_at_full_size() {
        let map = generated()[3].map(128);
        assert_eq!(area_average(&map, 128, 64).unwrap().texels(), map.texels());
        let full = crate::reference::projection::project(&map);
        for (w, h) in [(64, 32), (48, 24), (6, 3), (2, 1)] {
            let small = area_average(&map, w, h).unwrap();
            let p = crate::reference::projection::project(&small);
            // Band 0 is the total energy: exact up to f32 storage.
            assert!(((p[0] - full[0]) / full[0]).abs().max_element() < 1e-6, "{w}x{h}: {} vs {}", p[0], full[0]);
        }
        // A map constant on rows stays exact row-wise when rows align.
        let rows = EnvMap::from_fn("r", 64, 32, |_, j| [j as f32, 1.0, 2.0]).unwrap();
        let s = area_average(&rows, 32, 16).unwrap();
        let g = LatLong::new(64, 32);
        let (a, b) = (g.solid_angle(2), g.solid_angle(3));
        assert!((s.texel(5, 1)[0] as f64 - (2.0 * a + 3.0 * b) / (a + b)).abs() < 1e-5);
        assert!(area_average(&map, 256, 128).is_err());
    }

    #[test]
    fn bad_sweep_files_are_specific() {
        let base = "maps = ['gen_constant']\nencoders = ['sh1']\n";
        let e = |s: &str| format!("{:#}", sweep(&format!("{base}{s}")).err().unwrap());
        assert!(e("values = [1]").contains("knob"));
        assert!(e("knob = 'speed'\nvalues = [1]").contains("knob 'speed'"));
        assert!(e("knob = 'polar_nodes'\nvalues = []").contains("values"));
        assert!(e("knob = 'polar_nodes'\nvalues = [0]").contains("1..=16"));
        assert!(e("knob = 'ref_resolution'\nvalues = ['33x16']").contains("W = 2H"));
        // sh1 has no settings: the registry's own error names the key.
        assert!(e("knob = 'encoder.iterations'\nvalues = [3]").contains("iterations"));
        assert!(e("knob = 'polar_nodes'\nvalues = [2]\nmetrics = ['exact']").contains("metrics"));
    }

    /// Polar nodes: the reference error against the converged one falls with the node count
    /// and vanishes at the converged count; on the sphere with no effects the encoders do not
    /// depend on the knob.
    #[test]
    fn polar_node_sweep_converges() {
        let s = sweep(
            "knob = 'polar_nodes'\nvalues = [1, 2, 4, 16]\nmaps = ['x']\nencoders = ['sh1']\nresolution = [32, 16]",
        )
        .unwrap();
        let map = generated()[5].map(64);
        let rows = sweep_map(&s, &map, None).unwrap();
        let refs: Vec<f64> = rows.iter().filter(|r| r.encoder == "reference").map(|r| r.rmse).collect();
        assert_eq!(refs.len(), 4);
        assert!(refs[0] > refs[1] && refs[1] > refs[2], "{refs:?}");
        assert_eq!(refs[3], 0.0);
        let sh1: Vec<f64> = rows.iter().filter(|r| r.encoder == "sh1").map(|r| r.rmse).collect();
        assert!((sh1[0] - sh1[3]).abs() < 1e-3 * sh1[3]);
        assert!(rows.iter().all(|r| r.time_ns > 0.0));
        let csv = String::from_utf8(to_csv(&s, &rows).unwrap()).unwrap();
        assert!(csv.starts_with(&COLUMNS.join(",")));
        assert_eq!(csv.lines().count(), 1 + rows.len());
    }

    /// Reference input resolution: coarser maps give larger reference errors; at full
    /// resolution only the polar rule differs from the converged reference.
    #[test]
    fn ref_resolution_sweep_orders_errors() {
        let s = sweep("knob = 'ref_resolution'\nvalues = ['8x4', '32x16', 'full', '512x256']\nmaps = ['x']\nencoders = ['sh2']\nresolution = [32, 16]").unwrap();
        let map = generated()[3].map(128);
        let rows = sweep_map(&s, &map, None).unwrap();
        let refs: Vec<(String, f64)> =
            rows.iter().filter(|r| r.encoder == "reference").map(|r| (r.value.clone(), r.rmse)).collect();
        assert_eq!(refs.len(), 3, "512x256 is larger than the map and skipped: {refs:?}");
        assert!(refs[0].1 > refs[1].1 && refs[1].1 > refs[2].1, "{refs:?}");
    }

    /// Output resolution: the estimates converge to the finest one.
    #[test]
    fn out_resolution_sweep_converges() {
        let s = sweep("knob = 'out_resolution'\nvalues = ['8x4', '32x16', '128x64']\nmaps = ['x']\nencoders = ['sh1']")
            .unwrap();
        let rows = sweep_map(&s, &generated()[3].map(128), None).unwrap();
        let r: Vec<f64> = rows.iter().map(|r| r.rmse).collect();
        assert!((r[0] - r[2]).abs() > (r[1] - r[2]).abs(), "{r:?}");
        assert!(rows.iter().all(|r| r.encoder == "sh1"));
    }

    /// `encoder.KEY` through a test encoder with a setting: sweeping `bands` over 0, 1, 2
    /// reproduces the sh0, sh1 and sh2 rows of `runner::sweep_map` exactly (the mechanism the
    /// ZH3/HHD settings use once registered).
    #[test]
    fn encoder_setting_sweep_reproduces_each_setting() {
        struct Bands(usize);
        impl Encoder for Bands {
            fn id(&self) -> &str {
                "bands"
            }
            fn stored_scalars(&self) -> usize {
                3 * (self.0 + 1) * (self.0 + 1)
            }
            fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
                crate::encoders::sh::ShEncoder::new(self.0).fit(input)
            }
        }
        let build = |v: &toml::Value| -> Result<Vec<NamedEncoder>> {
            let mut t = toml::Table::new();
            t.insert("bands".into(), v.clone());
            let mut p = Params::new(t);
            let b = p.usize_in("bands", 2, 0..=2)?;
            p.finish("bands")?;
            Ok(vec![NamedEncoder { name: "bands".into(), encoder: Box::new(Bands(b)) }])
        };
        let mut s =
            sweep("knob = 'polar_nodes'\nvalues = [2]\nmaps = ['x']\nencoders = ['sh0', 'sh1', 'sh2']").unwrap();
        let map = generated()[3].map(64);
        let direct: Vec<f64> =
            crate::pipeline::runner::run_map(&s.exp, &map, &Default::default()).iter().map(|r| r.scores.rmse).collect();
        s.knob = Knob::EncoderKey("bands".into());
        s.values = (0..3).map(toml::Value::Integer).collect();
        let rows = sweep_map_with(&s, &map, &build, None).unwrap();
        assert_eq!(rows.len(), 3);
        for (r, want) in rows.iter().zip(&direct) {
            assert_eq!(r.encoder, "bands");
            assert!((r.rmse - want).abs() <= 1e-12 * want, "{r:?} vs {want}");
            assert_eq!(r.timed, "fit");
        }
        assert!(rows[0].rmse > rows[1].rmse && rows[1].rmse > rows[2].rmse);
        assert!(build(&toml::Value::String("x".into())).is_err());
    }
}
