//! The English of judging: verdict words and reasons, each check's headline and figure, map
//! sets and numbers as the pages and CLAIMS.csv print them. Nothing here decides: the numbers
//! and statuses come from [`crate::claims::judge`]'s checks.

use crate::claims::declaration::Statistic;
use crate::claims::judge::outcome::{CheckOutcome, ClaimOutcome, SetOutcome, Verdict};
use crate::claims::ratios::Summary;

impl Verdict {
    /// The verdict word (one of its kind's [`crate::claims::declaration::Kind::verdict_words`], or `untestable`).
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::HoldsIdentity => "holds (identity)",
            Verdict::Partly(_) => "partly",
            Verdict::Fails(_) => "fails",
            Verdict::Reproduced => "reproduced",
            Verdict::NotReproduced(_) => "not reproduced",
            Verdict::NotComparable => "not comparable",
            Verdict::Untestable(_) => crate::claims::declaration::UNTESTABLE,
        }
    }
    /// What part held, what failed, or why it cannot be judged.
    pub fn why(&self) -> &str {
        match self {
            Verdict::Holds | Verdict::HoldsIdentity | Verdict::Reproduced | Verdict::NotComparable => "",
            Verdict::Partly(s) | Verdict::Fails(s) | Verdict::NotReproduced(s) | Verdict::Untestable(s) => s,
        }
    }
}

/// A check's headline on each of its sets (`paper 5: …; all 19: …`).
fn headlines(c: &CheckOutcome) -> String {
    let parts: Vec<String> = c
        .sets
        .iter()
        .map(|s| if c.sets.len() > 1 { format!("{}: {}", set_short(s), s.headline) } else { s.headline.clone() })
        .collect();
    parts.join("; ")
}

impl ClaimOutcome {
    /// Our figure: the primary check's headline on each of its sets, then the headline of
    /// each context check declared `beside` (named).
    pub fn our_figure(&self) -> String {
        let mut parts: Vec<String> = self.checks.iter().filter(|c| c.decl.primary).map(headlines).collect();
        for c in self.checks.iter().filter(|c| c.decl.beside) {
            parts.push(format!("{}: {}", c.decl.name, headlines(c)));
        }
        parts.join(" · ")
    }
    /// The map sets judged, with their map counts (e.g. `paper (5); all (19)`).
    pub fn maps(&self) -> String {
        let mut v: Vec<String> = Vec::new();
        for c in &self.checks {
            for s in &c.sets {
                let l = set_label(s);
                if !v.contains(&l) {
                    v.push(l);
                }
            }
        }
        v.join("; ")
    }
}

/// `paper (5 maps)`, `scenes (2 constructed scenes)`; a check restricted to some maps names
/// them, `pisa_256x128, wells_probulator (of all; 2 maps)`; a set without a map column is
/// named alone.
pub fn set_label(s: &SetOutcome) -> String {
    if let Some(only) = &s.only {
        let noun = crate::claims::population::noun(&s.set);
        format!("{} (of {}; {})", only.join(", "), s.set, n_maps(s.maps, noun))
    } else if s.maps > 0 {
        format!("{} ({})", s.set, n_maps(s.maps, crate::claims::population::noun(&s.set)))
    } else {
        s.set.clone()
    }
}

/// `paper 5`: the set and its map count, short (for headlines).
fn set_short(s: &SetOutcome) -> String {
    if let Some(only) = &s.only {
        only.join(", ")
    } else if s.maps > 0 {
        format!("{} {}", s.set, s.maps)
    } else {
        s.set.clone()
    }
}

/// Three significant digits; scientific below 1e-3.
pub fn fmt3(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if !x.is_finite() {
        "non-finite".into()
    } else if x.abs() < 1e-3 || x.abs() >= 1e5 {
        format!("{x:.2e}")
    } else {
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    }
}

