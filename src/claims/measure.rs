//! A claims measurement's output: a small table of rows that a table row of an experiment
//! cannot hold yet (the curve fit, Fig. 2 in closed form, the blending study, the chroma
//! metric, quantised byte sizes). Written to `results/claims/measures/<name>.csv` and judged
//! by the same engine as every experiment table ([`crate::claims::judge`]). Key columns use
//! the engine's names (`map`, `encoder`, `case`, `metric`, …); numbers are written in their
//! shortest round-trip form, so the files compare exactly.

use crate::pipeline::table::num;
use anyhow::{bail, Result};
use std::path::Path;

/// One cell: text or a number.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// A text cell (a key such as `case` or `encoder`, a label, units), written as is.
    Text(String),
    /// A number, written in its shortest round-trip form; it must be finite.
    Num(f64),
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.to_string())
    }
}
impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}
impl From<&String> for Cell {
    fn from(s: &String) -> Self {
        Cell::Text(s.clone())
    }
}
impl From<f64> for Cell {
    fn from(x: f64) -> Self {
        Cell::Num(x)
    }
}
impl From<usize> for Cell {
    fn from(x: usize) -> Self {
        Cell::Num(x as f64)
    }
}

/// A measurement table.
#[derive(Clone, Debug, PartialEq)]
pub struct Measure {
    /// The table's name: its file is `claims/measures/<name>.csv`; claims cite it as `measure:<name>`.
    pub name: String,
    /// What the table is: reference, domain, weighting, resolution, units (first line of
    /// the page that lists it).
    pub about: String,
    /// The column names, in order (the CSV header).
    pub columns: Vec<String>,
    /// The rows, each with one cell per column.
    pub rows: Vec<Vec<Cell>>,
}

impl Measure {
    /// An empty table named `name` with these columns; `about` as [`Measure::about`].
    pub fn new(name: &str, about: &str, columns: &[&str]) -> Self {
        Measure {
            name: name.into(),
            about: about.into(),
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; it must have one cell per column.
    pub fn row(&mut self, cells: Vec<Cell>) {
        assert_eq!(cells.len(), self.columns.len(), "measure {}: a row of {} cells", self.name, cells.len());
        self.rows.push(cells);
    }

    /// The CSV text. A non-finite number is an error, never a cell.
    pub fn to_csv(&self) -> Result<Vec<u8>> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(&self.columns)?;
        for r in &self.rows {
            let mut rec = Vec::with_capacity(r.len());
            for (c, col) in r.iter().zip(&self.columns) {
                rec.push(match c {
                    Cell::Text(s) => s.clone(),
                    Cell::Num(x) if x.is_finite() => num(*x),
                    Cell::Num(x) => bail!("measure {}: column {col} is {x}", self.name),
                });
            }
            w.write_record(&rec)?;
        }
        w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
    }

    /// The file, relative to the results folder.
    pub fn rel_path(&self) -> String {
        format!("claims/measures/{}.csv", self.name)
    }
}

/// Writes every measurement under `results` (atomically) and `claims/measures/README.md`
/// listing what each is; returns the files written, relative to `results`.
pub fn write_all(results: &Path, measures: &[Measure]) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut readme = String::from(
        "# Claims measurements\n\nWritten by `probelab claims`; do not edit. Each table holds what an experiment \
         table row cannot (yet); `experiments/claims/*.toml` judges them like any table. Units E/π unless a \
         column says otherwise.\n\n",
    );
    for m in measures {
        crate::io::atomic::write(&results.join(m.rel_path()), &m.to_csv()?)?;
        readme += &format!("- `{}.csv`: {}\n", m.name, m.about);
        out.push(m.rel_path());
    }
    crate::io::atomic::write(&results.join("claims/measures/README.md"), readme.as_bytes())?;
    out.push("claims/measures/README.md".into());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_refuse_non_finite() {
        let mut m = Measure::new("t", "test", &["case", "x"]);
        m.row(vec!["a".into(), 0.1.into()]);
        m.row(vec!["b,c".into(), 1e-300.into()]);
        assert_eq!(String::from_utf8(m.to_csv().unwrap()).unwrap(), "case,x\na,0.1\n\"b,c\",1e-300\n");
        m.row(vec!["d".into(), f64::NAN.into()]);
        assert!(m.to_csv().unwrap_err().to_string().contains("column x is NaN"));
    }
}
