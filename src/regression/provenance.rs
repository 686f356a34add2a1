//! Provenance of a result table: `results/<experiment>/provenance.toml`, written with the
//! table (atomically, as one baseline) by `run`, `reproduce` and `bless`.
//!
//! It records what the numbers came from: the probelab version and git commit, the date, the
//! experiment's settings (its file verbatim and the parsed values), each map's file name,
//! sha256, pixel sha256 and resolution, the reference method ([`crate::reference::exact::Reference::describe`]) and
//! the sha256 of the table itself. `probelab check` reads the map checksums (a map that changed
//! is reported, never compared silently) and the table checksum (a table edited by hand, or an
//! interrupted `bless`, is reported). Nothing else in it counts as a change: a new date or
//! commit alone never fails a check.

use crate::envmap::load::sha256_hex;
use crate::pipeline::experiment::{DomainKind, Experiment};
use crate::pipeline::runner::RunReport;
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file name, next to `table.csv`.
pub const FILE_NAME: &str = "provenance.toml";

/// The provenance record. Unknown fields are accepted when reading (older or newer writers).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Provenance {
    /// The experiment's name.
    pub experiment: String,
    /// The probelab version (`CARGO_PKG_VERSION`) that wrote the table.
    pub probelab_version: String,
    /// `git rev-parse HEAD` at the time of the run, or "unknown" outside a git checkout.
    pub git_commit: String,
    /// Whether a file that can change the numbers differed from that commit ([`NUMBER_INPUTS`]
    /// and the experiment's file: uncommitted code or settings produced them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub git_dirty: Option<bool>,
    /// UTC, ISO 8601.
    pub date: String,
    /// sha256 of the table.csv written with this file.
    pub table_sha256: String,
    /// The settings the runner used.
    pub settings: Settings,
    /// Every map the run read.
    #[serde(default)]
    pub maps: Vec<MapRecord>,
}

/// The experiment's settings as the runner used them.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Settings {
    /// The experiment file, relative to the repository root where possible.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// `sphere` or `hemisphere`.
    pub domain: String,
    /// Each orientation's label with its normal.
    pub orientations: Vec<String>,
    /// The metrics' names.
    pub metrics: Vec<String>,
    /// Output resolution [W, H].
    pub resolution: [usize; 2],
    /// Gauss–Legendre nodes per row piece of the reference.
    pub polar_nodes: usize,
    /// Whether the CI check re-runs the experiment.
    pub ci: bool,
    /// Every encoder, in table order.
    pub encoders: Vec<EncoderRecord>,
    /// The experiment file's text, verbatim (empty for experiments built in code).
    pub experiment_toml: String,
}

/// An encoder as configured: its table name, kind, and solver class.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct EncoderRecord {
    /// The encoder's name in the table.
    pub name: String,
    /// Its registry id.
    pub kind: String,
    /// Whether its fit is iterative (its class for tolerance rules).
    pub iterative: bool,
}

/// A map as read.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct MapRecord {
    /// The map's name.
    pub name: String,
    /// The file's name (not its folder, which depends on the machine).
    pub file: String,
    /// sha256 of the file.
    pub sha256: String,
    /// The pixel sha256 (`envmap::identity`): the map's identity whatever file holds it.
    /// Absent from files written before it was recorded (docs/maps.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pixel_sha256: Option<String>,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// The product of the `.hdr` file's `EXPOSURE=` values its pixel values were divided by;
    /// written only when it is not 1, so the provenance of every other map reads as before.
    #[serde(default = "exposure_one", skip_serializing_if = "is_exposure_one")]
    pub exposure: f64,
    /// What was done to the file's colour beyond the exposure (a `COLORCORR=` undone, other
    /// primaries converted to Rec.709); written only when something was.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub colour: String,
    /// The reference method the map was scored against.
    pub reference: String,
}

/// The exposure of a map whose provenance does not say one: 1.
fn exposure_one() -> f64 {
    1.0
}

/// Whether an exposure is 1 (and so left out of the file).
fn is_exposure_one(e: &f64) -> bool {
    *e == 1.0
}

/// A map's size as the provenance pages show it: `WxH`, its exposure when it is not 1, and
/// what was done to its colour, if anything.
pub fn size_and_exposure(width: usize, height: usize, exposure: f64, colour: &str) -> String {
    let mut text = format!("{width}x{height}");
    if exposure != 1.0 {
        text += &format!(", EXPOSURE={exposure} (the file's pixel values divided by it)");
    }
    if !colour.is_empty() {
        text += &format!(", {colour}");
    }
    text
}

