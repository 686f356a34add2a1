//! Probe files: L2 SH radiance probes read from and written to disk, streamed in chunks (memory
//! does not grow with the file) and split into shards.
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
//!   first field starts with a letter is a header and is skipped.
//! - Raw binary (`.f32`, `.bin`, `.raw`): little-endian IEEE f32, 27 per probe, no header; the
//!   file size must be a multiple of 108 bytes.
//!
//! Every value must be finite with |v| ≤ [`MAX_PROBE_VALUE`] (so no encoder's arithmetic on it
//! overflows; a value outside is refused with its line or probe index and field), and a file
//! must hold at least one probe (an empty, comment-only or header-only file is an error). A
//! file is identified by the sha256 of its bytes ([`file_identity`]), so shards of different
//! files never merge.

use crate::math::colour::Rgb;
use crate::math::sh::{Sh9, N_SH};
use crate::pipeline::probeset::shard::Shard;
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use std::io::{BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Numbers per probe.
pub const COEFFS: usize = 3 * N_SH;
/// Probes per chunk by default (about 7 MB of probes in flight).
pub const DEFAULT_CHUNK: usize = 32_768;
/// The largest accepted |coefficient| of a probe. Scoring squares sums of coefficients and some
/// encoders take cubes and ratios of them; 1e30 keeps all of that far inside the f64 range
/// (1e30³ = 1e90), while real radiance, even a sun, is below 1e10. The bound is 1e30 as an f32
/// holds it (1.0000000150474662e30), in both formats, so that 1e30 written by any tool, in text
/// or as f32, is accepted (a raw f32 1e30 was once refused).
pub const MAX_PROBE_VALUE: f64 = 1e30_f32 as f64;

/// The identity of a probe file: its name, size and the sha256 of its bytes. Shards merge only
/// when their identities are equal, so two files of one size are never taken for one set.
pub fn file_identity(path: &Path) -> Result<String> {
    let f = std::fs::File::open(path).with_context(|| format!("{}: cannot open probe file", path.display()))?;
    let bytes = f.metadata().with_context(|| format!("{}: cannot stat", path.display()))?.len();
    let sha = crate::envmap::load::sha256_hex_of(BufReader::new(f))
        .with_context(|| format!("{}: cannot read probe file", path.display()))?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(format!("file {name} ({bytes} bytes, sha256 {sha})"))
}

/// Why a value is not a valid probe coefficient, if it is not.
fn bad_value(x: f64) -> Option<&'static str> {
    if !x.is_finite() {
        Some("is not finite")
    } else if x.abs() > MAX_PROBE_VALUE {
        Some("is out of range (|value| must be at most 1e30, as f32 rounds it: 1.0000000150474662e30)")
    } else {
        None
    }
}

