//! Scoring a probe set: the error of one probe against its exact reference, and the chunked,
//! parallel scoring of a set (a file or synthetic) into exact, mergeable statistics and the
//! summary table.
//!
//! ## The error of one probe
//!
//! The reference is the probe's L2 SH irradiance, E/π = Σ Â_l c_lm Y_lm (FORMULAS §3), over the
//! whole sphere, solid-angle weighted: rmse = √(mean over RGB of ∫(E_enc − E_ref)² dω / 4π).
//! - When the fit has the squared error in closed form
//!   ([`crate::encoders::encoder::Fitted::sphere_sq_error`]): for SH3 fits (SH, ZH3 expanded to SH3,
//!   quantised SH/ZH3; [`crate::encoders::encoder::Fitted::sh3`]) √(Σ_i |c_i − r_i|² / (3·4π))
//!   (Parseval; orthonormal basis); for Geomerics its SH3 projection and out-of-band energy by
//!   Funk–Hecke (`geomerics.rs`). Both are exact to rounding.
//! - Otherwise a fixed product Gauss rule (`--quadrature`, default 6x12): 6 Gauss–Legendre
//!   nodes in z × 12 azimuths (72 normals), exact for any encoder whose output lies in SH bands
//!   ≤ 5 (integrand degree ≤ 11) and so exact for every SH3-representable encoder too; the test
//!   bounds its error on non-polynomial reconstructions. Smaller rules trade accuracy for time
//!   (3x6 is still exact for SH3 outputs).
//!
//! rel_rmse = rmse / RMS of the reference over the sphere (closed form).

use crate::encoders::encoder::Fitted;
use crate::encoders::NamedEncoder;
use crate::math::colour::Rgb;
use crate::math::sh::{Sh9, N_SH};
use crate::math::stats::Summary;
use crate::pipeline::probeset::format::ProbeReader;
use crate::pipeline::probeset::shard::Shard;
use crate::pipeline::probeset::synth::Synth;
use anyhow::{bail, Context, Result};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};
use std::time::Instant;

/// What every probe error is measured against.
pub const REFERENCE: &str = "L2 SH irradiance of the probe (E/pi), sphere, solid-angle weighted";

/// The fixed quadrature of the non-closed-form errors: 6 Gauss–Legendre nodes in z × 12
/// azimuths, weights summing to 1 (exact for polynomials of degree ≤ 11 on the sphere).
pub struct SphereRule {
    /// "NZxNPHI", e.g. "6x12".
    pub label: String,
    /// Unit nodes with their weights (the weights sum to 1).
    pub nodes: Vec<(DVec3, f64)>,
    /// The SH basis at each node (so the reference costs 9 multiply-adds a node).
    basis: Vec<[f64; N_SH]>,
}

impl SphereRule {
    /// The product rule of `nz` Gauss–Legendre nodes in z times `nphi` equally spaced azimuths.
    pub fn product_gauss(nz: usize, nphi: usize) -> Self {
        let mut nodes = Vec::with_capacity(nz * nphi);
        for (z, w) in crate::math::quadrature::gauss_legendre(nz) {
            let r = (1.0 - z * z).max(0.0).sqrt();
            for k in 0..nphi {
                let (s, c) = (TAU * (k as f64 + 0.5) / nphi as f64).sin_cos();
                nodes.push((DVec3::new(r * c, r * s, z), 0.5 * w / nphi as f64));
            }
        }
        let basis = nodes.iter().map(|n| crate::math::sh::basis(n.0)).collect();
        SphereRule { label: format!("{nz}x{nphi}"), nodes, basis }
    }
    /// The default: 6×12, exact for outputs in SH bands ≤ 5.
    #[cfg(any(test, feature = "bench"))]
    pub fn standard() -> Self {
        Self::product_gauss(6, 12)
    }
    /// Parses `--quadrature NZxNPHI` (1 ≤ NZ ≤ 64, 1 ≤ NPHI ≤ 128). It is exact for encoder
    /// outputs in SH bands ≤ L when 2·NZ − 1 ≥ 2L + 2 and NPHI ≥ 2L + 1 (e.g. 3x6 for SH3).
    pub fn parse(s: &str) -> Result<Self> {
        let bad =
            || anyhow::anyhow!("--quadrature '{s}': expected NZxNPHI, e.g. 6x12 (1 <= NZ <= 64, 1 <= NPHI <= 128)");
        let (a, b) = s.split_once('x').ok_or_else(bad)?;
        let (nz, nphi): (usize, usize) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
        if !(1..=64).contains(&nz) || !(1..=128).contains(&nphi) {
            return Err(bad());
        }
        Ok(Self::product_gauss(nz, nphi))
    }
}

