//! Reading an experiment file: the text parsed and validated, every error naming the file and
//! the line; the lines where values are written, for errors found after loading.

use super::file::ExperimentFile;
use super::lines::{find_key, find_line, quote_line, string_literal_lines};
use super::model::Experiment;
use super::toml_file::parse_toml;
use anyhow::{Context, Result};
use std::path::Path;

impl Experiment {
    /// Reads and validates an experiment file; errors name the file and the line (see
    /// [`Experiment::parse`]).
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read experiment file", path.display()))?;
        Self::parse(&text, path)
    }

    /// Parses and validates the text of an experiment file read from `path` (which names it in
    /// errors and gives the default name). Every error starts with `path:LINE:` when the line
    /// is known: from TOML's own span for syntax and type errors, otherwise the line where the
    /// offending value or key is written ([`super::find_line`]); the line itself is quoted after the
    /// message. Never panics, whatever the text.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let file: ExperimentFile = parse_toml(text, path)?;
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("experiment").to_string();
        let mut exp = Self::from_file(file, &stem).map_err(|e| match find_line(text, &e) {
            Some(l) => anyhow::anyhow!("{}:{l}: {:#}{}", path.display(), e, quote_line(text, l)),
            None => anyhow::anyhow!("{}: {:#}", path.display(), e),
        })?;
        exp.source = Some(path.to_path_buf());
        Ok(exp)
    }

    /// The lines of the experiment's source file where each of `values` is written as a string
    /// (e.g. map names), for errors found after loading, such as maps that are not on the
    /// search path. The file is read once and indexed, so this is linear in its size and the
    /// number of values (300,000 missing maps once took minutes: a read and a scan per map).
    pub fn source_lines(&self, values: &[String]) -> Vec<Option<usize>> {
        let Some(text) = self.source.as_ref().and_then(|p| std::fs::read_to_string(p).ok()) else {
            return vec![None; values.len()];
        };
        let literals = string_literal_lines(&text);
        values.iter().map(|v| literals.get(v.as_str()).copied().or_else(|| find_key(&text, v))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_reports_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.toml");
        std::fs::write(&p, "maps = ['a']\nencoders = ['sh1',\n  'nope']\n").unwrap();
        let msg = format!("{:#}", Experiment::load(&p).err().unwrap());
        assert!(msg.contains("x.toml:3: ") && msg.contains("nope") && msg.contains("3 |   'nope']"), "{msg}");
        std::fs::write(&p, "maps = ['a'\nencoders = 3\n").unwrap();
        let msg = format!("{:#}", Experiment::load(&p).err().unwrap());
        assert!(msg.contains("x.toml:2:"), "{msg}");
    }

    /// Each validation error points at the line that causes it (not at an earlier line that
    /// merely contains the same word).
    #[test]
    fn errors_point_at_the_offending_line() {
        let line = |text: &str| {
            let e = Experiment::parse(text, Path::new("e.toml")).err().expect("must fail");
            let msg = format!("{e:#}");
            let l = msg.strip_prefix("e.toml:").and_then(|r| r.split(':').next()).and_then(|n| n.parse().ok());
            (l.unwrap_or(0usize), msg)
        };
        let cases: &[(&str, usize)] = &[
            // The description mentions sh: the literal 'sh' on line 3 is the culprit.
            ("description = 'sh and sh1'\nmaps = ['a']\nencoders = ['sh1', 'sh']\n", 3),
            ("maps = ['a']\nencoders = ['sh1']\neffects = ['hemisphere',\n 'fog']\norientations = ['up']\n", 4),
            ("maps = ['a']\nencoders = ['sh1']\norientations = ['up']\neffects = [{ kind = 'cone', cos_alpha = 0.5, bogus = 1 }]\n", 4),
            ("maps = ['a']\nencoders = [\n  { kind = 'sh1', bogus = 2 },\n]\n", 3),
            ("maps = ['a']\nencoders = [{ kind = 'zz9' }]\n", 2),
            ("maps = []\nencoders = ['sh1']\n", 1),
            ("maps = ['a']\nencoders = ['sh1']\nmetrics = ['exact', 'l2']\n", 3),
            ("maps = ['a']\n\nencoders = ['sh1']\nwhat = 1\n", 4),
            ("maps = ['a']\nencoders = ['sh1'\n", 2),
            ("maps = ['a']\nencoders = ['sh1']\nresolution = [100, 10]\n", 3),
            // An encoder defined only about a surface normal, on the sphere.
            ("maps = ['a']\nencoders = ['sh1',\n  'hbasis4']\n", 3),
        ];
        for (text, want) in cases {
            let (got, msg) = line(text);
            assert_eq!(got, *want, "{msg}");
        }
    }
}
