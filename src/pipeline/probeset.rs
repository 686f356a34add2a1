//! Probe sets at production scale: L2 SH radiance probes read from files or synthesised, scored
//! by any registered encoder in fixed-size chunks (memory does not grow with the set), with
//! mergeable statistics so a set can be split into shards on a batch engine.
//!
//! ## File formats (`probelab probes --input FILE`)
//!
//! A probe is the L2 SH of the radiance it sees (not cosine-convolved), in the FORMULAS §2
//! basis (Condon–Shortley phase, index 0..8 as in the table there), 27 numbers in
//! **coefficient-major** order: c0.r c0.g c0.b c1.r c1.g c1.b … c8.r c8.g c8.b — the layout of
//! a `float3 sh[9]` array.
//!
//! - CSV (`.csv`): one probe per row, 27 numbers separated by commas (spaces around them are
//!   allowed). Lines starting with `#` are comments; blank lines are skipped; a first row whose
//!   first field starts with a letter is a header and is skipped. Every value must be finite.
//! - Raw binary (`.f32`, `.bin`, `.raw`): little-endian IEEE f32, 27 per probe, no header; the
//!   file size must be a multiple of 108 bytes.
//!
//! ## Synthetic probes (`probelab probes --synth N --seed S`)
//!
//! Probe i depends only on (S, i, palette), never on chunking, threads or shards. Drawn from a
//! SplitMix64 stream seeded by (S, i):
//! - with probability 0.8, a palette map's SH3 (normalised to mean radiance luminance 1), under a
//!   uniformly random rotation (Shoemake) and an exposure 2^U(−3, 3);
//! - coloured ambient (always without a map, else with probability ½): constant radiance of
//!   luminance 2^U(−4, 0) · exposure;
//! - 0–3 lights (at least one without a map), each with a random colour and a uniformly random
//!   direction: directional (E/π facing it 2^U(−2, 3)), sphere (a cap of half-angle 0.5°–15°,
//!   E/π on its axis 2^U(−2, 3)) or cone (a cap of half-angle 15°–60°, E/π on its axis
//!   2^U(−3, 1)), all scaled by the exposure. Their SH are closed forms (`lighting::Light`).
//!
//! The palette is the SH3 of every `*_256x128` map on the search path (`PROBELAB_ENVMAPS`), or
//! the maps named with `--palette`; with none found, the generated analytic scenes' closed-form
//! SH. The palette's fingerprint is part of the set's identity (merging checks it).
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