/// How one probe's error was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// By the fit's closed form (`Fitted::sphere_sq_error`).
    ClosedForm,
    /// By the fixed sphere quadrature.
    Quadrature,
}

/// The sphere RMSE of a fit against the SH3 irradiance `reference` (E/π SH), by the closed form
/// when the fit has one ([`Fitted::sphere_sq_error`]: SH3 fits, Geomerics), else by `rule`.
pub fn probe_rmse(fit: &dyn Fitted, reference: &Sh9, rule: &SphereRule) -> (f64, Method) {
    match fit.sphere_sq_error(reference) {
        Some(se) => (closed_form_rmse(se), Method::ClosedForm),
        None => {
            let mut se = 0.0;
            for (&(n, w), y) in rule.nodes.iter().zip(&rule.basis) {
                let mut r = Rgb::ZERO;
                for i in 0..N_SH {
                    r += reference[i] * y[i];
                }
                se += w * (fit.irradiance(n) - r).length_squared();
            }
            ((se / 3.0).sqrt(), Method::Quadrature)
        }
    }
}

/// The sphere RMSE (RGB mean) of a closed-form squared error ∫|ΔE|² dω summed over RGB.
fn closed_form_rmse(se: f64) -> f64 {
    (se.max(0.0) / (3.0 * 4.0 * PI)).sqrt()
}

/// RMS over the sphere of SH (RGB mean), closed form.
pub fn sh_rms(sh: &Sh9) -> f64 {
    ((0..N_SH).map(|i| sh[i].length_squared()).sum::<f64>() / (3.0 * 4.0 * PI)).sqrt()
}

/// The statistics of one encoder over a set (or a shard of one).
#[derive(Clone, Debug, PartialEq)]
pub struct EncoderStats {
    /// Name of the encoder as configured.
    pub name: String,
    /// Scalars the encoder stores per probe.
    pub stored_scalars: usize,
    /// Probes whose error came from the closed form.
    pub closed_form: u64,
    /// Probes whose error came from quadrature.
    pub quadrature: u64,
    /// Its share of the wall time: thread seconds spent fitting and scoring this encoder,
    /// divided by the worker threads (summed over shards when merged).
    pub seconds: f64,
    /// Per-probe sphere RMSE of E/π.
    pub rmse: Summary,
    /// Per-probe RMSE relative to the RMS of the reference.
    pub rel_rmse: Summary,
}

impl EncoderStats {
    fn new(e: &NamedEncoder) -> Self {
        EncoderStats {
            name: e.name.clone(),
            stored_scalars: e.encoder.stored_scalars(),
            closed_form: 0,
            quadrature: 0,
            seconds: 0.0,
            rmse: Summary::default(),
            rel_rmse: Summary::default(),
        }
    }

    /// How errors were computed: closed form, quadrature (rule "NZxNPHI"), or both (with counts).
    pub fn method(&self, rule: &str) -> String {
        match (self.closed_form, self.quadrature) {
            (_, 0) => "closed form".into(),
            (0, _) => format!("quadrature ({rule} product Gauss)"),
            (c, q) => format!("mixed ({c} closed-form, {q} quadrature {rule})"),
        }
    }
}

/// The mergeable result of scoring a set or shards of it.
#[derive(Clone, Debug, PartialEq)]
pub struct SetStats {
    /// The set's identity (synthesis parameters and palette fingerprint, or the input file).
    pub source: String,
    /// Number of shards the set was split into (N of `--shard I/N`).
    pub shard_count: usize,
    /// The shards this state covers.
    pub shards: Vec<usize>,
    /// The quadrature rule of non-SH3 errors ("NZxNPHI").
    pub quadrature: String,
    /// Probes scored.
    pub probes: u64,
    /// Wall seconds of the run (summed over shards when merged).
    pub wall_s: f64,
    /// Seconds reading or synthesising probes (summed over shards).
    pub input_s: f64,
    /// Peak resident memory (VmHWM) of the run, in bytes (max over shards); 0 if unknown.
    pub peak_mem_bytes: u64,
    /// Worker threads of the run.
    pub threads: usize,
    /// Statistics per encoder, in the order the encoders were listed.
    pub encoders: Vec<EncoderStats>,
}

