//! The one claims engine: judges each declared claim ([`crate::claims::declaration`]) on its
//! evidence tables — experiment tables and claims measurements alike, read as CSV. Its one
//! primary check decides its one verdict, in the words its evidence kind allows
//! ([`crate::claims::declaration::Kind`]); its context checks are judged and shown, and never
//! change the verdict. A claim whose primary lacks its data is `untestable` (saying why).
//! Nothing here knows a claim, an encoder or a paper: every criterion and threshold comes from
//! the declaration.
//!
//! Ratios are taken per row (encoder / baseline, matched on the key columns), then per map —
//! a map's ratio is the geometric mean of its rows' ratios (its orientations, say) — and
//! summarised over maps by their median and geometric mean. Never a ratio of pooled means:
//! one map with large errors would decide it. Rows whose baseline value is at or below the
//! check's `floor` are excluded and counted, so no ratio divides by ~0.
//!
//! Judging and wording are apart: `scope` reads a check's rows, `check` and `baseline` judge
//! it on each map set, `verdict` decides the claim; `wording` gives all of it its English
//! (verdict words and reasons, headlines, figures); `outcome` holds what they pass along.

mod baseline;
mod check;
mod outcome;
mod scope;
mod verdict;
mod wording;

pub use outcome::{CheckOutcome, ClaimOutcome, Evidence, Status};
pub use verdict::judge_claim;
pub use wording::{fmt3, set_label};

#[cfg(test)]
mod tests;
