//! Result rows and their CSV form. Every row states its reference, domain, weighting,
//! resolution and units. The first nine columns are fixed; later columns are added
//! after them.

use crate::reference::metrics::Scores;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// The CSV header.
pub const COLUMNS: &[&str] = &[
    "map",
    "encoder",
    "domain",
    "metric",
    "rmse_r",
    "rmse_g",
    "rmse_b",
    "rmse",
    "rel_rmse",
    "neg_frac",
    "max_abs_err",
    "stored_scalars",
    "orientation_set",
    "effects",
    "weighting",
    "resolution",
    "units",
    "reference",
    "diagnostics",
    "at_normal_abs_err",
    "fit_ns",
    "eval_ns",
];

/// Columns that are wall-clock measurements (`timing.rs`): they vary from run to run, so
/// comparisons of tables ignore them by name. Empty when timing is off (`--no-timing`).
pub const TIMING_COLUMNS: &[&str] = &["fit_ns", "eval_ns"];

/// One scored (map, encoder, domain, metric).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The map's name.
    pub map: String,
    /// The encoder's name in the experiment.
    pub encoder: String,
    /// Domain label: `sphere`, `hemisphere:<orientation>` or `sphere@<orientation>`.
    pub domain: String,
    /// The metric's name (`exact` or `probulator`).
    pub metric: String,
    /// The error scores.
    pub scores: Scores,
    /// Scalars the encoder stores per probe or texel.
    pub stored_scalars: usize,
    /// The orientation set N came from ("-" without one).
    pub orientation_set: String,
    /// The effects applied ("none" without any).
    pub effects: String,
    /// How normals are weighted ("solid-angle" or "per-pixel").
    pub weighting: String,
    /// Output grid the scores were estimated on ("WxH").
    pub resolution: String,
    /// Units of the scores ("E/pi").
    pub units: String,
    /// Description of the reference the scores are against.
    pub reference: String,
    /// The fit's diagnostics as `key=value` pairs joined by ";".
    pub diagnostics: String,
    /// |E_encoder(N) − E_exact(N)|, the largest channel, at the surface normal N (the IrradZ
    /// point); `None` without a surface normal.
    pub at_normal_abs_err: Option<f64>,
    /// Median ns to fit one probe/texel (timing pass; None when timing is off).
    pub fit_ns: Option<f64>,
    /// Median ns per evaluated normal (timing pass; None when timing is off).
    pub eval_ns: Option<f64>,
}

/// Shortest round-trip form of an f64 (so baselines compare exactly); never NaN/Inf in output.
pub fn num(v: f64) -> String {
    if v == 0.0 || (v.is_finite() && (1e-4..1e6).contains(&v.abs())) {
        format!("{v}")
    } else if v.is_finite() {
        format!("{v:e}")
    } else {
        // A non-finite score is a bug upstream; make it loud in the table rather than silent.
        "nonfinite".to_string()
    }
}

impl Row {
    /// Fails, naming the row and the column, if any number of the row is NaN or infinite, or
    /// is one a table may not hold (`pipeline::table_cells`, the bound every table read back
    /// is held to): such a table is never printed nor kept as a baseline.
    pub fn check_finite(&self) -> Result<()> {
        let s = &self.scores;
        let cells = [
            ("rmse_r", Some(s.rmse_rgb[0])),
            ("rmse_g", Some(s.rmse_rgb[1])),
            ("rmse_b", Some(s.rmse_rgb[2])),
            ("rmse", Some(s.rmse)),
            ("rel_rmse", Some(s.rel_rmse)),
            ("neg_frac", Some(s.neg_frac)),
            ("max_abs_err", Some(s.max_abs)),
            ("at_normal_abs_err", self.at_normal_abs_err),
            ("fit_ns", self.fit_ns),
            ("eval_ns", self.eval_ns),
        ];
        let fault = |(col, v): &(&str, Option<f64>)| -> Option<String> {
            let v = (*v)?;
            if !v.is_finite() {
                return Some(format!("{col} is {v}, not a finite number"));
            }
            crate::pipeline::table_cells::fault(col, &num(v)).map(|why| format!("{col}: {why}"))
        };
        if let Some(why) = cells.iter().find_map(fault) {
            let case = [&self.orientation_set, &self.effects]
                .iter()
                .filter(|t| !t.is_empty())
                .map(|t| t.as_str())
                .collect::<Vec<_>>()
                .join(", ");
            bail!(
                "map '{}', encoder '{}'{}: {why}; no table is written (a setting or the map is out of range)",
                self.map,
                self.encoder,
                if case.is_empty() { String::new() } else { format!(" ({case})") }
            );
        }
        Ok(())
    }