/// Where probes come from.
pub enum Source {
    /// Synthetic probes of one shard's index range, generated on demand.
    Synth {
        /// The synthesiser.
        synth: Synth,
        /// First probe index of this shard.
        start: u64,
        /// One past the last probe index of this shard.
        end: u64,
        /// Index of the next probe to generate.
        next: u64,
    },
    /// Probes read from a file.
    File(ProbeReader),
}

impl Source {
    /// Up to `max` more probes.
    pub fn next_chunk(&mut self, max: usize) -> Result<Option<Vec<Sh9>>> {
        match self {
            Source::Synth { synth, end, next, .. } => {
                if *next >= *end {
                    return Ok(None);
                }
                let stop = (*next + max as u64).min(*end);
                let p = synth.probes(*next, stop);
                *next = stop;
                Ok(Some(p))
            }
            Source::File(r) => r.next_chunk(max),
        }
    }

    /// Where probe `k` of the chunk just returned comes from: "FILE:LINE" or "FILE: probe I",
    /// or "synthetic probe I" (I its index in the whole set).
    pub fn locate(&self, k: usize, chunk_len: usize) -> String {
        match self {
            Source::Synth { next, .. } => format!("synthetic probe {}", *next - chunk_len as u64 + k as u64),
            Source::File(r) => r.locate(k),
        }
    }
}

/// Peak resident set size of this process (VmHWM in /proc/self/status), in bytes.
pub fn peak_memory_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Probes one task scores with every encoder in turn: few enough that the block's probes and
/// references stay in the core's cache while each encoder reads them.
const BLOCK: usize = 256;

/// One probe's error under one encoder: rmse and rel_rmse.
type ProbeError = (f64, f64);

/// What one block tells the fold about one encoder.
#[derive(Clone, Copy, Default)]
struct Tally {
    /// Thread seconds the encoder's fits and errors took on the block.
    seconds: f64,
    /// Probes whose error came from the closed form.
    closed: u64,
    /// The first probe of the block (its index there) with a non-finite error.
    first_bad: Option<usize>,
}

/// Scores `encoders` over every probe `source` yields, `chunk` probes at a time; `sink`
/// receives each chunk first (e.g. to save the set). Statistics are exact and order-free, so
/// the result does not depend on threads or chunk size (timings aside).
///
/// A chunk is cut into blocks of [`BLOCK`] probes scored in parallel, each by every encoder
/// in turn (a probe's reference and its RMS are computed once); then each encoder's errors are
/// folded into its statistics, the encoders' summaries in parallel. An encoder's `seconds`
/// are the thread seconds of its fits and errors divided by the worker threads: its share
/// of the wall time.
pub fn score(
    source: &mut Source,
    source_id: &str,
    shard: Shard,
    encoders: &[NamedEncoder],
    rule: &SphereRule,
    chunk: usize,
    mut sink: impl FnMut(&[Sh9]) -> Result<()>,
) -> Result<SetStats> {
    let t0 = Instant::now();
    let mut stats: Vec<EncoderStats> = encoders.iter().map(EncoderStats::new).collect();
    let (mut probes, mut input_s) = (0u64, 0.0);
    let mut errors: Vec<ProbeError> = Vec::new();
    let mut tallies: Vec<Tally> = Vec::new();
    let threads = rayon::current_num_threads() as f64;
    loop {
        let t = Instant::now();
        let Some(set) = source.next_chunk(chunk.max(1))? else { break };
        input_s += t.elapsed().as_secs_f64();
        sink(&set)?;
        probes += set.len() as u64;
        let ne = encoders.len();
        errors.clear();
        errors.resize(set.len() * ne, (0.0, 0.0));
        tallies.clear();
        tallies.resize(set.len().div_ceil(BLOCK) * ne, Tally::default());
        set.par_chunks(BLOCK)
            .zip(errors.par_chunks_mut(BLOCK * ne))
            .zip(tallies.par_chunks_mut(ne))
            .for_each(|((block, out), tally)| score_block(block, encoders, rule, out, tally));
        for (e, st) in stats.iter_mut().enumerate() {
            for (b, tally) in tallies.chunks(ne).enumerate() {
                let Tally { seconds, closed, first_bad } = tally[e];
                if let Some(i) = first_bad {
                    let len = set.len().min((b + 1) * BLOCK) - b * BLOCK;
                    let (rmse, rel) = errors[b * BLOCK * ne + e * len + i];
                    // A non-finite error is the probe's arithmetic overflowing (or an encoder
                    // bug): an error naming the probe, never a value dropped from the statistics.
                    bail!(
                        "{}: encoder {} gives a non-finite error on this probe (rmse {rmse}, rel_rmse {rel}): its \
                         coefficients overflow or underflow the encoder's arithmetic; scale the probe set",
                        source.locate(b * BLOCK + i, set.len()),
                        st.name
                    );
                }
                st.seconds += seconds / threads;
                st.closed_form += closed;
                st.quadrature += (set.len().min((b + 1) * BLOCK) - b * BLOCK) as u64 - closed;
            }
        }
        fold(&mut stats, &errors, set.len(), ne);
    }
    Ok(SetStats {
        source: source_id.to_string(),
        shard_count: shard.count,
        shards: vec![shard.index],
        quadrature: rule.label.clone(),
        probes,
        wall_s: t0.elapsed().as_secs_f64(),
        input_s,
        peak_mem_bytes: peak_memory_bytes().unwrap_or(0),
        threads: rayon::current_num_threads(),
        encoders: stats,
    })
}

