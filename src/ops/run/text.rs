//! What `run` and `reproduce` say of the tables they store: written, matched, or the
//! differences and the refusal, and of a table checked on some of its maps (as it happens, on
//! stderr); the phrase of a closing summary; and the advice after baselines were refused.

use crate::ops::check::text::experiment;
use crate::regression::baseline::TABLE;
use crate::regression::guard::{PartialCheck, Stored};
use crate::regression::provenance;
use std::path::Path;

/// What became of the table in `dir` (`rows` rows): written, matched, or the differences and
/// the refusal (lines ending in newlines).
pub fn stored(stored: &Stored, dir: &Path, rows: usize) -> String {
    match stored {
        Stored::New => {
            format!("wrote {} ({rows} rows) and {} (new baseline)\n", dir.join(TABLE).display(), provenance::FILE_NAME)
        }
        Stored::Unchanged(c) => format!(
            "{}: matches the baseline ({} numbers compared); left unchanged\n",
            dir.join(TABLE).display(),
            c.comparison.numbers
        ),
        Stored::Refused(c) => format!("{}{}", experiment(c), not_overwritten(dir)),
    }
}

/// What the check of an experiment run on some of its maps (baseline in `dir`) shows as it
/// goes: the comparison's report and what became of the baseline.
pub fn partial_notes(check: &PartialCheck, dir: &Path) -> String {
    match check {
        PartialCheck::NoBaseline => {
            format!("{}: no baseline, and a run missing maps writes none\n", dir.join(TABLE).display())
        }
        PartialCheck::Compared(c) if c.passed() => experiment(c),
        PartialCheck::Compared(c) => format!("{}{}", experiment(c), not_overwritten(dir)),
    }
}

/// The line that says a moved baseline in `dir` was left as it was.
pub fn not_overwritten(dir: &Path) -> String {
    format!("{}: NOT overwritten: the baseline changes only through `probelab bless`\n", dir.join(TABLE).display())
}

/// One phrase for a closing summary: a new baseline, the numbers that matched, or how many
/// moved.
pub fn summary(stored: &Stored) -> String {
    match stored {
        Stored::New => "no baseline yet: new baseline written".to_string(),
        Stored::Unchanged(c) => {
            format!("{} numbers compared, nothing moved; baseline left unchanged", c.comparison.numbers)
        }
        Stored::Refused(c) => format!("FAILED ({} moved)", c.moved()),
    }
}

/// The advice after `run`/`reproduce` refused to overwrite the baselines of `refused`; `None`
/// when nothing was refused.
pub fn refusal_advice(refused: &[String]) -> Option<String> {
    (!refused.is_empty()).then(|| {
        format!(
            "{} experiment(s) differ from their baselines and were not written: {}.\n\
             Review the differences above; if they are intended, run `probelab bless {}` and quote its \
             output in the commit message.\n",
            refused.len(),
            refused.join(", "),
            refused.join(" ")
        )
    })
}
