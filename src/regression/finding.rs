//! A finding of `check`: one thing found when an experiment's fresh table is compared with
//! its baseline (a moved number, a changed map, a baseline problem), whether it fails the
//! check, its kind's name in the JSON document, and its sentence (docs/regression.md).

use crate::regression::baseline::{self, TABLE};
use crate::regression::provenance;
use std::fmt;

/// A problem found when checking one experiment against its baseline.
#[derive(Clone, Debug)]
pub enum Finding {
    /// No `table.csv` in the baseline folder.
    NoBaseline,
    /// A table but no (readable) provenance: map checksums cannot be verified.
    NoProvenance(String),
    /// The table's sha256 is not the one its provenance records (edited by hand, merged, or
    /// an interrupted bless).
    TableEdited {
        /// The table sha256 the provenance records.
        recorded: String,
        /// The sha256 of the table file as it is.
        actual: String,
    },
    /// A map of the experiment is not on this machine's search path (`why`: what was looked
    /// for and passed over, and how to get it when it is a known map).
    MapMissing {
        /// The map's name.
        map: String,
        /// What was looked for and passed over, and how to get the map when it is known.
        why: String,
        /// Whether missing maps were allowed for this check (then not a failure).
        allowed: bool,
    },
    /// A map read from another file than the baseline's, with the same pixels
    /// ([`crate::regression::check::same_map`]): its rows are compared. A note, never a failure.
    MapSamePixels {
        /// The map's name.
        map: String,
        /// The file it was read from now ("(no file)" for a generated map).
        file: String,
        /// The pixel sha256 both files share.
        pixel_sha256: String,
    },
    /// A map's file differs from the one the baseline was computed from; its rows are not
    /// compared.
    MapChanged {
        /// The map's name.
        map: String,
        /// The baseline's file: size and start of its sha256.
        old: String,
        /// The file read now: size and start of its sha256.
        new: String,
    },
    /// The table has rows of a map the provenance does not list; they are not compared.
    MapUnrecorded {
        /// The map's name.
        map: String,
    },
    /// A difference in the table.
    Change(baseline::Change),
}

impl Finding {
    /// Whether this finding fails the check.
    pub fn fails(&self) -> bool {
        !matches!(self, Finding::MapMissing { allowed: true, .. } | Finding::MapSamePixels { .. })
    }
}

impl Finding {
    /// A short machine-readable name of the finding's kind (`check --format json`).
    pub fn kind(&self) -> &'static str {
        match self {
            Finding::NoBaseline => "no_baseline",
            Finding::NoProvenance(_) => "no_provenance",
            Finding::TableEdited { .. } => "table_edited",
            Finding::MapMissing { .. } => "map_missing",
            Finding::MapSamePixels { .. } => "map_same_pixels",
            Finding::MapChanged { .. } => "map_changed",
            Finding::MapUnrecorded { .. } => "map_unrecorded",
            Finding::Change(baseline::Change::Moved { .. }) => "moved",
            Finding::Change(baseline::Change::Text { .. }) => "text_changed",
            Finding::Change(baseline::Change::RowAdded(_)) => "row_added",
            Finding::Change(baseline::Change::RowRemoved(_)) => "row_removed",
            Finding::Change(baseline::Change::ColumnAdded(_)) => "column_added",
            Finding::Change(baseline::Change::ColumnRemoved(_)) => "column_removed",
        }
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Finding::NoBaseline => write!(f, "no baseline {TABLE}: nothing to compare with"),
            Finding::NoProvenance(why) => {
                write!(f, "no usable {}: {why}; map checksums cannot be verified", provenance::FILE_NAME)
            }
            Finding::TableEdited { recorded, actual } => write!(
                f,
                "{TABLE} is not the table {} vouches for (sha256 {} recorded, {} found): edited outside \
                 `probelab bless`, or a bless was interrupted",
                provenance::FILE_NAME,
                &recorded[..recorded.len().min(12)],
                &actual[..actual.len().min(12)]
            ),
            // Why it is missing, and how to get it, is said once for every experiment
            // (`regression::missing`), not in each experiment's report.
            Finding::MapMissing { map, allowed: false, .. } => {
                write!(f, "map {map} not found on this machine: its rows were not checked (--require-all-maps)")
            }
            Finding::MapMissing { map, allowed: true, .. } => {
                write!(f, "map {map} not found on this machine: its rows were not checked")
            }
            Finding::MapSamePixels { map, file, pixel_sha256 } => write!(
                f,
                "map {map} read from {file}, not the baseline's file but the same pixels (pixel sha256 {}): its rows \
                 were compared",
                &pixel_sha256[..pixel_sha256.len().min(12)]
            ),
            Finding::MapChanged { map, old, new } => {
                write!(
                    f,
                    "map {map} is not the file the baseline used ({old} then, {new} now): its rows were not compared"
                )
            }
            Finding::MapUnrecorded { map } => write!(
                f,
                "map {map} has rows in the baseline but no checksum in {}: its rows were not compared",
                provenance::FILE_NAME
            ),
            Finding::Change(c) => write!(f, "{c}"),
        }
    }
}