/// Scores one block of probes with every encoder: `out` holds the block's errors encoder by
/// encoder (`out[e * len + i]`), `tally` what the fold needs per encoder. An encoder with
/// batch closed-form errors ([`crate::encoders::encoder::Encoder::sphere_sq_errors`]) gives
/// them straight from the block's irradiance; any other is fitted probe by probe.
fn score_block(
    block: &[Sh9],
    encoders: &[NamedEncoder],
    rule: &SphereRule,
    out: &mut [ProbeError],
    tally: &mut [Tally],
) {
    let references: Vec<Sh9> = block.iter().map(Sh9::convolve_cosine).collect();
    let rms: Vec<f64> = references.iter().map(sh_rms).collect();
    let mut se = vec![0.0; block.len()];
    let relative = |rmse: f64, rms: f64| {
        if rms > 0.0 {
            rmse / rms
        } else if rmse == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    };
    for ((e, out), tally) in encoders.iter().zip(out.chunks_mut(block.len())).zip(tally) {
        let t = Instant::now();
        let mut closed = 0;
        if e.encoder.sphere_sq_errors(block, &references, &mut se) {
            for ((o, &se), &rms) in out.iter_mut().zip(&se).zip(&rms) {
                let rmse = closed_form_rmse(se);
                *o = (rmse, relative(rmse, rms));
            }
            closed = block.len() as u64;
        } else {
            e.encoder.fit_sphere_each(block, &mut |i, fit| {
                let (rmse, method) = probe_rmse(fit, &references[i], rule);
                closed += u64::from(method == Method::ClosedForm);
                out[i] = (rmse, relative(rmse, rms[i]));
            });
        }
        tally.closed = closed;
        tally.first_bad = out.iter().position(|v| !v.0.is_finite() || !v.1.is_finite());
        tally.seconds = t.elapsed().as_secs_f64();
    }
}

/// Folds a chunk's errors (laid out as [`score_block`] writes them, blocks in order) into each
/// encoder's two summaries, all summaries in parallel (adding is exact and order-free).
fn fold(stats: &mut [EncoderStats], errors: &[ProbeError], len: usize, ne: usize) {
    let mut summaries: Vec<(usize, bool, &mut Summary)> = stats
        .iter_mut()
        .enumerate()
        .flat_map(|(e, st)| [(e, false, &mut st.rmse), (e, true, &mut st.rel_rmse)])
        .collect();
    summaries.par_iter_mut().for_each(|(e, rel, summary)| {
        for (b, block) in errors.chunks(BLOCK * ne).enumerate() {
            let n = len.min((b + 1) * BLOCK) - b * BLOCK;
            for v in &block[*e * n..(*e + 1) * n] {
                summary.add(if *rel { v.1 } else { v.0 });
            }
        }
    });
}

