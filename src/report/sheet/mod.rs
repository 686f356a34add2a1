//! Comparison sheets (`sheet_<map>.png`): for one experiment on one map, a row per encoder and,
//! per view of the sphere of normals ([`View`](crate::reference::view::View)), three lit
//! spheres: the reference, the encoder and its signed relative error; and a fourth, the
//! encoder's chroma error (CIE 1931 xy distance), on sheets whose encoders differ in colour. All spheres of a sheet
//! share one [`Tone`](super::tone::Tone); the error sphere's colour scale is the sheet's
//! [`ErrorScale`](super::tone::ErrorScale) (both in `tone.rs`). A sphere domain is drawn front
//! and top; a hemisphere domain as a disc looking down N.
//!
//! At scale N (`probelab report --scale N`, [`MAX_SCALE`] at most) every measure below is N
//! times larger: the sheet is laid out at scale 1 and each position and length multiplied by N,
//! the discs are evaluated at N·[`DISC`] pixels (every pixel at its own normal, not enlarged),
//! text is drawn at N times its even pixel size and the thumbnail is filtered at N·[`THUMB_W`].
//!
//! The rmse under each error sphere is the `exact` metric — solid-angle weighted over the
//! case's output domain at the experiment's resolution — read from the experiment's table, or
//! else scored here by the runner's one scoring step
//! ([`score_fit`](crate::pipeline::runner::score_fit)) from the same
//! [`CaseData`](crate::pipeline::runner::CaseData) and fit the runner scores, so it equals the
//! table's figure.
//!
//! Files: `layout.rs` (the measures and [`SheetLayout`]), `render.rs` ([`Sheet`] painted),
//! `thumbnail.rs` (the map's thumbnail), `figures.rs` (the figures under each row),
//! `chroma.rs` (the chroma discs: CIE xy distance, their scale and when they are drawn),
//! `compose.rs` ([`experiment_sheet`]: a sheet made from an experiment and a map), `pages.rs`
//! (a long sheet split into pages no taller than [`MAX_PAGE_H`]).

mod chroma;
mod compose;
mod figures;
mod layout;
mod pages;
mod render;
#[cfg(test)]
mod tests;
mod thumbnail;

pub use compose::{experiment_sheet, share_error_scale};
pub use layout::MAX_SCALE;
pub use layout::{LINE_H, MARGIN};
pub use pages::{file_page, page_file, MAX_PAGE_H};
pub use render::Sheet;
pub use thumbnail::latlong_thumbnail;
