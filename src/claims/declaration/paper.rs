//! A paper and its declared claims, as validated from its declaration file.

use super::check::CheckDecl;
use super::kind::Kind;
use super::threshold::ThresholdFrom;
use std::collections::BTreeMap;

/// The longest `says` and `paper_figure` phrases (the report's at-a-glance table never cuts a
/// cell, so its cells are short at the source).
pub const SAYS_MAX: usize = 110;

/// A paper and its claims.
#[derive(Clone, Debug)]
pub struct Paper {
    /// The file stem (`zh3`, `hemi`, `brief2018`).
    pub key: String,
    /// The paper's title, as cited in the report (`title`).
    pub title: String,
    /// The paper's authors, as cited in the report (`authors`).
    pub authors: String,
    /// Where the paper appeared, as cited in the report (`venue`).
    pub venue: String,
    /// The paper's place in the report, smallest first (`order`).
    pub order: i64,
    /// Named map sets (besides `all`).
    pub map_sets: BTreeMap<String, Vec<String>>,
    /// The maps the paper's claims measurements run on, in order (`[measurements] maps`; empty
    /// when the file declares none).
    pub measurement_maps: Vec<String>,
    /// The paper's claims, in report order (`[[claim]]`).
    pub claims: Vec<ClaimDecl>,
}

/// One declared claim.
#[derive(Clone, Debug)]
pub struct ClaimDecl {
    /// The claim id of CLAIMS.md, unique within the paper (`id`, e.g. `Z6`).
    pub id: String,
    /// What the paper says, in a phrase of at most [`SAYS_MAX`] characters (`says`).
    pub says: String,
    /// The claim in full (`statement`; `says` when not given).
    pub statement: String,
    /// The paper's own figure for the claim, as text (`paper_figure`).
    pub paper_figure: String,
    /// When the claim counts as holding, in words that mirror the paper's (`criterion`).
    pub criterion: String,
    /// The paper's own sentence, verbatim, hedges included (`quote`; fragments joined by " … ").
    pub quote: String,
    /// Where the primary's threshold comes from (`threshold_from`).
    pub threshold_from: ThresholdFrom,
    /// The evidence kind (`kind`), which decides the verdict words.
    pub kind: Kind,
    /// When the criterion was fixed (`fixed`): `before data` or `after data: <reason>`.
    pub fixed: String,
    /// Why our figure and the paper's may differ (`differs`).
    pub differs: String,
    /// The figures of ours beside the paragraph (`figure`), for a claim whose paper evidence
    /// is an image: each a path under `results/` and a caption (what to look at).
    pub figures: Vec<super::figure::Figure>,
    /// The checks (`[[claim.check]]`): exactly one primary, the others context.
    pub checks: Vec<CheckDecl>,
}

impl ClaimDecl {
    /// The primary check: the one that decides the verdict.
    #[cfg(test)]
    pub fn primary(&self) -> &CheckDecl {
        // Cannot fail: `parse` refuses a claim without exactly one primary check.
        self.checks.iter().find(|k| k.primary).expect("validated: one primary check")
    }
}