impl SetStats {
    /// Merges another state of the same set (disjoint shards). Every count is added with
    /// checked arithmetic; on any error `self` is unchanged.
    pub fn merge(&mut self, o: &SetStats) -> Result<()> {
        if o.source != self.source {
            bail!("different probe sets: '{}' vs '{}'", self.source, o.source);
        }
        if o.quadrature != self.quadrature {
            bail!("different quadrature rules: {} vs {}", self.quadrature, o.quadrature);
        }
        if o.shard_count != self.shard_count {
            bail!("different shard counts: {} vs {}", self.shard_count, o.shard_count);
        }
        if let Some(s) = o.shards.iter().find(|s| self.shards.contains(s)) {
            bail!("shard {s}/{} appears twice; each shard must be merged once", self.shard_count);
        }
        let names = |s: &SetStats| s.encoders.iter().map(|e| (e.name.clone(), e.stored_scalars)).collect::<Vec<_>>();
        if names(self) != names(o) {
            bail!("different encoder lists: {:?} vs {:?}", names(self), names(o));
        }
        let overflow = |what: &str| anyhow::anyhow!("the merged {what} overflows 64 bits");
        let mut m = self.clone();
        m.shards.extend(&o.shards);
        m.shards.sort_unstable();
        m.probes = m.probes.checked_add(o.probes).ok_or_else(|| overflow("probe count"))?;
        m.wall_s += o.wall_s;
        m.input_s += o.input_s;
        m.peak_mem_bytes = m.peak_mem_bytes.max(o.peak_mem_bytes);
        m.threads = m.threads.max(o.threads);
        for (a, b) in m.encoders.iter_mut().zip(&o.encoders) {
            a.closed_form = a.closed_form.checked_add(b.closed_form).ok_or_else(|| overflow("closed-form count"))?;
            a.quadrature = a.quadrature.checked_add(b.quadrature).ok_or_else(|| overflow("quadrature count"))?;
            a.seconds += b.seconds;
            a.rmse.merge(&b.rmse).with_context(|| format!("{} rmse", a.name))?;
            a.rel_rmse.merge(&b.rel_rmse).with_context(|| format!("{} rel_rmse", a.name))?;
        }
        *self = m;
        Ok(())
    }

    /// Whether every shard of the set is present.
    pub fn complete(&self) -> bool {
        self.shards.len() == self.shard_count
    }

    /// The summary table (CSV): one row per encoder, after one comment line `# source: …`
    /// naming the probe set (its palette of maps can run to hundreds of characters, which
    /// repeated in a column on every row would make the table unreadable in a terminal).
    /// Documented in docs/scale.md.
    pub fn summary_csv(&self) -> Result<Vec<u8>> {
        let num = crate::pipeline::table::num;
        // A statistic over no valid probe is empty, never 0.
        let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
        let sh1 = self.encoders.iter().find(|e| e.name == crate::encoders::BASELINE).and_then(|e| e.rmse.mean());
        let mut w = csv::Writer::from_writer(format!("# source: {}\n", self.source.replace('\n', " ")).into_bytes());
        w.write_record(SUMMARY_COLUMNS)?;
        let shards = if self.complete() {
            format!("all {}", self.shard_count)
        } else {
            format!("{:?} of {}", self.shards, self.shard_count)
        };
        for e in &self.encoders {
            let reduction = match (sh1, e.rmse.mean()) {
                (Some(b), Some(m)) if b > 0.0 => num(1.0 - m / b),
                _ => String::new(),
            };
            let pps =
                if e.seconds > 0.0 { num((e.rmse.count + e.rmse.invalid) as f64 / e.seconds) } else { String::new() };
            w.write_record([
                e.name.clone(),
                self.probes.to_string(),
                opt(e.rmse.mean()),
                opt(e.rmse.quantile(0.5)),
                opt(e.rmse.quantile(0.95)),
                opt(e.rmse.extrema().map(|m| m.1)),
                opt(e.rel_rmse.mean()),
                opt(e.rel_rmse.quantile(0.5)),
                opt(e.rel_rmse.quantile(0.95)),
                opt(e.rel_rmse.extrema().map(|m| m.1)),
                reduction,
                e.stored_scalars.to_string(),
                e.method(&self.quadrature),
                (e.rmse.invalid + e.rel_rmse.invalid).to_string(),
                pps,
                num(e.seconds),
                num(self.wall_s),
                num(self.peak_mem_bytes as f64 / (1024.0 * 1024.0)),
                shards.clone(),
                "sphere".into(),
                "solid-angle".into(),
                "E/pi".into(),
                REFERENCE.into(),
            ])?;
        }
        w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
    }
}

