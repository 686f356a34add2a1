//! The maps a `check` or `reproduce` could not find on this machine, each said once.
//!
//! A fresh clone has only the CC0 maps of `envmaps/`; the paper probes (not CC0) come from
//! elsewhere (docs/maps.md). Every experiment that reads them would otherwise say so for each
//! of its maps, with the whole not-found message each time. Instead the commands collect the
//! missing maps here, as they go, and print: each missing map once (how many experiments read
//! it, and any file passed over for it), then the one fix (the folders searched and
//! `PROBELAB_ENVMAPS`); and one closing line of what could not be checked.

use crate::envmap::search::{self, SearchPath};
use crate::regression::baseline::Table;
use std::path::Path;

/// One map not found: the experiments that name it and why it was not found.
struct Missing {
    name: String,
    why: String,
    experiments: usize,
}

/// The missing maps of a whole command, and what went unchecked for want of them.
#[derive(Default)]
pub struct MissingMaps {
    maps: Vec<Missing>,
    /// Experiments none of whose maps was found.
    skipped: usize,
    /// Experiments run on some of their maps.
    partial: usize,
    /// Baseline rows of missing maps, not compared.
    rows: usize,
}

impl MissingMaps {
    /// Records an experiment naming `maps` maps, of which `missing` were not found (`why`, same
    /// order: `RunReport::missing_why`), leaving `rows` baseline rows unchecked.
    pub fn add(&mut self, maps: usize, missing: &[String], why: &[String], rows: usize) {
        if missing.is_empty() {
            return;
        }
        if missing.len() >= maps {
            self.skipped += 1;
        } else {
            self.partial += 1;
        }
        self.rows += rows;
        for (k, name) in missing.iter().enumerate() {
            match self.maps.iter_mut().find(|m| m.name == *name) {
                Some(m) => m.experiments += 1,
                None => self.maps.push(Missing {
                    name: name.clone(),
                    why: why.get(k).cloned().unwrap_or_default(),
                    experiments: 1,
                }),
            }
        }
    }

    /// Whether every map was found.
    pub fn is_empty(&self) -> bool {
        self.maps.is_empty()
    }

    /// The missing maps' names, in the order first met.
    pub fn names(&self) -> Vec<&str> {
        self.maps.iter().map(|m| m.name.as_str()).collect()
    }

    /// Experiments none of whose maps was found.
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// Baseline rows of the missing maps, not compared.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// What the command prints to stderr: each missing map once, with how many experiments read
    /// it and the files passed over for it (a known map missing outright needs no more), then
    /// the one fix. Empty when nothing is missing.
    pub fn notes(&self, search: &SearchPath) -> String {
        if self.maps.is_empty() {
            return String::new();
        }
        let mut s = format!("{} map(s) not on the map search path:\n", self.maps.len());
        for m in &self.maps {
            let detail = match (crate::envmap::known::by_name(&m.name), search::passed_over_in(&m.why)) {
                (_, Some(p)) => format!(": {p}"),
                (Some(_), None) => String::new(),
                // Not on the search path goes without saying: only a suggestion is left.
                (None, None) => match m.why.strip_prefix(search::NO_FILE) {
                    Some(rest) => rest.to_string(),
                    None => format!(": {}", m.why),
                },
            };
            s += &format!("  {} (read by {} experiment(s)){detail}\n", m.name, m.experiments);
        }
        s += &format!(
            "Searched: {}. To check them too, set {}=<folder holding them> (colon-separated folders); \
             `probelab maps` lists the known maps missing and where to get them (docs/maps.md).\n",
            search.describe(),
            search::ENV_VAR
        );
        s
    }

    /// The one closing line of what could not be checked, `what` naming the work ("checked",
    /// "reproduced"); `None` when nothing is missing.
    pub fn line(&self, what: &str) -> Option<String> {
        (!self.maps.is_empty()).then(|| {
            format!(
                "not {what} here: {} map(s) missing ({}): {} experiment(s) skipped, {} run on part of their maps, \
                 {} baseline row(s) not compared (`--require-all-maps` makes this an error)",
                self.maps.len(),
                self.names().join(", "),
                self.skipped,
                self.partial,
                self.rows
            )
        })
    }
}

/// The rows of the baseline `<dir>/table.csv` whose map is one of `maps` (0 when there is no
/// baseline): what an experiment skipped for want of maps leaves unchecked.
pub fn baseline_rows(dir: &Path, maps: &[String]) -> anyhow::Result<usize> {
    let path = dir.join(crate::regression::baseline::TABLE);
    if !path.is_file() {
        return Ok(0);
    }
    Ok(rows_of(&Table::read(&path)?, maps))
}

/// The rows of `table` whose map is one of `maps` (by name, or by the file stem a path entry
/// gets in tables).
pub fn rows_of(table: &Table, maps: &[String]) -> usize {
    let names: Vec<String> = maps
        .iter()
        .flat_map(|m| {
            let stem = Path::new(m).file_stem().map(|s| s.to_string_lossy().into_owned());
            std::iter::once(m.clone()).chain(stem)
        })
        .collect();
    table.keys().iter().filter(|k| names.contains(&k.map)).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_missing_map_is_counted_once_across_experiments() {
        let mut m = MissingMaps::default();
        let why = |n: usize| vec![format!("{} (did you mean 'c'?)", search::NO_FILE); n];
        m.add(3, &["a".into(), "b".into()], &why(2), 10);
        m.add(2, &["a".into(), "b".into()], &why(2), 4);
        m.add(4, &[], &[], 0);
        assert_eq!(m.names(), ["a", "b"]);
        assert_eq!((m.skipped(), m.rows()), (1, 14));
        let line = m.line("checked").unwrap();
        assert!(
            line.starts_with("not checked here: 2 map(s) missing (a, b): 1 experiment(s) skipped, 1 run"),
            "{line}"
        );
        let notes = m.notes(&SearchPath::new(vec![]));
        assert_eq!(notes.matches("  a (read by 2 experiment(s)) (did you mean 'c'?)\n").count(), 1, "{notes}");
        assert_eq!(notes.matches("PROBELAB_ENVMAPS").count(), 1, "{notes}");
        assert!(MissingMaps::default().line("checked").is_none());
    }
}