    /// The row's CSV fields, in [`COLUMNS`] order.
    pub fn fields(&self) -> Vec<String> {
        let s = &self.scores;
        vec![
            self.map.clone(),
            self.encoder.clone(),
            self.domain.clone(),
            self.metric.clone(),
            num(s.rmse_rgb[0]),
            num(s.rmse_rgb[1]),
            num(s.rmse_rgb[2]),
            num(s.rmse),
            num(s.rel_rmse),
            num(s.neg_frac),
            num(s.max_abs),
            self.stored_scalars.to_string(),
            self.orientation_set.clone(),
            self.effects.clone(),
            self.weighting.clone(),
            self.resolution.clone(),
            self.units.clone(),
            self.reference.clone(),
            self.diagnostics.clone(),
            self.at_normal_abs_err.map(num).unwrap_or_default(),
            self.fit_ns.map(|v| format!("{v:.1}")).unwrap_or_default(),
            self.eval_ns.map(|v| format!("{v:.2}")).unwrap_or_default(),
        ]
    }
}

/// The rows as CSV text with the header. A row with a non-finite number is an error naming
/// its map, encoder, case and column: such a table is never printed nor kept as a baseline.
pub fn to_csv(rows: &[Row]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS)?;
    for r in rows {
        r.check_finite()?;
        w.write_record(r.fields())?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// The columns whose cells are numbers (JSON numbers in `eval`'s document, `ops::json`; an
/// empty cell is `null`).
pub const NUMERIC_COLUMNS: &[&str] = &[
    "rmse_r",
    "rmse_g",
    "rmse_b",
    "rmse",
    "rel_rmse",
    "neg_frac",
    "max_abs_err",
    "stored_scalars",
    "at_normal_abs_err",
    "fit_ns",
    "eval_ns",
];

/// Writes the rows to `path` atomically.
#[cfg(test)]
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    crate::io::atomic::write(path, &to_csv(rows)?)
}

/// A CSV table as text: the header and the records. Baselines compare tables in this form
/// (`regression::baseline`) and the claims engine judges them in it (`claims::judge`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CsvText {
    /// The header's column names.
    pub columns: Vec<String>,
    /// The records, each a list of field texts.
    pub rows: Vec<Vec<String>>,
}

impl CsvText {
    /// Parses CSV with a header; `origin` names the source in errors. An empty header, a
    /// column named twice or a bad number (`pipeline::table_cells`) is an error.
    pub fn parse(bytes: &[u8], origin: &Path) -> Result<CsvText> {
        let mut r = csv::ReaderBuilder::new().has_headers(true).from_reader(bytes);
        let columns: Vec<String> = r
            .headers()
            .with_context(|| format!("{}: cannot read the CSV header", origin.display()))?
            .iter()
            .map(String::from)
            .collect();
        if columns.is_empty() || columns.iter().all(|c| c.is_empty()) {
            bail!("{}: empty table (no header)", origin.display());
        }
        for (i, c) in columns.iter().enumerate() {
            if columns[..i].contains(c) {
                bail!("{}: column '{c}' appears twice in the header", origin.display());
            }
        }
        let mut rows = Vec::new();
        for rec in r.records() {
            let rec = rec.with_context(|| format!("{}: malformed CSV", origin.display()))?;
            let line = rec.position().map_or(0, |p| p.line());
            crate::pipeline::table_cells::check_record(origin, line, &columns, rec.iter())?;
            rows.push(rec.iter().map(String::from).collect());
        }
        Ok(CsvText { columns, rows })
    }

    /// The index of a column.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }
}