/// Columns of the probe summary. The last ones after `error_method`/`invalid` are timings and
/// run figures (non-deterministic): see [`SUMMARY_TIMING_COLUMNS`].
pub const SUMMARY_COLUMNS: &[&str] = &[
    "encoder",
    "probes",
    "rmse_mean",
    "rmse_p50",
    "rmse_p95",
    "rmse_max",
    "rel_rmse_mean",
    "rel_rmse_p50",
    "rel_rmse_p95",
    "rel_rmse_max",
    "reduction_vs_sh1",
    "stored_scalars",
    "error_method",
    "invalid",
    "probes_per_s",
    "encoder_s",
    "wall_s",
    "peak_mem_mib",
    "shards",
    "domain",
    "weighting",
    "units",
    "reference",
];

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::encoders::build_list;
    use crate::encoders::encoder::FitInput;
    use crate::math::sh::delta_light;
    use crate::pipeline::probeset::synth::scene_palette;

    #[test]
    fn quadrature_rules_parse() {
        assert_eq!(SphereRule::parse("3x6").unwrap().nodes.len(), 18);
        for bad in ["6", "0x4", "6x0", "65x2", "ax3"] {
            assert!(SphereRule::parse(bad).is_err(), "{bad}");
        }
    }

    /// The closed form equals the quadrature for SH3 fits (the rule is exact to degree 11).
    #[test]
    fn closed_form_equals_quadrature_for_sh3_fits() {
        struct NoHook(Sh9);
        impl Fitted for NoHook {
            fn irradiance(&self, n: DVec3) -> Rgb {
                self.0.eval(n)
            }
            fn stored(&self) -> crate::encoders::stored::Stored {
                crate::encoders::stored::Stored::new("test: hides its SH3 form")
            }
        }
        let s = Synth::new(3, scene_palette());
        let (rule, small) = (SphereRule::standard(), SphereRule::parse("3x6").unwrap());
        for e in build_list("sh0,sh1,sh2").unwrap() {
            for i in 0..50 {
                let p = s.probe(i);
                let r = p.convolve_cosine();
                let fit = e.encoder.fit(&FitInput::sphere(&p));
                let (a, m) = probe_rmse(fit.as_ref(), &r, &rule);
                assert_eq!(m, Method::ClosedForm);
                for rule in [&rule, &small] {
                    let (b, m) = probe_rmse(&NoHook(fit.sh3().unwrap()), &r, rule);
                    assert_eq!(m, Method::Quadrature);
                    assert!(
                        (a - b).abs() <= 1e-12 * (a + sh_rms(&r)),
                        "{} probe {i} {}: {a} vs {b}",
                        e.name,
                        rule.label
                    );
                }
            }
        }
        // Weights sum to 1 and the rule integrates Y6² (degree 4) to 1/4π.
        let w: f64 = rule.nodes.iter().map(|n| n.1).sum();
        assert!((w - 1.0).abs() < 1e-14);
        let y6: f64 = rule.nodes.iter().map(|&(n, w)| w * crate::math::sh::basis(n)[6].powi(2)).sum();
        assert!((y6 - 1.0 / (4.0 * PI)).abs() < 1e-14);
    }

    /// Every registered encoder that gives its sphere error in closed form agrees with a fine
    /// product Gauss rule (64x128) applied to its evaluated output, on synthetic probes: to
    /// 1e-12 for SH3 outputs (the rule is exact for them), 1e-6 otherwise (Geomerics: its
    /// (1 + t)^p lobe limits the rule, not the closed form). The registry is iterated, so an
    /// encoder that claims a closed form is held to it.
    #[test]
    fn every_closed_form_error_equals_fine_quadrature() {
        struct Hidden<'a>(&'a dyn Fitted);
        impl Fitted for Hidden<'_> {
            fn irradiance(&self, n: DVec3) -> Rgb {
                self.0.irradiance(n)
            }
            fn stored(&self) -> crate::encoders::stored::Stored {
                self.0.stored()
            }
        }
        let s = Synth::new(5, scene_palette());
        let fine = SphereRule::product_gauss(64, 128);
        let mut claimed = Vec::new();
        for k in crate::encoders::REGISTRY {
            let e = crate::encoders::build(k.id, None, toml::Table::new()).unwrap();
            for i in 0..12 {
                let p = s.probe(i);
                let r = p.convolve_cosine();
                let fit = e.encoder.fit(&FitInput::sphere(&p));
                let (a, m) = probe_rmse(fit.as_ref(), &r, &fine);
                if m != Method::ClosedForm {
                    continue;
                }
                if i == 0 {
                    claimed.push(k.id);
                }
                let (b, _) = probe_rmse(&Hidden(fit.as_ref()), &r, &fine);
                let tol = if fit.sh3().is_some() { 1e-12 } else { 1e-6 };
                assert!((a - b).abs() <= tol * (a + sh_rms(&r)), "{} probe {i}: {a} vs {b}", k.id);
                if let Some(c) = fit.sh3() {
                    for n in crate::reference::domain::fibonacci_sphere(20) {
                        let d = (c.eval(n) - fit.irradiance(n)).abs().max_element();
                        assert!(
                            d <= 1e-12 * (1.0 + c.eval(n).abs().max_element()),
                            "{}: sh3() is not the output",
                            k.id
                        );
                    }
                }
            }
        }
        for id in ["sh1", "sh2", "geomerics", "zh3_hallucinate", "zh3_stored_shared", "zh3_solved_shared", "sh2_q28"] {
            assert!(claimed.contains(&id), "{id} lost its closed form: {claimed:?}");
        }
    }

    /// The batch fits probe sets score through are each encoder's fits: for every registered
    /// encoder, `fit_sphere_each` visits every probe once, in order, with a fit whose output,
    /// closed-form error, stored form and diagnostics equal those of `fit` bit for bit.
    #[test]
    fn batch_fits_are_the_encoders_fits() {
        let s = Synth::new(9, scene_palette());
        let probes = s.probes(0, 40);
        let normals = crate::reference::domain::fibonacci_sphere(16);
        for k in crate::encoders::REGISTRY {
            let e = crate::encoders::build(k.id, None, toml::Table::new()).unwrap();
            let mut seen = Vec::new();
            e.encoder.fit_sphere_each(&probes, &mut |i, batch| {
                seen.push(i);
                let p = &probes[i];
                let fit = e.encoder.fit(&FitInput::sphere(p));
                let r = p.convolve_cosine();
                assert_eq!(batch.sphere_sq_error(&r), fit.sphere_sq_error(&r), "{} probe {i}", k.id);
                for &n in &normals {
                    assert_eq!(batch.irradiance(n), fit.irradiance(n), "{} probe {i} at {n}", k.id);
                }
                assert_eq!(format!("{:?}", batch.stored()), format!("{:?}", fit.stored()), "{}", k.id);
                assert_eq!(batch.diagnostics(), fit.diagnostics(), "{}", k.id);
            });
            assert_eq!(seen, (0..probes.len()).collect::<Vec<_>>(), "{}", k.id);
        }
    }

    /// The batch errors probe sets score through are each encoder's fits' errors: for every
    /// registered encoder with a batch, bit for bit `fit(..).sphere_sq_error`, on synthetic
    /// probes, on probes whose L1 vanishes in every channel or in one (no zonal axis there), on
    /// a black probe, and non-finite (NaN) wherever the fit's is, on probes with an infinite or
    /// NaN coefficient in bands 0 and 1 (which a batch may not skip as "equal to the
    /// reference", and on which an iterative solve must still end).
    #[test]
    fn batch_errors_are_the_fits_errors() {
        let closed_forms = [
            "sh1",
            "sh2",
            "geomerics",
            "zh3_hallucinate",
            "zh3_hallucinate_channel",
            "zh3_hallucinate_ambdir",
            "zh3_hallucinate_sphere",
            "zh3_stored_channel",
            "zh3_stored_shared",
        ];
        let mut probes = Synth::new(11, scene_palette()).probes(0, 40);
        probes.push(crate::math::sh::constant(Rgb::new(0.2, 0.3, 0.4)));
        probes.push(delta_light(DVec3::new(0.3, -0.8, 0.52).normalize(), Rgb::new(1.0, 0.0, 2.0)));
        probes.push(probes[3] + delta_light(DVec3::X, Rgb::new(0.0, 0.5, 0.0)));
        probes.push(Sh9::ZERO);
        for (i, c, v) in [(0, 1, f64::INFINITY), (2, 0, f64::NAN), (3, 2, f64::NEG_INFINITY), (6, 1, f64::INFINITY)] {
            let mut p = probes[5];
            p[i][c] = v;
            probes.push(p);
        }
        let irradiance: Vec<Sh9> = probes.iter().map(Sh9::convolve_cosine).collect();
        let mut batched = Vec::new();
        for k in crate::encoders::REGISTRY {
            let e = crate::encoders::build(k.id, None, toml::Table::new()).unwrap();
            let mut out = vec![f64::NAN; probes.len()];
            if !e.encoder.sphere_sq_errors(&probes, &irradiance, &mut out) {
                continue;
            }
            batched.push(k.id);
            for (i, (p, r)) in probes.iter().zip(&irradiance).enumerate() {
                let want = e.encoder.fit(&FitInput::sphere(p)).sphere_sq_error(r).unwrap();
                let same = out[i].to_bits() == want.to_bits() || (out[i].is_nan() && want.is_nan());
                assert!(same, "{} probe {i}: {} vs {want}", k.id, out[i]);
            }
        }
        for id in closed_forms {
            assert!(batched.contains(&id), "{id} lost its batch errors: {batched:?}");
        }
    }

    /// The fixed rule on non-polynomial reconstructions: a Geomerics-style q^p lobe and a
    /// clamped SH, against a fine rule (FORMULAS §6 model, written out here as a test function).
    #[test]
    fn quadrature_error_on_non_polynomial_fits() {
        struct Lobe {
            d: DVec3,
            p: f64,
        }
        impl Fitted for Lobe {
            fn irradiance(&self, n: DVec3) -> Rgb {
                let q = 0.5 * (1.0 + self.d.dot(n));
                Rgb::splat(0.3 + 1.7 * q.powf(self.p))
            }
            fn stored(&self) -> crate::encoders::stored::Stored {
                crate::encoders::stored::Stored::new("test lobe")
            }
        }
        struct Clamped(Sh9);
        impl Fitted for Clamped {
            fn irradiance(&self, n: DVec3) -> Rgb {
                self.0.eval(n).max(Rgb::ZERO)
            }
            fn stored(&self) -> crate::encoders::stored::Stored {
                crate::encoders::stored::Stored::new("test clamped SH")
            }
        }
        let (coarse, fine) = (SphereRule::standard(), SphereRule::product_gauss(64, 128));
        let reference = crate::math::sh::constant(Rgb::ONE).convolve_cosine();
        let mut worst: f64 = 0.0;
        for p in [1.0, 1.37, 2.2, 2.9] {
            let f = Lobe { d: DVec3::new(0.3, 0.5, 0.81).normalize(), p };
            let (a, b) = (probe_rmse(&f, &reference, &coarse).0, probe_rmse(&f, &reference, &fine).0);
            worst = worst.max((a - b).abs() / b);
        }
        assert!(worst < 1e-3, "lobe relative error {worst}");
        // A clamped L1 lobe with a kink: the rule is still within a few percent.
        let l1 = delta_light(DVec3::Y, Rgb::splat(3.0)).truncate(1).convolve_cosine();
        let (a, b) = (probe_rmse(&Clamped(l1), &l1, &coarse).0, probe_rmse(&Clamped(l1), &l1, &fine).0);
        assert!((a - b).abs() / b < 0.1, "clamped: {a} vs {b}");
    }

    pub(crate) fn score_synth(synth: &Synth, n: u64, shard: Shard, chunk: usize) -> SetStats {
        let (start, end) = shard.range(n);
        let mut src = Source::Synth { synth: synth.clone(), start, end, next: start };
        let rule = SphereRule::standard();
        score(&mut src, "test", shard, &build_list("sh0,sh1,sh2").unwrap(), &rule, chunk, |_| Ok(())).unwrap()
    }

    pub(crate) fn strip_timing(mut s: SetStats) -> SetStats {
        s.wall_s = 0.0;
        s.input_s = 0.0;
        s.peak_mem_bytes = 0;
        for e in &mut s.encoders {
            e.seconds = 0.0;
        }
        s
    }
    /// The statistics are what a direct computation gives: sh2 is exact (rmse 0), and sh1's
    /// mean rmse equals the mean of independently computed band-2 energies.
    #[test]
    fn statistics_match_a_direct_computation() {
        let synth = Synth::new(5, scene_palette());
        let n = 3000;
        let s = score_synth(&synth, n, Shard::ALL, 512);
        let (sh0, sh1, sh2) = (&s.encoders[0], &s.encoders[1], &s.encoders[2]);
        assert_eq!(sh2.rmse.max, 0.0);
        let mut direct: Vec<f64> = (0..n)
            .map(|i| {
                // sh1 misses exactly the band-2 irradiance: rmse² = Σ_{i≥4} |¼c_i|² / (3·4π).
                let p = synth.probe(i);
                ((4..9).map(|k| (p[k] * 0.25).length_squared()).sum::<f64>() / (12.0 * PI)).sqrt()
            })
            .collect();
        let mean = direct.iter().sum::<f64>() / n as f64;
        let got = sh1.rmse.mean().unwrap();
        assert!((got - mean).abs() < 1e-12 * mean, "{got} vs {mean}");
        direct.sort_by(f64::total_cmp);
        let p95 = direct[(0.95 * n as f64).ceil() as usize - 1];
        let got = sh1.rmse.quantile(0.95).unwrap();
        assert!((got - p95).abs() <= crate::math::stats::SKETCH_RELATIVE_ERROR * p95);
        assert!(sh0.rmse.mean() > sh1.rmse.mean());
        assert!(sh1.rmse.mean().is_some());
        let csv = String::from_utf8(s.summary_csv().unwrap()).unwrap();
        assert!(csv.starts_with(&format!("# source: {}\n{}", s.source, SUMMARY_COLUMNS.join(","))), "{csv}");
        assert!(csv.contains("\nsh2,3000,0,"), "{csv}");
    }
}
