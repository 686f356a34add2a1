//! Tolerances for comparing a fresh table with its baseline (`probelab check`, `bless`, and
//! the overwrite guard of `run`/`reproduce`), read from `tolerances.toml` at the repository
//! root. Tolerances are data: a list of rules, each scoped by column, encoder kind and encoder
//! class, applied in file order; a later matching rule overrides the fields it sets.
//!
//! | key        | type     | default      | meaning |
//! |------------|----------|--------------|---------|
//! | `columns`  | list of strings | every column | column names; one `*` matches any run of characters (`"*_ns"`, `"diagnostics.*"`) |
//! | `encoders` | list of strings | every kind   | encoder kinds (registry ids, not table names) |
//! | `class`    | string   | either       | `"iterative"` or `"closed-form"` ([`crate::encoders::encoder::Encoder::is_iterative`]) |
//! | `rel`      | float    | (unchanged)  | relative tolerance |
//! | `abs`      | float    | (unchanged)  | absolute tolerance, in the column's units |
//! | `ignore`   | bool     | (unchanged)  | the column's values are not compared at all |
//! | `why`      | string   | —            | the reason, for readers |
//!
//! Before any rule applies a value must match exactly (rel = abs = 0). A number passes when
//! |new − old| ≤ max(abs, rel·|old|). Columns of the `diagnostics` cell are compared one key at
//! a time as `diagnostics.<key>`.

use crate::encoders::REGISTRY;
use anyhow::{bail, Context, Result};
use serde::Deserialize;
use std::path::Path;

/// The file name, at the repository root.
pub const FILE_NAME: &str = "tolerances.toml";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TolerancesFile {
    #[serde(default)]
    rule: Vec<Rule>,
}

/// One rule of `tolerances.toml`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rule {
    /// Column names the rule applies to (one `*` matches any run of characters); empty: every
    /// column.
    #[serde(default)]
    pub columns: Vec<String>,
    /// Encoder kinds (registry ids) the rule applies to; empty: every kind.
    #[serde(default)]
    pub encoders: Vec<String>,
    /// `iterative` or `closed-form`; None: either.
    pub class: Option<String>,
    /// Relative tolerance to set; None leaves it unchanged.
    pub rel: Option<f64>,
    /// Absolute tolerance to set, in the column's units; None leaves it unchanged.
    pub abs: Option<f64>,
    /// Whether the column is not compared at all; None leaves it unchanged.
    pub ignore: Option<bool>,
    /// Why the rule exists, for readers.
    #[allow(dead_code, reason = "accepted in tolerances.toml for readers; the comparison never reads it")]
    pub why: Option<String>,
}

/// How one value is compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// Not compared (timings).
    Ignore,
    /// |new − old| ≤ max(abs, rel·|old|).
    Within {
        /// Relative tolerance, a fraction of |old|.
        rel: f64,
        /// Absolute tolerance, in the column's units.
        abs: f64,
    },
}

impl Tolerance {
    /// Exact equality.
    pub const EXACT: Tolerance = Tolerance::Within { rel: 0.0, abs: 0.0 };

    /// Whether `new` is close enough to `old`. Non-finite values pass only if identical.
    pub fn accepts(&self, old: f64, new: f64) -> bool {
        match *self {
            Tolerance::Ignore => true,
            Tolerance::Within { rel, abs } => {
                if old == new {
                    return true;
                }
                let d = (new - old).abs();
                d.is_finite() && d <= abs.max(rel * old.abs())
            }
        }
    }
}

impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Tolerance::Ignore => write!(f, "ignored"),
            Tolerance::Within { rel, abs } => write!(f, "rel {rel:e}, abs {abs:e}"),
        }
    }
}

/// What a value belongs to: the encoder kind and whether it is iterative (None for columns
/// that belong to no encoder).
#[derive(Clone, Copy, Debug)]
pub struct EncoderClass<'a> {
    /// The encoder kind (registry id).
    pub kind: &'a str,
    /// Whether the encoder's fit is iterative.
    pub iterative: bool,
}