/// How many maps (or, in a table without maps, cases) a summary holds, as a phrase (`19 maps`).
fn n_maps(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// The rows a check left out, as the tail of its figure (`; left out: …`), or nothing.
pub(super) fn left_out(
    base: &str,
    col: &str,
    floor: f64,
    below_floor: usize,
    unmatched: usize,
    empty: usize,
) -> String {
    let mut v = Vec::new();
    if below_floor > 0 {
        v.push(format!("{below_floor} with {base} {col} ≤ floor {}", fmt3(floor)));
    }
    if unmatched > 0 {
        v.push(format!("{unmatched} without a {base} row"));
    }
    if empty > 0 {
        v.push(format!("{empty} without a value"));
    }
    if v.is_empty() {
        String::new()
    } else {
        format!("; left out: {}", v.join(", "))
    }
}

/// The tail of a bound's figure for rows without a value (or nothing).
fn without_value(excluded: usize) -> String {
    if excluded > 0 {
        format!(" ({excluded} row(s) without a value left out)")
    } else {
        String::new()
    }
}

/// A bound on every row, as it came out: the worst value (largest for an upper bound) and where.
pub(super) struct BoundFigures<'a> {
    /// The judged column.
    pub col: &'a str,
    /// The check's encoder.
    pub encoder: &'a str,
    /// An upper bound (`every_at_most`), or a lower one.
    pub upper: bool,
    /// The bound.
    pub bound: f64,
    /// The worst value and its row's label.
    pub worst: (f64, &'a str),
    /// Rows within the bound, of how many.
    pub passing: usize,
    /// Rows judged.
    pub rows: usize,
    /// Rows without a value, left out.
    pub excluded: usize,
}

/// `median_at_least`'s headline: the median of the per-map values against the bound, and how
/// many maps meet it alone.
pub(super) fn median_bound(
    col: &str,
    (median, bound): (f64, f64),
    (passing, of): (usize, usize),
    noun: &str,
) -> String {
    format!(
        "per-map median {col} {}{} ≥ {} ({passing}/{of} {noun}s ≥ {})",
        fmt3(median),
        if median >= bound { "" } else { ", not" },
        fmt3(bound),
        fmt3(bound)
    )
}

/// A bound's headline and figure.
pub(super) fn bound(b: &BoundFigures) -> (String, String) {
    let (col, upper) = (b.col, b.upper);
    let op = if upper { "≤" } else { "≥" };
    let headline = format!(
        "{} {col} {} {op} {} ({}/{})",
        if upper { "max" } else { "min" },
        fmt3(b.worst.0),
        fmt3(b.bound),
        b.passing,
        b.rows
    );
    let figure = format!(
        "{col} of {}: {} {} at {}; {op} {} in {}/{} rows{}",
        b.encoder,
        if upper { "largest" } else { "smallest" },
        fmt3(b.worst.0),
        b.worst.1,
        fmt3(b.bound),
        b.passing,
        b.rows,
        without_value(b.excluded)
    );
    (headline, figure)
}

/// `every_equal`'s headline and figure: `passing` of `rows` equal `value`, `off` the others.
pub(super) fn exact(
    col: &str,
    encoder: &str,
    value: f64,
    (passing, rows): (usize, usize),
    off: &[&str],
    excluded: usize,
) -> (String, String) {
    let headline = format!("{col} = {} in {passing}/{rows}", fmt3(value));
    let figure = format!(
        "{col} of {encoder}: {headline} rows{}{}",
        if off.is_empty() { String::new() } else { format!("; differs at {}", off.join(", ")) },
        without_value(excluded)
    );
    (headline, figure)
}

/// `equal`'s headline and figure: the worst relative difference (and its row) against the
/// tolerance.
pub(super) fn equal(
    worst: (f64, &str),
    tolerance: f64,
    abs_tolerance: f64,
    (passing, rows): (usize, usize),
    left_out: &str,
) -> (String, String) {
    let headline = format!("largest relative difference {} ≤ {} ({passing}/{rows})", fmt3(worst.0), fmt3(tolerance));
    let figure =
        format!("{headline}; worst at {}; differences ≤ {} count as equal{left_out}", worst.1, fmt3(abs_tolerance));
    (headline, figure)
}

/// A per-map ratio's label: the map and how many rows it summarises.
pub(super) fn map_label(map: &str, rows: usize) -> String {
    format!("{map} ({rows} row{})", if rows == 1 { "" } else { "s" })
}

/// `ratio_every` / `ratio_some`'s headline: how many rows (or maps) are below, with the per-map
/// median and geometric mean.
pub(super) fn ratio_count(passing: usize, of: usize, unit: &str, below: f64, sum: &Summary) -> String {
    let (med, gm) = (fmt3(sum.median), fmt3(sum.geomean));
    format!("{passing}/{of} {unit} < {} (per-map median {med}, geomean {gm})", fmt3(below))
}

/// `ratio_stat`'s headline: the statistic against its band, the other statistic beside it.
pub(super) fn ratio_stat(
    statistic: Statistic,
    (stat, ok): (f64, bool),
    (min, max): (Option<f64>, Option<f64>),
    sum: &Summary,
    (noun, in_band): (&str, usize),
) -> String {
    let band = match (min, max) {
        (Some(a), Some(b)) => format!("in [{}, {}]", fmt3(a), fmt3(b)),
        (Some(a), None) => format!("≥ {}", fmt3(a)),
        (None, Some(b)) => format!("≤ {}", fmt3(b)),
        (None, None) => unreachable!("validated: a band"),
    };
    let other = match statistic {
        Statistic::Median => format!("geomean {}", fmt3(sum.geomean)),
        Statistic::GeoMean => format!("median {}", fmt3(sum.median)),
    };
    format!(
        "per-map {} {}{} {band} ({other}; {in_band}/{} {noun}s {band})",
        if statistic == Statistic::Median { "median" } else { "geomean" },
        fmt3(stat),
        if ok { "" } else { ", not" },
        sum.maps.len()
    )
}

/// `ratio_either`'s headline: how many maps are below 1 and how many above, with the per-map
/// median and geometric mean.
pub(super) fn ratio_either((below, above): (usize, usize), sum: &Summary, noun: &str) -> String {
    let m = sum.maps.len();
    format!(
        "{below}/{m} {noun}s < 1, {above}/{m} > 1 (per-map median {}, geomean {})",
        fmt3(sum.median),
        fmt3(sum.geomean)
    )
}

/// `ratio_summary`'s headline: the per-map median and geometric mean, no criterion.
pub(super) fn ratio_summary(sum: &Summary, noun: &str) -> String {
    format!("per-map median {}, geomean {} ({})", fmt3(sum.median), fmt3(sum.geomean), n_maps(sum.maps.len(), noun))
}

/// A ratio test's figure: its headline, the per-map summary and the per-row range over `n`
/// rows, `(lo, hi)`, naming the aggregation.
pub(super) fn ratio_figure(
    (encoder, base, col): (&str, &str, &str),
    headline: &str,
    sum: &Summary,
    noun: &str,
    (n, lo, hi): (usize, f64, f64),
    left_out: &str,
) -> String {
    format!(
        "{encoder}/{base} {col}: {headline}; per-map ratios (each the geometric mean of its rows' ratios) over {}: \
         median {}, geometric mean {}, range {}–{}; per-row ratios over {n} rows: range {}–{}{left_out}",
        n_maps(sum.maps.len(), noun),
        fmt3(sum.median),
        fmt3(sum.geomean),
        fmt3(sum.min),
        fmt3(sum.max),
        fmt3(lo),
        fmt3(hi)
    )
}

/// Why a primary cannot be judged: each untestable set and its reason (`on paper (5 maps): …`).
pub(super) fn untestable_on(s: &SetOutcome, why: &str) -> String {
    format!("on {}: {why}", set_label(s))
}

/// `untestable`'s reason: the primary's name and its untestable sets.
pub(super) fn untestable_reason(name: &str, untestable: &[String]) -> String {
    format!("'{name}' {}", untestable.join("; "))
}

/// `not reproduced`'s reason: where the example's criterion is not met.
pub(super) fn not_met(name: &str, failing: &[String]) -> String {
    format!("'{name}' not met on {}", failing.join(" and "))
}

/// `partly`'s reason: where the primary holds and where not.
pub(super) fn partly(name: &str, passing: &[String], failing: &[String]) -> String {
    format!("'{name}' holds on {}, not on {}", passing.join(" and "), failing.join(" and "))
}

/// `fails`'s reason: where.
pub(super) fn fails(name: &str, failing: &[String]) -> String {
    format!("'{name}' fails on {}", failing.join(" and "))
}