impl Provenance {
    /// The provenance of `table` (the CSV bytes about to be written) produced by `report`.
    pub fn new(exp: &Experiment, report: &RunReport, table: &[u8], root: &Path) -> Self {
        let (git_commit, git_dirty) = git_state(root, exp.source.as_deref());
        let file = exp.source.as_ref().map(|p| {
            let rel = p.strip_prefix(root).unwrap_or(p);
            rel.to_string_lossy().into_owned()
        });
        let experiment_toml = exp.source.as_ref().and_then(|p| std::fs::read_to_string(p).ok()).unwrap_or_default();
        let mut orientations: Vec<String> = Vec::new();
        for o in &exp.orientations {
            orientations.push(format!("{} ({:?})", o.label, o.normal.to_array()));
        }
        Provenance {
            experiment: exp.name.clone(),
            probelab_version: env!("CARGO_PKG_VERSION").into(),
            git_commit,
            git_dirty,
            date: utc_now(),
            table_sha256: sha256_hex(table),
            settings: Settings {
                file,
                domain: match exp.domain {
                    DomainKind::Sphere => "sphere".into(),
                    DomainKind::Hemisphere => "hemisphere".into(),
                },
                orientations,
                metrics: exp.metrics.iter().map(|m| m.name().to_string()).collect(),
                resolution: [exp.resolution.0, exp.resolution.1],
                polar_nodes: exp.polar_nodes,
                ci: exp.ci,
                encoders: exp
                    .encoders
                    .iter()
                    .map(|e| EncoderRecord {
                        name: e.name.clone(),
                        kind: e.encoder.id().to_string(),
                        iterative: e.encoder.is_iterative(),
                    })
                    .collect(),
                experiment_toml,
            },
            maps: report
                .maps
                .iter()
                .map(|m| MapRecord {
                    name: m.name.clone(),
                    file: m
                        .path
                        .as_ref()
                        .and_then(|p| p.file_name())
                        .map(|f| f.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    sha256: m.sha256.clone(),
                    pixel_sha256: Some(m.pixel_sha256.clone()).filter(|p| !p.is_empty()),
                    width: m.width,
                    height: m.height,
                    exposure: m.exposure,
                    colour: m.colour.clone(),
                    reference: report
                        .rows
                        .iter()
                        .find(|r| r.map == m.name)
                        .map(|r| r.reference.clone())
                        .unwrap_or_else(|| "none (no rows)".into()),
                })
                .collect(),
        }
    }

    /// The TOML text.
    pub fn to_toml(&self) -> Result<String> {
        Ok(format!(
            "# How results/{}/table.csv was produced (written by probelab; see src/regression/provenance.rs).\n{}",
            self.experiment,
            toml::to_string(self).context("provenance: cannot serialise")?
        ))
    }

    /// Reads a provenance file; errors name it.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("{}: cannot read", path.display()))?;
        toml::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {}", path.display(), e.to_string().trim_end()))
    }

    /// The record of map `name`, if any.
    pub fn map(&self, name: &str) -> Option<&MapRecord> {
        self.maps.iter().find(|m| m.name == name)
    }
}

/// The files of the repository, besides the experiment's own file, that can change a table's
/// numbers: the code, the locked dependencies, the build script and the tolerances.
pub const NUMBER_INPUTS: [&str; 5] = ["src", "Cargo.lock", "Cargo.toml", "build.rs", "tolerances.toml"];

/// `git rev-parse HEAD` in `root`, and whether a file that can change the numbers differs from
/// it: anything under `src/` (untracked files included), [`NUMBER_INPUTS`], or `experiment`
/// when it lies in the repository. A change elsewhere (README.md, docs, results) leaves the
/// record clean. ("unknown", None) when git or the repository is not there. Never fails, and
/// never takes git's index lock (`--no-optional-locks`), so it cannot disturb a concurrent git.
pub fn git_state(root: &Path, experiment: Option<&Path>) -> (String, Option<bool>) {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("--no-optional-locks")
            .arg("-C")
            .arg(root)
            .args(args)
            .stderr(std::process::Stdio::null())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "HEAD"]) {
        Some(c) if c.len() >= 7 && c.chars().all(|x| x.is_ascii_hexdigit()) => {
            // Pathspecs are relative to `root`; an experiment outside it is not the repository's.
            let exp = experiment.and_then(|p| {
                let (p, r) = (std::fs::canonicalize(p).ok()?, std::fs::canonicalize(root).ok()?);
                Some(p.strip_prefix(r).ok()?.to_str()?.to_string())
            });
            let mut args = vec!["status", "--porcelain", "--untracked-files=all", "--"];
            args.extend(NUMBER_INPUTS);
            args.extend(exp.as_deref());
            let dirty = git(&args).map(|s| !s.is_empty());
            (c, dirty)
        }
        _ => ("unknown".into(), None),
    }
}