/// The parsed rules.
#[derive(Clone, Debug, Default)]
pub struct Tolerances {
    rules: Vec<Rule>,
}

impl Tolerances {
    /// Reads `<root>/tolerances.toml`.
    pub fn load(root: &Path) -> Result<Self> {
        let path = root.join(FILE_NAME);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "{}: cannot read the tolerances file (it belongs at the repository root: {})",
                path.display(),
                crate::pipeline::experiment::NOT_A_CHECKOUT
            )
        })?;
        Self::parse(&text).map_err(|e| anyhow::anyhow!("{}: {e:#}", path.display()))
    }

    /// Parses and validates the rules.
    pub fn parse(text: &str) -> Result<Self> {
        let f: TolerancesFile = toml::from_str(text).map_err(|e| anyhow::anyhow!("{}", e.to_string().trim_end()))?;
        for (i, r) in f.rule.iter().enumerate() {
            let at = format!("rule {} ([[rule]] number {})", i + 1, i + 1);
            for (k, v) in [("rel", r.rel), ("abs", r.abs)] {
                if let Some(v) = v {
                    if !v.is_finite() || v < 0.0 {
                        bail!("{at}: {k} = {v}: expected a finite number >= 0");
                    }
                }
            }
            if r.rel.is_none() && r.abs.is_none() && r.ignore.is_none() {
                bail!("{at}: sets none of rel, abs, ignore");
            }
            if let Some(c) = &r.class {
                if c != "iterative" && c != "closed-form" {
                    bail!("{at}: class '{c}': expected \"iterative\" or \"closed-form\"");
                }
            }
            for e in &r.encoders {
                if !REGISTRY.iter().any(|k| k.id == e) {
                    bail!("{at}: unknown encoder kind '{e}' (valid: {})", crate::encoders::known_ids());
                }
            }
            for c in &r.columns {
                if c.is_empty() || c.matches('*').count() > 1 {
                    bail!("{at}: column pattern '{c}': expected a name with at most one '*'");
                }
            }
        }
        Ok(Tolerances { rules: f.rule })
    }

    /// The tolerance for a value in `column` of a row of `encoder` (None: the row's encoder is
    /// unknown, and only rules without an encoder scope apply).
    pub fn get(&self, column: &str, encoder: Option<EncoderClass>) -> Tolerance {
        let (mut rel, mut abs, mut ignore) = (0.0, 0.0, false);
        for r in &self.rules {
            if !r.columns.is_empty() && !r.columns.iter().any(|p| glob(p, column)) {
                continue;
            }
            if !r.encoders.is_empty() && !encoder.is_some_and(|e| r.encoders.iter().any(|k| k == e.kind)) {
                continue;
            }
            if let Some(c) = &r.class {
                match encoder {
                    Some(e) if e.iterative == (c == "iterative") => {}
                    _ => continue,
                }
            }
            rel = r.rel.unwrap_or(rel);
            abs = r.abs.unwrap_or(abs);
            ignore = r.ignore.unwrap_or(ignore);
        }
        if ignore {
            Tolerance::Ignore
        } else {
            Tolerance::Within { rel, abs }
        }
    }
}