use crate::encoders::encoder::{FitInput, Fitted};
use crate::encoders::NamedEncoder;
use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use crate::math::sh::{constant, delta_light, Sh9, N_SH};
use crate::math::sh_rotation::{uniform_rotation, ShRotation};
use crate::math::stats::{Summary, SummaryState};
use crate::reference::lighting::Light;
use anyhow::{bail, Context, Result};
use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};
use std::io::{BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Numbers per probe.
pub const COEFFS: usize = 3 * N_SH;
/// Probes per chunk by default (about 7 MB of probes in flight).
pub const DEFAULT_CHUNK: usize = 32_768;
/// The state file's format tag.
pub const STATE_FORMAT: &str = "probelab-probe-stats/1";
/// What every probe error is measured against.
pub const REFERENCE: &str = "L2 SH irradiance of the probe (E/pi), sphere, solid-angle weighted";

// ---------------------------------------------------------------------------------------------
// Shards

/// Shard I of N: the contiguous range of probe indices [⌊I·T/N⌋, ⌊(I+1)·T/N⌋) of a set of T.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses "I/N" with 0 ≤ I < N.
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || anyhow::anyhow!("--shard '{s}': expected I/N with 0 <= I < N, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) =
            (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The index range of this shard in a set of `total` probes.
    pub fn range(&self, total: u64) -> (u64, u64) {
        let at = |k: usize| ((k as u128 * total as u128) / self.count as u128) as u64;
        (at(self.index), at(self.index + 1))
    }
}

// ---------------------------------------------------------------------------------------------
// Reading and writing probe files

/// A probe file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Csv,
    F32,
}

impl Format {
    /// From a `--format` value or, when None, the file extension.
    pub fn resolve(path: &Path, explicit: Option<&str>) -> Result<Self> {
        let name = match explicit {
            Some(f) => f.to_string(),
            None => path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase(),
        };
        match name.as_str() {
            "csv" => Ok(Format::Csv),
            "f32" | "bin" | "raw" => Ok(Format::F32),
            _ => bail!(
                "{}: unknown probe file format '{name}' (use a .csv, .f32, .bin or .raw file, or --format csv|f32)",
                path.display()
            ),
        }
    }
}

/// Coefficient-major 27 numbers → SH.
pub fn from_coeffs(v: &[f64; COEFFS]) -> Sh9 {
    Sh9(std::array::from_fn(|i| Rgb::new(v[3 * i], v[3 * i + 1], v[3 * i + 2])))
}

/// SH → coefficient-major 27 numbers.
pub fn to_coeffs(sh: &Sh9) -> [f64; COEFFS] {
    std::array::from_fn(|k| sh[k / 3][k % 3])
}

/// Streams probes from a file, one shard of it, in chunks.
pub struct ProbeReader {
    path: PathBuf,
    inner: Inner,
    /// Probes of this shard not yet returned.
    remaining: u64,
    /// Probes in this shard.
    pub len: u64,
}

enum Inner {
    Csv { rdr: csv::Reader<BufReader<std::fs::File>>, header_checked: bool },
    F32 { rdr: BufReader<std::fs::File> },
}

fn csv_reader(path: &Path) -> Result<csv::Reader<BufReader<std::fs::File>>> {
    let f = std::fs::File::open(path).with_context(|| format!("{}: cannot open probe file", path.display()))?;
    Ok(csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(BufReader::with_capacity(1 << 20, f)))
}

/// Whether a CSV record is a header (its first field starts with a letter).
fn is_header(r: &csv::ByteRecord) -> bool {
    r.get(0).and_then(|f| f.first()).is_some_and(|c| c.is_ascii_alphabetic())
}

/// Whether a CSV record is a blank line (the csv crate yields one empty field for it).
fn is_blank(r: &csv::ByteRecord) -> bool {
    r.is_empty() || (r.len() == 1 && r[0].is_empty())
}

impl ProbeReader {
    /// Opens a probe file for shard `shard` of it. CSV files are counted in a first pass when
    /// sharded (the shard ranges need the total).
    pub fn open(path: &Path, format: Format, shard: Shard) -> Result<Self> {
        match format {
            Format::F32 => {
                let f =
                    std::fs::File::open(path).with_context(|| format!("{}: cannot open probe file", path.display()))?;
                let bytes = f.metadata().with_context(|| format!("{}: cannot stat", path.display()))?.len();
                let rec = (COEFFS * 4) as u64;
                if bytes % rec != 0 {
                    bail!(
                        "{}: size {bytes} bytes is not a multiple of {rec} (27 little-endian f32 per probe); truncated or not a probe file",
                        path.display()
                    );
                }
                let (start, end) = shard.range(bytes / rec);
                let mut rdr = BufReader::with_capacity(1 << 20, f);
                rdr.seek(SeekFrom::Start(start * rec)).with_context(|| format!("{}: cannot seek", path.display()))?;
                Ok(ProbeReader {
                    path: path.into(),
                    inner: Inner::F32 { rdr },
                    remaining: end - start,
                    len: end - start,
                })
            }
            Format::Csv => {
                let (start, end) = if shard.count == 1 {
                    (0, u64::MAX)
                } else {
                    let total = count_csv(path)?;
                    shard.range(total)
                };
                let mut me = ProbeReader {
                    path: path.into(),
                    inner: Inner::Csv { rdr: csv_reader(path)?, header_checked: false },
                    remaining: end - start,
                    len: end - start,
                };
                // Skip the probes before this shard (parsing only their boundaries).
                let mut skip = start;
                let mut rec = csv::ByteRecord::new();
                while skip > 0 {
                    if !me.next_record(&mut rec)? {
                        break;
                    }
                    skip -= 1;
                }
                Ok(me)
            }
        }
    }

    /// The next data record of a CSV (skipping blank lines and the header); false at the end.
    fn next_record(&mut self, rec: &mut csv::ByteRecord) -> Result<bool> {
        let Inner::Csv { rdr, header_checked } = &mut self.inner else { unreachable!("CSV only") };
        loop {
            let more = rdr.read_byte_record(rec).with_context(|| format!("{}: unreadable CSV", self.path.display()))?;
            if !more {
                return Ok(false);
            }
            if is_blank(rec) {
                continue;
            }
            if !*header_checked {
                *header_checked = true;
                if is_header(rec) {
                    continue;
                }
            }
            return Ok(true);
        }
    }

    /// Up to `max` more probes of the shard; None at its end.
    pub fn next_chunk(&mut self, max: usize) -> Result<Option<Vec<Sh9>>> {
        let want = (max as u64).min(self.remaining) as usize;
        if want == 0 {
            return Ok(None);
        }
        let out = match &mut self.inner {
            Inner::F32 { rdr } => {
                let mut buf = vec![0u8; want * COEFFS * 4];
                rdr.read_exact(&mut buf).with_context(|| format!("{}: unexpected end of file", self.path.display()))?;
                let probes: Vec<Sh9> = buf
                    .par_chunks_exact(COEFFS * 4)
                    .map(|b| {
                        from_coeffs(&std::array::from_fn(|k| {
                            f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]) as f64
                        }))
                    })
                    .collect();
                if let Some(i) = probes.iter().position(|p| !p.is_finite()) {
                    let at = self.len - self.remaining + i as u64;
                    bail!("{}: probe {at} (of this shard) holds a NaN or infinite value", self.path.display());
                }
                probes
            }
            Inner::Csv { .. } => {
                let mut recs = Vec::with_capacity(want);
                let mut rec = csv::ByteRecord::new();
                while recs.len() < want && self.next_record(&mut rec)? {
                    recs.push(rec.clone());
                }
                if recs.is_empty() {
                    self.remaining = 0;
                    return Ok(None);
                }
                let parsed: Vec<Result<Sh9, String>> = recs.par_iter().map(parse_record).collect();
                let mut probes = Vec::with_capacity(parsed.len());
                for (r, p) in recs.iter().zip(parsed) {
                    match p {
                        Ok(p) => probes.push(p),
                        Err(e) => {
                            let line = r.position().map(|p| p.line()).unwrap_or(0);
                            bail!("{}:{line}: {e}", self.path.display());
                        }
                    }
                }
                probes
            }
        };
        self.remaining -= out.len() as u64;
        Ok(Some(out))
    }
}