/// The current UTC time as `YYYY-MM-DDThh:mm:ssZ`.
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    utc_from_unix(secs as i64)
}

/// Seconds since 1970-01-01T00:00:00Z as ISO 8601 UTC (proleptic Gregorian calendar; the
/// days-to-civil conversion of H. Hinnant, "chrono-Compatible Low-Level Date Algorithms").
pub fn utc_from_unix(secs: i64) -> String {
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dates checked against `date -u -d @SECS`: the epoch, a leap day, the end of a century
    /// that is not a leap year, and a date before 1970.
    #[test]
    fn utc_dates() {
        assert_eq!(utc_from_unix(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_from_unix(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_from_unix(4_107_542_399), "2100-02-28T23:59:59Z");
        assert_eq!(utc_from_unix(4_107_542_400), "2100-03-01T00:00:00Z");
        assert_eq!(utc_from_unix(1_700_000_000), "2023-11-14T22:13:20Z");
        assert_eq!(utc_from_unix(-1), "1969-12-31T23:59:59Z");
    }

    #[test]
    fn git_state_outside_a_repository_is_unknown() {
        let d = tempfile::tempdir().unwrap();
        assert_eq!(git_state(d.path(), None), ("unknown".to_string(), None));
    }

    #[test]
    fn round_trips_through_toml() {
        let p = Provenance {
            experiment: "x".into(),
            probelab_version: "0.1.0".into(),
            git_commit: "unknown".into(),
            git_dirty: None,
            date: utc_from_unix(0),
            table_sha256: sha256_hex(b""),
            settings: Settings {
                file: Some("experiments/x.toml".into()),
                domain: "sphere".into(),
                orientations: vec![],
                metrics: vec!["exact".into()],
                resolution: [256, 128],
                polar_nodes: 2,
                ci: true,
                encoders: vec![EncoderRecord { name: "sh1".into(), kind: "sh1".into(), iterative: false }],
                experiment_toml: "maps = [\"a\"]\n# \"\"\" quotes '''\nencoders = [\"sh1\"]\n".into(),
            },
            maps: vec![MapRecord {
                name: "a".into(),
                file: "a.exr".into(),
                sha256: sha256_hex(b"a"),
                pixel_sha256: Some(sha256_hex(b"pixels")),
                width: 4,
                height: 2,
                exposure: 1.0,
                colour: String::new(),
                reference: "exact".into(),
            }],
        };
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join(FILE_NAME);
        std::fs::write(&f, p.to_toml().unwrap()).unwrap();
        assert_eq!(Provenance::read(&f).unwrap(), p);
        // The sha256 of the empty string (FIPS 180-2 test vector).
        assert_eq!(p.table_sha256, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
        // An exposure of 1 is not written, so every committed provenance.toml reads as before;
        // another is written, read back and shown beside the size.
        let text = p.to_toml().unwrap();
        assert!(!text.contains("exposure"), "{text}");
        let mut q = p.clone();
        q.maps[0].exposure = 4.0;
        std::fs::write(&f, q.to_toml().unwrap()).unwrap();
        assert_eq!(Provenance::read(&f).unwrap().maps[0].exposure, 4.0);
        assert_eq!(size_and_exposure(4, 2, 1.0, ""), "4x2");
        assert_eq!(size_and_exposure(4, 2, 4.0, ""), "4x2, EXPOSURE=4 (the file's pixel values divided by it)");
        assert_eq!(size_and_exposure(4, 2, 1.0, "COLORCORR=2 1 1"), "4x2, COLORCORR=2 1 1");
        assert!(!text.contains("colour"), "{text}");
        q.maps[0].colour = "COLORCORR=2 1 1".into();
        std::fs::write(&f, q.to_toml().unwrap()).unwrap();
        assert_eq!(Provenance::read(&f).unwrap().maps[0].colour, "COLORCORR=2 1 1");
    }
}