/// `pattern` with at most one `*` matching `name`.
fn glob(pattern: &str, name: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == name,
        Some((pre, post)) => name.len() >= pre.len() + post.len() && name.starts_with(pre) && name.ends_with(post),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLOSED: Option<EncoderClass> = Some(EncoderClass { kind: "sh2", iterative: false });
    const ITER: Option<EncoderClass> = Some(EncoderClass { kind: "sh1", iterative: true });

    fn rules() -> Tolerances {
        Tolerances::parse(
            r#"
            [[rule]]
            rel = 1e-9
            [[rule]]
            class = "iterative"
            rel = 1e-6
            abs = 1e-12
            [[rule]]
            columns = ["*_ns"]
            ignore = true
            [[rule]]
            encoders = ["sh2"]
            columns = ["neg_frac", "diagnostics.*"]
            abs = 1e-3
            why = "test"
            "#,
        )
        .unwrap()
    }

    #[test]
    fn later_rules_override_the_fields_they_set() {
        let t = rules();
        assert_eq!(t.get("rmse", CLOSED), Tolerance::Within { rel: 1e-9, abs: 0.0 });
        assert_eq!(t.get("rmse", ITER), Tolerance::Within { rel: 1e-6, abs: 1e-12 });
        assert_eq!(t.get("fit_ns", CLOSED), Tolerance::Ignore);
        assert_eq!(t.get("eval_ns", None), Tolerance::Ignore);
        assert_eq!(t.get("neg_frac", CLOSED), Tolerance::Within { rel: 1e-9, abs: 1e-3 });
        assert_eq!(t.get("diagnostics.iters", CLOSED), Tolerance::Within { rel: 1e-9, abs: 1e-3 });
        assert_eq!(t.get("neg_frac", ITER), Tolerance::Within { rel: 1e-6, abs: 1e-12 });
        // No encoder: class- and encoder-scoped rules do not apply.
        assert_eq!(t.get("rmse", None), Tolerance::Within { rel: 1e-9, abs: 0.0 });
        assert_eq!(Tolerances::default().get("rmse", CLOSED), Tolerance::EXACT);
    }

    /// The boundary, with powers of two so that it is exact in f64: rel = 2⁻³⁰ about 1.0
    /// admits 1 + 2⁻³⁰ and rejects the next double up.
    #[test]
    fn accepts_up_to_the_boundary_and_not_one_ulp_beyond() {
        let rel = 2f64.powi(-30);
        let t = Tolerance::Within { rel, abs: 0.0 };
        let edge = 1.0 + rel;
        assert!(t.accepts(1.0, edge));
        assert!(t.accepts(1.0, 1.0 - rel));
        assert!(!t.accepts(1.0, edge.next_up()));
        assert!(!t.accepts(1.0, (1.0 - rel).next_down()));
        // The absolute floor governs near zero.
        let a = Tolerance::Within { rel: 1e-9, abs: 0.5 };
        assert!(a.accepts(0.0, 0.5) && !a.accepts(0.0, 0.5f64.next_up()));
        assert!(!Tolerance::EXACT.accepts(0.0, f64::MIN_POSITIVE));
        assert!(!t.accepts(1.0, f64::INFINITY) && !t.accepts(f64::NAN, f64::NAN));
        assert!(Tolerance::Ignore.accepts(1.0, 2.0));
    }

    #[test]
    fn bad_rules_are_rejected_with_the_rule_number() {
        let e = |s: &str| format!("{:#}", Tolerances::parse(s).err().unwrap());
        assert!(e("[[rule]]\nrel = -1.0").contains("rule 1"));
        assert!(e("[[rule]]\nrel = 1.0\n[[rule]]\nclass = 'fast'\nrel = 1.0").contains("rule 2"));
        assert!(e("[[rule]]\nencoders = ['shx']\nrel = 1.0").contains("unknown encoder kind 'shx'"));
        assert!(e("[[rule]]\ncolumns = ['a*b*']\nrel = 1.0").contains("at most one"));
        assert!(e("[[rule]]\ncolumns = ['a']").contains("none of rel, abs, ignore"));
        assert!(e("[[rule]]\nrel = 1.0\nbogus = 2").contains("bogus"));
    }

    #[test]
    fn the_committed_file_parses_and_ignores_timings() {
        let t = Tolerances::load(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
        assert_eq!(t.get("fit_ns", CLOSED), Tolerance::Ignore);
        assert_eq!(t.get("eval_ns", ITER), Tolerance::Ignore);
        match (t.get("rmse", CLOSED), t.get("rmse", ITER)) {
            (Tolerance::Within { rel: c, .. }, Tolerance::Within { rel: i, .. }) => assert!(c == 1e-9 && i > c),
            other => panic!("{other:?}"),
        }
    }
}
