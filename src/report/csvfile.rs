//! A CSV file read by column name. The report reads every result file through this, so a
//! column added later (`fit_ns`, `eval_ns`, …) is found by its name wherever it
//! sits, and a file that lacks a column is skipped or refused with the file and column named.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// A CSV file with a header row, held as strings.
#[derive(Clone, Debug)]
pub struct CsvTable {
    /// Where the table was read from; it names the file in errors.
    pub path: PathBuf,
    /// The column names of the header row, trimmed.
    pub headers: Vec<String>,
    /// The records, each with one field per header, untrimmed.
    pub rows: Vec<Vec<String>>,
}

impl CsvTable {
    /// Reads `path`; every record must have as many fields as the header.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
        Self::parse(path, &bytes)
    }

    /// Parses CSV bytes; `path` only names the source in errors. Every numeric cell is
    /// checked (`pipeline::table_cells`): a bad one is refused as `FILE:LINE:COLUMN`.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Self> {
        let mut r = csv::ReaderBuilder::new().has_headers(true).from_reader(bytes);
        let headers: Vec<String> = r
            .headers()
            .with_context(|| format!("{}: cannot read the CSV header", path.display()))?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        if headers.is_empty() || headers.iter().all(|h| h.is_empty()) {
            bail!("{}: no CSV header", path.display());
        }
        let mut rows = Vec::new();
        for (i, rec) in r.records().enumerate() {
            let rec = rec.with_context(|| format!("{}: CSV record {}", path.display(), i + 2))?;
            let line = rec.position().map_or(i as u64 + 2, |p| p.line());
            crate::pipeline::table_cells::check_record(path, line, &headers, rec.iter())?;
            rows.push(rec.iter().map(|s| s.to_string()).collect());
        }
        Ok(CsvTable { path: path.to_path_buf(), headers, rows })
    }

    /// The index of a column, if present.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// The indices of columns that must be present; the error names the file, the missing
    /// columns and the expected set.
    pub fn require(&self, names: &[&str]) -> Result<Vec<usize>> {
        let missing: Vec<&str> = names.iter().copied().filter(|n| self.col(n).is_none()).collect();
        if !missing.is_empty() {
            bail!(
                "{}: missing column(s) {} (expected columns: {}; found: {})",
                self.path.display(),
                missing.join(", "),
                names.join(","),
                self.headers.join(",")
            );
        }
        // Cannot fail: a missing name returned the error above.
        Ok(names.iter().map(|n| self.col(n).expect("checked above")).collect())
    }

    /// The number in row `row`, column `col`: `None` when the cell is empty; an error naming
    /// the file, line and column when it is not a finite number.
    pub fn num(&self, row: usize, col: usize) -> Result<Option<f64>> {
        let s = self.rows[row][col].trim();
        if s.is_empty() {
            return Ok(None);
        }
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => bail!(
                "{}: line {}, column '{}': '{}' is not a finite number",
                self.path.display(),
                row + 2,
                crate::math::echo::value(&self.headers[col]),
                crate::math::echo::value(s)
            ),
        }
    }

    /// Whether every row holds the same value in column `col`.
    pub fn is_constant(&self, col: usize) -> bool {
        self.rows.windows(2).all(|w| w[0][col] == w[1][col])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_by_name_and_clear_errors() {
        let t = CsvTable::parse(Path::new("x.csv"), b"a,b,fit_ns\n1,hello,\n2,x,3.5\n").unwrap();
        assert_eq!(t.col("fit_ns"), Some(2));
        assert_eq!(t.num(0, 2).unwrap(), None);
        assert_eq!(t.num(1, 2).unwrap(), Some(3.5));
        let e = t.num(0, 1).unwrap_err().to_string();
        assert!(e.contains("x.csv") && e.contains("line 2") && e.contains("'b'"), "{e}");
        let e = t.require(&["a", "rmse"]).unwrap_err().to_string();
        assert!(e.contains("x.csv") && e.contains("missing column(s) rmse"), "{e}");
        assert!(!t.is_constant(0));
        let e = CsvTable::parse(Path::new("y.csv"), b"a,b\n1,2,3\n").unwrap_err();
        assert!(format!("{e:#}").contains("y.csv"), "{e:#}");
    }

    #[test]
    fn nan_is_refused() {
        for (bytes, at) in
            [(&b"a,v\nx,1\nx,NaN\n"[..], "x.csv:3:2:"), (b"v\ninf\n", "x.csv:2:1:"), (b"v\n1e300\n", "x.csv:2:1:")]
        {
            let e = format!("{:#}", CsvTable::parse(Path::new("x.csv"), bytes).unwrap_err());
            assert!(e.starts_with(at), "{e}");
        }
    }
}