fn parse_record(r: &csv::ByteRecord) -> Result<Sh9, String> {
    if r.len() != COEFFS {
        return Err(format!(
            "expected {COEFFS} numbers (a probe's L2 SH, coefficient-major RGB), got {} field(s)",
            r.len()
        ));
    }
    let mut v = [0.0; COEFFS];
    for (k, f) in r.iter().enumerate() {
        let s = std::str::from_utf8(f).map_err(|_| format!("field {} is not UTF-8", k + 1))?;
        let x: f64 = s.parse().map_err(|_| format!("field {} ('{s}') is not a number", k + 1))?;
        if !x.is_finite() {
            return Err(format!("field {} ('{s}') is not finite", k + 1));
        }
        v[k] = x;
    }
    Ok(from_coeffs(&v))
}

/// Counts the data records of a CSV probe file.
fn count_csv(path: &Path) -> Result<u64> {
    let mut r = ProbeReader {
        path: path.into(),
        inner: Inner::Csv { rdr: csv_reader(path)?, header_checked: false },
        remaining: u64::MAX,
        len: u64::MAX,
    };
    let mut rec = csv::ByteRecord::new();
    let mut n = 0;
    while r.next_record(&mut rec)? {
        n += 1;
    }
    Ok(n)
}

/// Reads every probe of a file (for small sets and tools such as `fit-hallucination`).
pub fn read_all(path: &Path, format: Option<&str>) -> Result<Vec<Sh9>> {
    let mut r = ProbeReader::open(path, Format::resolve(path, format)?, Shard::ALL)?;
    let mut out = Vec::new();
    while let Some(c) = r.next_chunk(DEFAULT_CHUNK)? {
        out.extend(c);
    }
    Ok(out)
}

