//! The evidence kind of a claim, which decides the verdict words it may get, and the one word
//! of a claim whose evidence is missing.

/// What kind of evidence a claim is, which decides the verdict words it may get.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// True by derivation or construction, checked numerically to rounding (by an independent
    /// path where one exists): `holds (identity)` or `fails`.
    Identity,
    /// A general statement over maps or scenes: `holds`, `partly` or `fails`, decided by the
    /// primary check.
    Measured,
    /// Stated for one case (usually the paper's figure): `reproduced` or `not reproduced`, on
    /// the paper's case or the closest we have; the rate over all maps is context.
    Example,
    /// The paper's figure comes from a population we do not have (a production set): `not
    /// comparable`; our figure stands beside theirs, with the reason. It never holds or fails.
    Anchor,
}

impl Kind {
    /// Every kind, in the order the docs list them.
    pub const ALL: [Kind; 4] = [Kind::Identity, Kind::Measured, Kind::Example, Kind::Anchor];

    /// The key's value (`identity`, `measured`, `example`, `anchor`).
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Identity => "identity",
            Kind::Measured => "measured",
            Kind::Example => "example",
            Kind::Anchor => "anchor",
        }
    }

    /// The verdict words a claim of this kind may get when its evidence is there
    /// (`untestable` is the one word any kind gets when it is not).
    pub fn verdict_words(self) -> &'static [&'static str] {
        match self {
            Kind::Identity => &["holds (identity)", "fails"],
            Kind::Measured => &["holds", "partly", "fails"],
            Kind::Example => &["reproduced", "not reproduced"],
            Kind::Anchor => &["not comparable"],
        }
    }

    /// The kind named `s`, if any.
    pub fn parse(s: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.as_str() == s)
    }
}

/// The word of a claim whose evidence is missing, for any kind.
pub const UNTESTABLE: &str = "untestable";