/// A probe file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated text, one probe per line.
    Csv,
    /// Raw little-endian f32 records.
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
    /// Index in the file of this shard's first probe.
    start: u64,
    /// Where the last chunk's probes are: their line numbers (CSV) or nothing (raw f32, whose
    /// probes are numbered from `chunk_first`).
    chunk_lines: Vec<u64>,
    chunk_first: u64,
    /// The file holds no probe at all (known only for unsharded CSV when its end is reached).
    whole_file: bool,
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
                if bytes == 0 {
                    bail!("{}: empty probe file (0 bytes): no probes", path.display());
                }
                let (start, end) = shard.range(bytes / rec);
                let mut rdr = BufReader::with_capacity(1 << 20, f);
                rdr.seek(SeekFrom::Start(start * rec)).with_context(|| format!("{}: cannot seek", path.display()))?;
                Ok(ProbeReader {
                    path: path.into(),
                    inner: Inner::F32 { rdr },
                    remaining: end - start,
                    len: end - start,
                    start,
                    chunk_lines: Vec::new(),
                    chunk_first: start,
                    whole_file: false,
                })
            }
            Format::Csv => {
                let (start, end) = if shard.count == 1 {
                    (0, u64::MAX)
                } else {
                    let total = count_csv(path)?;
                    if total == 0 {
                        bail!("{}: {NO_PROBES}", path.display());
                    }
                    shard.range(total)
                };
                let mut me = ProbeReader {
                    path: path.into(),
                    inner: Inner::Csv { rdr: csv_reader(path)?, header_checked: false },
                    remaining: end - start,
                    len: end - start,
                    start,
                    chunk_lines: Vec::new(),
                    chunk_first: start,
                    whole_file: shard.count == 1,
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
                let first = self.start + (self.len - self.remaining);
                for (i, p) in probes.iter().enumerate() {
                    for (k, x) in to_coeffs(p).into_iter().enumerate() {
                        if let Some(why) = bad_value(x) {
                            bail!(
                                "{}: probe {} (byte {}), value {} ({x}) {why}",
                                self.path.display(),
                                first + i as u64,
                                (first + i as u64) * (COEFFS as u64 * 4) + 4 * k as u64,
                                k + 1
                            );
                        }
                    }
                }
                self.chunk_first = first;
                probes
            }
            Inner::Csv { .. } => {
                let mut recs = Vec::with_capacity(want);
                let mut rec = csv::ByteRecord::new();
                while recs.len() < want && self.next_record(&mut rec)? {
                    recs.push(rec.clone());
                }
                if recs.is_empty() {
                    if self.whole_file && self.remaining == self.len {
                        bail!("{}: {NO_PROBES}", self.path.display());
                    }
                    self.remaining = 0;
                    return Ok(None);
                }
                let parsed: Vec<Result<Sh9, String>> = recs.par_iter().map(parse_record).collect();
                let mut probes = Vec::with_capacity(parsed.len());
                self.chunk_lines.clear();
                for (r, p) in recs.iter().zip(parsed) {
                    let line = r.position().map(|p| p.line()).unwrap_or(0);
                    match p {
                        Ok(p) => probes.push(p),
                        Err(e) => bail!("{}:{line}: {e}", self.path.display()),
                    }
                    self.chunk_lines.push(line);
                }
                self.chunk_first = self.start + (self.len - self.remaining);
                probes
            }
        };
        self.remaining -= out.len() as u64;
        Ok(Some(out))
    }

    /// Where probe `k` of the last chunk is in the file: "FILE:LINE" (CSV) or "FILE: probe I"
    /// (raw f32, I counted from 0 in the whole file).
    pub fn locate(&self, k: usize) -> String {
        match self.chunk_lines.get(k) {
            Some(line) => format!("{}:{line}", self.path.display()),
            None => format!("{}: probe {}", self.path.display(), self.chunk_first + k as u64),
        }
    }
}

/// What an input without a single probe is told.
const NO_PROBES: &str = "no probes: the file is empty or holds only comments, blank lines or a header";

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
        if let Some(why) = bad_value(x) {
            return Err(format!("field {} ('{s}') {why}", k + 1));
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
        start: 0,
        chunk_lines: Vec::new(),
        chunk_first: 0,
        whole_file: false,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::probeset::synth::{scene_palette, Synth};

    #[test]
    fn csv_and_f32_files_round_trip_and_shard() {
        let synth = Synth::new(9, scene_palette());
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
        assert!(format!("{:#}", read_all(&p, None).err().unwrap()).contains("is not finite"));
        assert!(Format::resolve(Path::new("x.txt"), None).is_err());
    }

    /// The bound ±1e30 holds the same in both formats: 1e30 as f32 (1.000000015e30) is accepted
    /// raw and as text, the next f32 up is refused in both.
    #[test]
    fn the_bound_is_1e30_as_f32_holds_it_in_both_formats() {
        let dir = tempfile::tempdir().unwrap();
        let at = 1e30f32;
        assert_eq!(f64::from(at), 1.0000000150474662e30);
        let above = f32::from_bits(at.to_bits() + 1);
        for (v, ok) in [(at, true), (-at, true), (above, false)] {
            let raw = dir.path().join("v.f32");
            std::fs::write(&raw, [v.to_le_bytes().to_vec(), vec![0u8; 104]].concat()).unwrap();
            let text = dir.path().join("v.csv");
            std::fs::write(&text, format!("{}{}\n", f64::from(v), ",0".repeat(26))).unwrap();
            for p in [&raw, &text] {
                let got = read_all(p, None);
                assert_eq!(got.is_ok(), ok, "{v:e} in {}: {:?}", p.display(), got.err());
            }
        }
        let text = dir.path().join("w.csv");
        std::fs::write(&text, format!("1.000000015e30{}\n", ",0".repeat(26))).unwrap();
        assert!(read_all(&text, None).is_ok());
    }
}