/// Writes probes in `format` (CSV: a `#` comment line naming the layout, then shortest
/// round-trip decimals; F32: raw little-endian).
pub fn write_probes(w: &mut impl Write, format: Format, probes: &[Sh9], first: bool) -> Result<()> {
    match format {
        Format::Csv => {
            if first {
                writeln!(w, "# probelab L2 SH radiance probes: 27 numbers per row, coefficient-major RGB (c0.r,c0.g,c0.b,c1.r,...,c8.b), FORMULAS section 2 basis")?;
            }
            let mut line = String::with_capacity(27 * 24);
            for p in probes {
                line.clear();
                for (k, v) in to_coeffs(p).iter().enumerate() {
                    if k > 0 {
                        line.push(',');
                    }
                    line.push_str(&crate::pipeline::table::num(*v));
                }
                line.push('\n');
                w.write_all(line.as_bytes())?;
            }
        }
        Format::F32 => {
            let mut buf = Vec::with_capacity(probes.len() * COEFFS * 4);
            for p in probes {
                for v in to_coeffs(p) {
                    buf.extend_from_slice(&(v as f32).to_le_bytes());
                }
            }
            w.write_all(&buf)?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Synthesis

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny counter-based generator, seeded per probe.
#[derive(Clone, Debug)]
pub struct Rng(u64);

fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    /// The stream of probe `index` of the set seeded by `seed`.
    pub fn for_probe(seed: u64, index: u64) -> Self {
        Rng(mix64(seed ^ mix64(index.wrapping_add(0x9e37_79b9_7f4a_7c15))))
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.0)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
    /// A uniformly random unit vector.
    pub fn direction(&mut self) -> DVec3 {
        let z = self.uniform(-1.0, 1.0);
        let (s, c) = (TAU * self.f64()).sin_cos();
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * c, r * s, z)
    }
    /// A random light colour of Rec.709 luminance 1 (saturation up to 0.6).
    pub fn colour(&mut self) -> Rgb {
        let s = self.uniform(0.0, 0.6);
        let c = Rgb::new(self.f64(), self.f64(), self.f64()).map(|u| (1.0 + s * (2.0 * u - 1.0)).max(0.05));
        c / luminance(c)
    }
}

/// The probe synthesiser (see the module doc).
#[derive(Clone, Debug)]
pub struct Synth {
    pub seed: u64,
    /// Palette SH3, each normalised to mean radiance luminance 1.
    palette: Vec<Sh9>,
    pub palette_names: Vec<String>,
}

impl Synth {
    /// A synthesiser over `palette` (name, radiance SH3); entries with no light are dropped.
    pub fn new(seed: u64, palette: Vec<(String, Sh9)>) -> Self {
        let mut names = Vec::new();
        let mut sh = Vec::new();
        for (n, s) in palette {
            let mean = luminance(s[0] * crate::math::sh::k::Y00);
            if mean > 0.0 && s.is_finite() {
                names.push(n);
                sh.push(s * (1.0 / mean));
            }
        }
        Synth { seed, palette: sh, palette_names: names }
    }

    /// A short fingerprint of the seed and palette (FNV-1a over their bits).
    pub fn fingerprint(&self) -> String {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |x: u64| {
            for b in x.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        eat(self.seed);
        for s in &self.palette {
            for v in to_coeffs(s) {
                eat(v.to_bits());
            }
        }
        format!("{h:016x}")
    }

    /// Probe `i` of the set.
    pub fn probe(&self, i: u64) -> Sh9 {
        let mut rng = Rng::for_probe(self.seed, i);
        let mut sh = Sh9::ZERO;
        let with_map = !self.palette.is_empty() && rng.f64() < 0.8;
        let exposure = 2f64.powf(rng.uniform(-3.0, 3.0));
        if with_map {
            let m = &self.palette[rng.below(self.palette.len())];
            let q = uniform_rotation(rng.f64(), rng.f64(), rng.f64());
            sh = ShRotation::from_quat(q).apply(m) * exposure;
        }
        if !with_map || rng.f64() < 0.5 {
            let c = rng.colour() * (2f64.powf(rng.uniform(-4.0, 0.0)) * exposure);
            sh = sh + constant(c);
        }
        let lights = (rng.below(4) + usize::from(!with_map)).min(3);
        for _ in 0..lights {
            let kind = rng.below(3);
            let d = rng.direction();
            let colour = rng.colour() * exposure;
            sh = sh
                + match kind {
                    // Directional: E/π facing it = e/π.
                    0 => delta_light(d, colour * (PI * 2f64.powf(rng.uniform(-2.0, 3.0)))),
                    // Sphere and cone lights: caps; on their axis E/π = L·sin²α (FORMULAS §1 units).
                    _ => {
                        let (lo, hi, e_lo, e_hi) =
                            if kind == 1 { (0.5, 15.0, -2.0, 3.0) } else { (15.0, 60.0, -3.0, 1.0) };
                        let alpha = rng.uniform(lo, hi).to_radians();
                        let e = 2f64.powf(rng.uniform(e_lo, e_hi));
                        Light::Cap { axis: d, half_angle: alpha, radiance: colour * (e / alpha.sin().powi(2)) }.sh()
                    }
                };
        }
        sh
    }

    /// Probes [start, end) in parallel (index order).
    pub fn probes(&self, start: u64, end: u64) -> Vec<Sh9> {
        (start..end).into_par_iter().map(|i| self.probe(i)).collect()
    }
}

// ---------------------------------------------------------------------------------------------
// Scoring

/// The fixed quadrature of the non-closed-form errors: 6 Gauss–Legendre nodes in z × 12
/// azimuths, weights summing to 1 (exact for polynomials of degree ≤ 11 on the sphere).
pub struct SphereRule {
    /// "NZxNPHI", e.g. "6x12".
    pub label: String,
    pub nodes: Vec<(DVec3, f64)>,
    /// The SH basis at each node (so the reference costs 9 multiply-adds a node).
    basis: Vec<[f64; N_SH]>,
}

impl SphereRule {
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
    ClosedForm,
    Quadrature,
}

/// The sphere RMSE of a fit against the SH3 irradiance `reference` (E/π SH), by the closed form
/// when the fit has one ([`Fitted::sphere_sq_error`]: SH3 fits, Geomerics), else by `rule`.
pub fn probe_rmse(fit: &dyn Fitted, reference: &Sh9, rule: &SphereRule) -> (f64, Method) {
    match fit.sphere_sq_error(reference) {
        Some(se) => ((se.max(0.0) / (3.0 * 4.0 * PI)).sqrt(), Method::ClosedForm),
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

/// RMS over the sphere of SH (RGB mean), closed form.
pub fn sh_rms(sh: &Sh9) -> f64 {
    ((0..N_SH).map(|i| sh[i].length_squared()).sum::<f64>() / (3.0 * 4.0 * PI)).sqrt()
}

/// The statistics of one encoder over a set (or a shard of one).
#[derive(Clone, Debug, PartialEq)]
pub struct EncoderStats {
    pub name: String,
    pub stored_scalars: usize,
    pub closed_form: u64,
    pub quadrature: u64,
    /// Wall seconds spent fitting and scoring this encoder (summed over shards when merged).
    pub seconds: f64,
    pub rmse: Summary,
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
    pub shard_count: usize,
    /// The shards this state covers.
    pub shards: Vec<usize>,
    /// The quadrature rule of non-SH3 errors ("NZxNPHI").
    pub quadrature: String,
    pub probes: u64,
    /// Wall seconds of the run (summed over shards when merged).
    pub wall_s: f64,
    /// Seconds reading or synthesising probes (summed over shards).
    pub input_s: f64,
    /// Peak resident memory (VmHWM) of the run, in bytes (max over shards); 0 if unknown.
    pub peak_mem_bytes: u64,
    pub threads: usize,
    pub encoders: Vec<EncoderStats>,
}

/// Where probes come from.
pub enum Source {
    Synth { synth: Synth, start: u64, end: u64, next: u64 },
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
}

/// Peak resident set size of this process (VmHWM in /proc/self/status), in bytes.
pub fn peak_memory_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Scores `encoders` over every probe `source` yields, `chunk` probes at a time; `sink`
/// receives each chunk first (e.g. to save the set). Statistics are exact and order-free, so
/// the result does not depend on threads or chunk size (timings aside).
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
    loop {
        let t = Instant::now();
        let Some(set) = source.next_chunk(chunk.max(1))? else { break };
        input_s += t.elapsed().as_secs_f64();
        sink(&set)?;
        probes += set.len() as u64;
        for (e, st) in encoders.iter().zip(stats.iter_mut()) {
            let t = Instant::now();
            let values: Vec<(f64, f64, Method)> = set
                .par_iter()
                .with_min_len(256)
                .map(|p| {
                    let reference = p.convolve_cosine();
                    let fit = e.encoder.fit(&FitInput::sphere(p));
                    let (rmse, method) = probe_rmse(fit.as_ref(), &reference, rule);
                    let rms = sh_rms(&reference);
                    let rel = if rms > 0.0 {
                        rmse / rms
                    } else if rmse == 0.0 {
                        0.0
                    } else {
                        f64::INFINITY
                    };
                    (rmse, rel, method)
                })
                .collect();
            // The two summaries fold on two threads (adding is exact and order-free).
            let (rmse, rel) = (&mut st.rmse, &mut st.rel_rmse);
            rayon::join(|| values.iter().for_each(|v| rmse.add(v.0)), || values.iter().for_each(|v| rel.add(v.1)));
            let closed = values.iter().filter(|v| v.2 == Method::ClosedForm).count() as u64;
            st.closed_form += closed;
            st.quadrature += values.len() as u64 - closed;
            st.seconds += t.elapsed().as_secs_f64();
        }
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

impl SetStats {
    /// Merges another state of the same set (disjoint shards).
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
        self.shards.extend(&o.shards);
        self.shards.sort_unstable();
        self.probes += o.probes;
        self.wall_s += o.wall_s;
        self.input_s += o.input_s;
        self.peak_mem_bytes = self.peak_mem_bytes.max(o.peak_mem_bytes);
        self.threads = self.threads.max(o.threads);
        for (a, b) in self.encoders.iter_mut().zip(&o.encoders) {
            a.closed_form += b.closed_form;
            a.quadrature += b.quadrature;
            a.seconds += b.seconds;
            a.rmse.merge(&b.rmse);
            a.rel_rmse.merge(&b.rel_rmse);
        }
        Ok(())
    }

    /// Whether every shard of the set is present.
    pub fn complete(&self) -> bool {
        self.shards.len() == self.shard_count
    }

    /// The summary table (CSV): one row per encoder. Documented in README ("Probe sets").
    pub fn summary_csv(&self) -> Result<Vec<u8>> {
        let num = crate::pipeline::table::num;
        let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
        let sh1 = self.encoders.iter().find(|e| e.name == "sh1").map(|e| e.rmse.mean());
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(SUMMARY_COLUMNS)?;
        let shards = if self.complete() {
            format!("all {}", self.shard_count)
        } else {
            format!("{:?} of {}", self.shards, self.shard_count)
        };
        for e in &self.encoders {
            let reduction = match sh1 {
                Some(b) if b > 0.0 => num(1.0 - e.rmse.mean() / b),
                _ => String::new(),
            };
            let pps =
                if e.seconds > 0.0 { num((e.rmse.count + e.rmse.invalid) as f64 / e.seconds) } else { String::new() };
            w.write_record([
                e.name.clone(),
                self.probes.to_string(),
                num(e.rmse.mean()),
                opt(e.rmse.quantile(0.5)),
                opt(e.rmse.quantile(0.95)),
                num(e.rmse.max),
                num(e.rel_rmse.mean()),
                opt(e.rel_rmse.quantile(0.5)),
                opt(e.rel_rmse.quantile(0.95)),
                num(e.rel_rmse.max),
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
                self.source.clone(),
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
    "source",
];

/// Summary columns that vary from run to run (timings, memory, shard bookkeeping).
pub const SUMMARY_TIMING_COLUMNS: &[&str] = &["probes_per_s", "encoder_s", "wall_s", "peak_mem_mib", "shards"];

// ---------------------------------------------------------------------------------------------
// The state file

#[derive(Serialize, Deserialize)]
struct EncoderState {
    name: String,
    stored_scalars: usize,
    closed_form: u64,
    quadrature: u64,
    seconds: f64,
    rmse: SummaryState,
    rel_rmse: SummaryState,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StateFile {
    format: String,
    source: String,
    reference: String,
    shard_count: usize,
    shards: Vec<usize>,
    quadrature: String,
    probes: u64,
    wall_s: f64,
    input_s: f64,
    peak_mem_bytes: u64,
    threads: usize,
    encoders: Vec<EncoderState>,
}

impl SetStats {
    /// The state as TOML (exact: sums as big-integer digits, sketches as bucket counts).
    pub fn to_toml(&self) -> Result<String> {
        let f = StateFile {
            format: STATE_FORMAT.into(),
            source: self.source.clone(),
            reference: REFERENCE.into(),
            shard_count: self.shard_count,
            shards: self.shards.clone(),
            quadrature: self.quadrature.clone(),
            probes: self.probes,
            wall_s: self.wall_s,
            input_s: self.input_s,
            peak_mem_bytes: self.peak_mem_bytes,
            threads: self.threads,
            encoders: self
                .encoders
                .iter()
                .map(|e| EncoderState {
                    name: e.name.clone(),
                    stored_scalars: e.stored_scalars,
                    closed_form: e.closed_form,
                    quadrature: e.quadrature,
                    seconds: e.seconds,
                    rmse: (&e.rmse).into(),
                    rel_rmse: (&e.rel_rmse).into(),
                })
                .collect(),
        };
        Ok(toml::to_string(&f)?)
    }

    /// Reads a state file written by [`Self::to_toml`]; errors name the file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read probe statistics", path.display()))?;
        let f: StateFile = toml::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: not a probe statistics file: {e}", path.display()))?;
        if f.format != STATE_FORMAT {
            bail!("{}: format '{}', expected '{STATE_FORMAT}'", path.display(), f.format);
        }
        if f.reference != REFERENCE {
            bail!("{}: errors measured against '{}', expected '{REFERENCE}'", path.display(), f.reference);
        }
        if f.shard_count == 0 || f.shards.iter().any(|&s| s >= f.shard_count) {
            bail!("{}: shards {:?} do not fit shard_count {}", path.display(), f.shards, f.shard_count);
        }
        let encoders = f
            .encoders
            .into_iter()
            .map(|e| {
                Ok(EncoderStats {
                    name: e.name,
                    stored_scalars: e.stored_scalars,
                    closed_form: e.closed_form,
                    quadrature: e.quadrature,
                    seconds: e.seconds,
                    rmse: e.rmse.to_summary()?,
                    rel_rmse: e.rel_rmse.to_summary()?,
                })
            })
            .collect::<Result<Vec<_>>>()
            .with_context(|| format!("{}: corrupt statistics", path.display()))?;
        Ok(SetStats {
            source: f.source,
            shard_count: f.shard_count,
            shards: f.shards,
            quadrature: f.quadrature,
            probes: f.probes,
            wall_s: f.wall_s,
            input_s: f.input_s,
            peak_mem_bytes: f.peak_mem_bytes,
            threads: f.threads,
            encoders,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Command line: `probelab probes` and `probelab merge`

/// `probelab probes`: score encoders over a probe set (a file or synthetic).
#[derive(clap::Args, Debug)]
pub struct ProbesArgs {
    /// A probe file: CSV (27 numbers a row, coefficient-major RGB) or raw little-endian f32
    /// (.f32/.bin/.raw, 27 per probe). See README, "Probe sets".
    #[arg(long, conflicts_with = "synth", required_unless_present = "synth")]
    pub input: Option<PathBuf>,
    /// File format: csv or f32 (default: from the extension).
    #[arg(long)]
    pub format: Option<String>,
    /// Synthesise N probes instead (deterministic from --seed and the palette).
    #[arg(long)]
    pub synth: Option<u64>,
    /// Seed of the synthetic set.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Comma-separated maps whose SH3 seed synthetic probes (default: every *_256x128 map on
    /// the search path; the generated scenes when there is none).
    #[arg(long)]
    pub palette: Option<String>,
    /// Comma-separated encoder ids, or `all` (sh1 is always added: it is the baseline).
    #[arg(long, default_value = "sh1,sh2")]
    pub encoders: String,
    /// Process shard I of N (contiguous probe ranges); merge the --out files with `probelab merge`.
    #[arg(long, default_value = "0/1")]
    pub shard: String,
    /// Write the mergeable statistics (TOML) to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Quadrature rule NZxNPHI for encoders whose fit is not SH3 (6x12 is exact for outputs in SH
    /// bands <= 5; fewer nodes are faster and approximate; see README).
    #[arg(long, default_value = "6x12")]
    pub quadrature: String,
    /// Probes per chunk (memory in flight; results do not depend on it).
    #[arg(long, default_value_t = DEFAULT_CHUNK)]
    pub chunk: usize,
    /// Also write this shard's probes to FILE (.csv or .f32), e.g. to export a synthetic set.
    #[arg(long)]
    pub save: Option<PathBuf>,
}

/// `probelab merge`: combine shard statistics.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Statistics files written by `probelab probes --out`.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Write the merged statistics (TOML) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The encoders of `--encoders` (`all` = the registry), with sh1 first if it was not listed.
pub fn encoder_list(list: &str) -> Result<Vec<NamedEncoder>> {
    let list = if list.trim() == "all" {
        crate::encoders::REGISTRY.iter().map(|k| k.id).collect::<Vec<_>>().join(",")
    } else {
        list.to_string()
    };
    let mut v = crate::encoders::build_list(&list)?;
    if !v.iter().any(|e| e.name == "sh1") {
        v.insert(0, crate::encoders::build("sh1", None, toml::Table::new())?);
    }
    Ok(v)
}

/// The synthesis palette: the named maps, or every `*_256x128` map on the search path, or (with
/// none) the generated scenes' closed-form SH.
pub fn palette(search: &crate::envmap::search::SearchPath, names: Option<&str>) -> Result<Vec<(String, Sh9)>> {
    let paths: Vec<PathBuf> = match names {
        Some(list) => list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|n| search.resolve(n).map_err(anyhow::Error::from))
            .collect::<Result<_>>()?,
        None => {
            let mut found: Vec<(String, PathBuf)> = Vec::new();
            for d in search.dirs() {
                let Ok(entries) = std::fs::read_dir(d) else { continue };
                for p in entries.filter_map(|e| e.ok().map(|e| e.path())) {
                    let ext_ok = p.extension().is_some_and(|x| x == "exr" || x == "hdr");
                    let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("").to_string();
                    if ext_ok && stem.ends_with("_256x128") && !found.iter().any(|f| f.0 == stem) {
                        found.push((stem, p));
                    }
                }
            }
            found.sort();
            found.into_iter().map(|f| f.1).collect()
        }
    };
    if paths.is_empty() {
        return Ok(crate::reference::scenes::generated().into_iter().map(|s| (s.id.clone(), s.sh())).collect());
    }
    paths
        .par_iter()
        .map(|p| {
            let map = crate::envmap::load::load(p)?;
            Ok((map.name.clone(), crate::reference::projection::project(&map)))
        })
        .collect()
}

/// Runs `probelab probes`; prints the summary CSV on stdout and run figures on stderr.
pub fn command(a: ProbesArgs, search: &crate::envmap::search::SearchPath) -> Result<i32> {
    let shard = Shard::parse(&a.shard)?;
    let encoders = encoder_list(&a.encoders)?;
    let rule = SphereRule::parse(&a.quadrature)?;
    if a.chunk == 0 {
        bail!("--chunk must be at least 1");
    }
    let (mut source, source_id) = match (&a.input, a.synth) {
        (Some(path), _) => {
            let format = Format::resolve(path, a.format.as_deref())?;
            let bytes =
                std::fs::metadata(path).with_context(|| format!("{}: cannot open probe file", path.display()))?.len();
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            (Source::File(ProbeReader::open(path, format, shard)?), format!("file {name} ({bytes} bytes)"))
        }
        (None, Some(n)) => {
            let synth = Synth::new(a.seed, palette(search, a.palette.as_deref())?);
            let id = format!(
                "synth n={n} seed={} palette={} [{}] fingerprint={}",
                a.seed,
                synth.palette_names.len(),
                synth.palette_names.join(" "),
                synth.fingerprint()
            );
            let (start, end) = shard.range(n);
            (Source::Synth { synth, start, end, next: start }, id)
        }
        (None, None) => bail!("give --input FILE or --synth N"),
    };
    let stats = match &a.save {
        Some(path) => {
            let format = Format::resolve(path, None)?;
            let mut first = true;
            crate::pipeline::atomic::write_with(path, |w| {
                score(&mut source, &source_id, shard, &encoders, &rule, a.chunk, |c| {
                    write_probes(w, format, c, std::mem::take(&mut first))
                })
            })?
        }
        None => score(&mut source, &source_id, shard, &encoders, &rule, a.chunk, |_| Ok(()))?,
    };
    if let Some(out) = &a.out {
        crate::pipeline::atomic::write(out, stats.to_toml()?.as_bytes())?;
        eprintln!("wrote {}", out.display());
    }
    eprintln!(
        "probes: {} (shard {}/{}), wall {:.3} s, input {:.3} s, peak memory {:.1} MiB (VmHWM), {} thread(s)",
        stats.probes,
        shard.index,
        shard.count,
        stats.wall_s,
        stats.input_s,
        stats.peak_mem_bytes as f64 / (1024.0 * 1024.0),
        stats.threads
    );
    std::io::stdout().write_all(&stats.summary_csv()?)?;
    Ok(0)
}

/// Runs `probelab merge`.
pub fn merge_command(a: MergeArgs) -> Result<i32> {
    let mut merged: Option<SetStats> = None;
    for f in &a.files {
        let s = SetStats::load(f)?;
        match &mut merged {
            None => merged = Some(s),
            Some(m) => m.merge(&s).with_context(|| format!("merging {}", f.display()))?,
        }
    }
    let merged = merged.expect("clap requires at least one file");
    if !merged.complete() {
        let missing: Vec<usize> = (0..merged.shard_count).filter(|s| !merged.shards.contains(s)).collect();
        eprintln!("warning: partial merge: shard(s) {missing:?} of {} missing", merged.shard_count);
    }
    if let Some(out) = &a.out {
        crate::pipeline::atomic::write(out, merged.to_toml()?.as_bytes())?;
        eprintln!("wrote {}", out.display());
    }
    std::io::stdout().write_all(&merged.summary_csv()?)?;
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoders::build_list;

    fn palette() -> Vec<(String, Sh9)> {
        crate::reference::scenes::generated().into_iter().map(|s| (s.id.clone(), s.sh())).collect()
    }

    #[test]
    fn shard_ranges_partition_the_set() {
        for total in [0u64, 1, 7, 100, 3_000_000] {
            for n in 1..6 {
                let mut next = 0;
                for i in 0..n {
                    let (a, b) = Shard { index: i, count: n }.range(total);
                    assert_eq!(a, next);
                    next = b;
                }
                assert_eq!(next, total);
            }
        }
        assert_eq!(Shard::parse("2/5").unwrap(), Shard { index: 2, count: 5 });
        assert_eq!(SphereRule::parse("3x6").unwrap().nodes.len(), 18);
        for bad in ["6", "0x4", "6x0", "65x2", "ax3"] {
            assert!(SphereRule::parse(bad).is_err(), "{bad}");
        }
        for bad in ["5/5", "1/0", "x/2", "3", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn synthesis_is_deterministic_and_physical() {
        let s = Synth::new(7, palette());
        assert_eq!(s.probe(12345), s.probe(12345));
        assert_ne!(s.probe(1), s.probe(2));
        assert_ne!(Synth::new(8, palette()).probe(1), s.probe(1));
        assert_eq!(s.probes(10, 20)[3], s.probe(13));
        // Every probe is a sum of non-negative lights: its mean radiance is positive, and its
        // SH3 irradiance (a smoothed non-negative function) is mostly non-negative.
        for i in 0..2000 {
            let p = s.probe(i);
            assert!(p.is_finite() && p[0].min_element() > 0.0, "probe {i}: {:?}", p[0]);
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
        }
        let s = Synth::new(3, palette());
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
        }
        let s = Synth::new(5, palette());
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
        }
        struct Clamped(Sh9);
        impl Fitted for Clamped {
            fn irradiance(&self, n: DVec3) -> Rgb {
                self.0.eval(n).max(Rgb::ZERO)
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

    fn score_synth(synth: &Synth, n: u64, shard: Shard, chunk: usize) -> SetStats {
        let (start, end) = shard.range(n);
        let mut src = Source::Synth { synth: synth.clone(), start, end, next: start };
        let rule = SphereRule::standard();
        score(&mut src, "test", shard, &build_list("sh0,sh1,sh2").unwrap(), &rule, chunk, |_| Ok(())).unwrap()
    }

    fn strip_timing(mut s: SetStats) -> SetStats {
        s.wall_s = 0.0;
        s.input_s = 0.0;
        s.peak_mem_bytes = 0;
        for e in &mut s.encoders {
            e.seconds = 0.0;
        }
        s
    }

    /// Splitting a set in two (here: unevenly, with different chunk sizes) and merging the two
    /// shard states gives exactly the one-pass state, through the TOML files.
    #[test]
    fn shards_merge_exactly() {
        let synth = Synth::new(11, palette());
        let n = 5003;
        let whole = strip_timing(score_synth(&synth, n, Shard::ALL, 1000));
        let dir = tempfile::tempdir().unwrap();
        let mut parts = Vec::new();
        for (i, chunk) in [(0, 333), (1, 4096)] {
            let s = score_synth(&synth, n, Shard { index: i, count: 2 }, chunk);
            let p = dir.path().join(format!("s{i}.toml"));
            std::fs::write(&p, s.to_toml().unwrap()).unwrap();
            parts.push(SetStats::load(&p).unwrap());
        }
        let mut merged = parts[0].clone();
        merged.merge(&parts[1]).unwrap();
        let mut merged = strip_timing(merged);
        assert_eq!(merged.shards, vec![0, 1]);
        merged.shard_count = 1;
        merged.shards = vec![0];
        assert_eq!(merged, whole);
        let e = parts[0].clone().merge(&parts[0]).err().unwrap().to_string();
        assert!(e.contains("twice"), "{e}");
    }

    /// The statistics are what a direct computation gives: sh2 is exact (rmse 0), and sh1's
    /// mean rmse equals the mean of independently computed band-2 energies.
    #[test]
    fn statistics_match_a_direct_computation() {
        let synth = Synth::new(5, palette());
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
        assert!((sh1.rmse.mean() - mean).abs() < 1e-12 * mean, "{} vs {mean}", sh1.rmse.mean());
        direct.sort_by(f64::total_cmp);
        let p95 = direct[(0.95 * n as f64).ceil() as usize - 1];
        let got = sh1.rmse.quantile(0.95).unwrap();
        assert!((got - p95).abs() <= crate::math::stats::SKETCH_RELATIVE_ERROR * p95);
        assert!(sh0.rmse.mean() > sh1.rmse.mean());
        let csv = String::from_utf8(s.summary_csv().unwrap()).unwrap();
        assert!(csv.starts_with(&SUMMARY_COLUMNS.join(",")));
        assert!(csv.contains("\nsh2,3000,0,"), "{csv}");
    }

    #[test]
    fn csv_and_f32_files_round_trip_and_shard() {
        let synth = Synth::new(9, palette());
        let probes = synth.probes(0, 101);
        let dir = tempfile::tempdir().unwrap();
        for (name, format) in [("p.csv", Format::Csv), ("p.f32", Format::F32)] {
            let path = dir.path().join(name);
            let mut f = std::fs::File::create(&path).unwrap();
            write_probes(&mut f, format, &probes[..50], true).unwrap();
            write_probes(&mut f, format, &probes[50..], false).unwrap();
            drop(f);
            let back = read_all(&path, None).unwrap();
            assert_eq!(back.len(), 101);
            for (a, b) in back.iter().zip(&probes) {
                for k in 0..9 {
                    let want = if format == Format::F32 { b[k].as_vec3().as_dvec3() } else { b[k] };
                    assert_eq!(a[k], want, "{name}");
                }
            }
            // Three shards cover the file in order.
            let mut all = Vec::new();
            for i in 0..3 {
                let mut r = ProbeReader::open(&path, format, Shard { index: i, count: 3 }).unwrap();
                while let Some(c) = r.next_chunk(7).unwrap() {
                    all.extend(c);
                }
            }
            assert_eq!(all, back, "{name}");
        }
    }

    /// Coefficient-major order: a row 1..27 puts 1,2,3 in c0 (r,g,b) and 4,5,6 in c1.
    #[test]
    fn csv_order_is_coefficient_major_with_header_comments_and_blanks() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("o.csv");
        let row: Vec<String> = (1..=27).map(|k| k.to_string()).collect();
        let header: Vec<String> = (0..9).flat_map(|i| ["r", "g", "b"].map(|c| format!("c{i}_{c}"))).collect();
        std::fs::write(
            &path,
            format!("# comment\n{}\n\n{}\n  {} \n", header.join(","), row.join(","), row.join(" , ")),
        )
        .unwrap();
        let p = read_all(&path, None).unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0][0], Rgb::new(1.0, 2.0, 3.0));
        assert_eq!(p[0][1], Rgb::new(4.0, 5.0, 6.0));
        assert_eq!(p[1][8], Rgb::new(25.0, 26.0, 27.0));
    }

    #[test]
    fn bad_files_name_the_file_line_and_fault() {
        let dir = tempfile::tempdir().unwrap();
        let ones = vec!["1"; 27].join(",");
        let cases = [
            ("short.csv", format!("{ones}\n1,2,3\n"), "short.csv:2: expected 27 numbers"),
            ("word.csv", format!("{ones}\n{}x\n", "1,".repeat(26)), "word.csv:2: field 27 ('x') is not a number"),
            ("nan.csv", format!("{}NaN\n", "1,".repeat(26)), "nan.csv:1: field 27 ('NaN') is not finite"),
        ];
        for (name, text, want) in cases {
            let p = dir.path().join(name);
            std::fs::write(&p, text).unwrap();
            let e = format!("{:#}", read_all(&p, None).err().unwrap());
            assert!(e.contains(want), "{e}");
        }
        let p = dir.path().join("cut.f32");
        std::fs::write(&p, vec![0u8; 108 * 2 + 5]).unwrap();
        assert!(format!("{:#}", read_all(&p, None).err().unwrap()).contains("not a multiple of 108"));
        let p = dir.path().join("inf.f32");
        let mut b = vec![0u8; 108];
        b[4..8].copy_from_slice(&f32::INFINITY.to_le_bytes());
        std::fs::write(&p, b).unwrap();
        assert!(format!("{:#}", read_all(&p, None).err().unwrap()).contains("NaN or infinite"));
        assert!(Format::resolve(Path::new("x.txt"), None).is_err());
    }
}
