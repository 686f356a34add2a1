//! The JSON documents `eval`, `fit` and `check` print with `--format json` (and the Python
//! package parses): each one object that opens with its `schema` (`probelab.eval/1`,
//! `probelab.fit/1`, `probelab.check/1`) and lists the `maps` it read with their identities
//! (name, path, size, file sha256, pixel sha256); numbers are JSON numbers, diagnostics are
//! objects of numbers. Every key, its type and unit: `docs/json.md`, the contract; a change
//! to what a key means is a new schema version.

use crate::envmap::{identity, EnvMap};
use crate::pipeline::runner::MapInfo;
use crate::pipeline::table::{Row, COLUMNS, NUMERIC_COLUMNS};
use anyhow::{Context, Result};
use serde_json::{json, Map as Object, Value};

/// The schema of `eval`'s document.
pub const EVAL: &str = "probelab.eval/1";
/// The schema of `fit`'s document.
pub const FIT: &str = "probelab.fit/1";
/// The schema of `check`'s document.
pub const CHECK: &str = "probelab.check/1";

/// A map a document read, with its identity (`docs/maps.md`).
#[derive(Clone, Debug, PartialEq)]
pub struct MapEntry {
    /// The name or path as given (on the command line, in the experiment, to the Python call).
    pub given: String,
    /// Its name in the rows (the file stem, or the known map's name).
    pub name: String,
    /// The file read, as the search path found it (not made absolute); `None` for texels
    /// handed over in memory.
    pub path: Option<String>,
    /// Width and height in texels.
    pub size: (usize, usize),
    /// The sha256 of the file's bytes; `None` without a file.
    pub sha256: Option<String>,
    /// The pixel sha256 (`envmap::identity`).
    pub pixel_sha256: String,
}

impl MapEntry {
    /// The entry of a map a run read ([`MapInfo`]).
    pub fn from_info(info: &MapInfo) -> MapEntry {
        MapEntry {
            given: info.given.clone(),
            name: info.name.clone(),
            path: info.path.as_ref().map(|p| p.display().to_string()),
            size: (info.width, info.height),
            sha256: Some(info.sha256.clone()).filter(|s| !s.is_empty()),
            pixel_sha256: info.pixel_sha256.clone(),
        }
    }

    /// The entry of a map in memory, asked for as `given`.
    pub fn from_map(given: &str, map: &EnvMap) -> MapEntry {
        MapEntry {
            given: given.to_string(),
            name: map.name.clone(),
            path: map.path.as_ref().map(|p| p.display().to_string()),
            size: (map.width(), map.height()),
            sha256: map.sha256.clone(),
            pixel_sha256: map.pixel_sha256.clone().unwrap_or_else(|| identity::pixel_sha256(map)),
        }
    }

    /// `{ "name", "given", "path", "size": [w, h], "sha256", "pixel_sha256" }`.
    pub fn to_json(&self) -> Value {
        json!({
            "name": self.name,
            "given": self.given,
            "path": self.path,
            "size": [self.size.0, self.size.1],
            "sha256": self.sha256,
            "pixel_sha256": self.pixel_sha256,
        })
    }
}

/// The `maps` list: each map once (by name and file sha256), in the order first read.
pub fn maps(entries: &[MapEntry]) -> Value {
    let mut seen = Vec::new();
    let mut out = Vec::new();
    for e in entries {
        let key = (&e.name, &e.sha256, &e.pixel_sha256);
        if !seen.contains(&key) {
            seen.push(key);
            out.push(e.to_json());
        }
    }
    Value::Array(out)
}

/// One row of a result table as an object keyed by the CSV's [`COLUMNS`]: the
/// [`NUMERIC_COLUMNS`] as numbers (an empty cell is `null`), `diagnostics` as an object of
/// numbers, the other columns as strings. A row with a non-finite number is an error, as for
/// the CSV.
pub fn row(r: &Row) -> Result<Value> {
    r.check_finite()?;
    let mut obj = Object::new();
    for (col, cell) in COLUMNS.iter().zip(r.fields()) {
        let v = if *col == "diagnostics" {
            diagnostics(&cell).with_context(|| format!("column diagnostics of {} {}", r.map, r.encoder))?
        } else if !NUMERIC_COLUMNS.contains(col) {
            Value::String(cell)
        } else if cell.is_empty() {
            Value::Null
        } else if let Ok(k) = cell.parse::<u64>() {
            Value::Number(k.into())
        } else {
            let x: f64 = cell.parse().with_context(|| format!("column {col}: '{cell}' is not a number"))?;
            serde_json::Number::from_f64(x).map(Value::Number).unwrap_or(Value::Null)
        };
        obj.insert(col.to_string(), v);
    }
    Ok(Value::Object(obj))
}

/// The table's `diagnostics` cell (`key=value` pairs joined by `;`) as an object of numbers.
pub fn diagnostics(cell: &str) -> Result<Value> {
    let mut obj = Object::new();
    for pair in cell.split(';').filter(|p| !p.is_empty()) {
        let (k, v) = pair.split_once('=').with_context(|| format!("'{pair}': expected key=value"))?;
        let x: f64 = v.parse().with_context(|| format!("'{pair}': the value is not a number"))?;
        obj.insert(k.to_string(), serde_json::Number::from_f64(x).map(Value::Number).unwrap_or(Value::Null));
    }
    Ok(Value::Object(obj))
}

/// A fit's diagnostics (`Fit::diagnostics`) as an object of numbers (`null` if not finite).
pub fn diagnostics_of(pairs: &[(&str, f64)]) -> Value {
    Value::Object(pairs.iter().map(|(k, v)| (k.to_string(), json!(v))).collect())
}

/// `eval`'s document: `{ "schema", "maps", "rows" }`.
pub fn eval_document(maps_read: &[MapEntry], rows: &[Row]) -> Result<Value> {
    let rows: Vec<Value> = rows.iter().map(row).collect::<Result<_>>()?;
    Ok(json!({ "schema": EVAL, "maps": maps(maps_read), "rows": rows }))
}

/// A document as the text printed: pretty, with a final newline.
pub fn text(doc: &Value) -> Result<String> {
    Ok(serde_json::to_string_pretty(doc)? + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagnostics_become_an_object_of_numbers() {
        let d = diagnostics("iterations=12;residual=1.5e-7").unwrap();
        assert_eq!(d["iterations"].as_f64(), Some(12.0));
        assert_eq!(d["residual"].as_f64(), Some(1.5e-7));
        assert_eq!(diagnostics("").unwrap(), json!({}));
        assert!(diagnostics("k=abc").is_err());
        assert!(diagnostics("novalue").is_err());
    }

    #[test]
    fn a_map_read_twice_is_listed_once() {
        let e = MapEntry {
            given: "m".into(),
            name: "m".into(),
            path: Some("envmaps/m.exr".into()),
            size: (4, 2),
            sha256: Some("ab".into()),
            pixel_sha256: "cd".into(),
        };
        let listed = maps(&[e.clone(), e.clone()]);
        assert_eq!(listed.as_array().unwrap().len(), 1);
        assert_eq!(listed[0]["size"], json!([4, 2]));
        assert_eq!(listed[0]["sha256"], "ab");
    }
}
