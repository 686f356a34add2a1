//! What judging gives: a check's status and the values it judged on each map set, a claim's
//! one verdict and its checks ([`crate::claims::judge`]); the evidence they are judged on.

use crate::claims::declaration::{CheckDecl, Kind};

/// An evidence table: CSV text with a header (the same text table the baselines use).
pub use crate::pipeline::table::CsvText as Evidence;

/// Where a check, or a claim, stands.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// The criterion is met.
    Pass,
    /// The criterion is not met.
    Fail,
    /// A figure without a criterion (`ratio_summary`): shown, neither met nor missed.
    Shown,
    /// The data to judge it is missing; the reason.
    Untestable(String),
}

/// One value a check judged: the row's label (its key; the map for per-map ratios), the value
/// (a ratio for ratio tests) and whether it passes on its own.
#[derive(Clone, Debug)]
pub struct RowValue {
    /// The row's key as text (map, domain, effects, metric, case: those the table has).
    pub label: String,
    /// The value judged: the cell, or its ratio to the baseline encoder's for ratio tests.
    pub value: f64,
    /// Whether this row alone meets the criterion.
    pub pass: bool,
}

/// A check judged on one map set.
#[derive(Clone, Debug)]
pub struct SetOutcome {
    /// `all`, or a declared set name.
    pub set: String,
    /// Distinct maps judged.
    pub maps: usize,
    /// The maps the check is restricted to within the set (its `maps`), if it is: the set's
    /// label then names them, so "all" never stands for a subset.
    pub only: Option<Vec<String>>,
    /// The check's status on this set.
    pub status: Status,
    /// One short phrase with the number.
    pub headline: String,
    /// The full figure.
    pub figure: String,
    /// Every row judged, in the table's order.
    pub values: Vec<RowValue>,
    /// Rows left out: baseline at or below the floor, or no value.
    #[cfg_attr(not(test), allow(dead_code, reason = "read by the unit tests, which check what was judged"))]
    pub excluded: usize,
}

/// A check judged on each set it declares.
#[derive(Clone, Debug)]
pub struct CheckOutcome {
    /// The check as declared in the claims file.
    pub decl: CheckDecl,
    /// Its outcome on each map set it names (or `all`).
    pub sets: Vec<SetOutcome>,
}

/// A claim's one verdict, in the words its kind allows.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// `measured`: the primary check passes on every set it is judged on.
    Holds,
    /// `identity`: the identity is met numerically, to rounding.
    HoldsIdentity,
    /// `measured`: the primary passes on some of its sets and not others; which.
    Partly(String),
    /// `measured` or `identity`: the primary check fails; where.
    Fails(String),
    /// `example`: the paper's case (or the closest we have) shows what the paper says.
    Reproduced,
    /// `example`: it does not; where.
    NotReproduced(String),
    /// `anchor`: the paper's figure comes from a population we do not have.
    NotComparable,
    /// The primary check cannot be judged (its evidence is missing); why.
    Untestable(String),
}

/// A judged claim.
#[derive(Clone, Debug)]
pub struct ClaimOutcome {
    /// The claim's id (`Z1`, `H3`, `D2`, …).
    pub id: String,
    /// The claim's evidence kind.
    pub kind: Kind,
    /// The one verdict, decided by the primary check.
    pub verdict: Verdict,
    /// Every check, judged (the primary among them).
    pub checks: Vec<CheckOutcome>,
}

impl Status {
    /// Pass when every row passes.
    pub(super) fn pass_if(all: bool) -> Status {
        if all {
            Status::Pass
        } else {
            Status::Fail
        }
    }
}

impl SetOutcome {
    /// A set that could not be judged, and why.
    pub(super) fn untestable(set: &str, maps: usize, why: String) -> SetOutcome {
        SetOutcome {
            set: set.into(),
            maps,
            only: None,
            status: Status::Untestable(why),
            headline: "no data".into(),
            figure: String::new(),
            values: vec![],
            excluded: 0,
        }
    }
}
