//! The measures and geometry of a comparison sheet at scale 1 — disc, cells, rows, margins,
//! header, thumbnail, colour bars — and [`SheetLayout`], which places every cell, disc and the
//! colour bar at the sheet's scale (each measure times the scale).

use super::super::text::{even_px, text_width, BODY, HEADING};

/// A sphere's (disc's) diameter at scale 1, in pixels. Every measure below is in pixels at
/// scale 1.
pub const DISC: u32 = 96;
/// A sphere's cell width: the disc and 12 px.
pub const CELL_W: u32 = DISC + 12;
/// A sphere's cell height: the disc and 8 px.
pub const CELL_H: u32 = DISC + 8;
/// Three text lines under each row of spheres (the figures, and the shares that saturate).
pub const ROW_H: u32 = CELL_H + 60;
/// The narrowest label column; wider when a name or storage note needs it ([`label_width`]).
pub const LABEL_W: u32 = 128;
/// Sizes of a row's name (bold) and storage note.
pub(super) const NAME_PX: f64 = HEADING;
pub(super) const NOTE_PX: f64 = BODY;
/// The margin around the sheet.
pub const MARGIN: u32 = 12;
/// The gap between two views' groups of three cells.
pub const VIEW_GAP: u32 = 16;
/// The most header lines drawn under the title (a line too wide for the sheet wraps).
pub const HEADER_LINES: u32 = 9;
/// The height of one header line.
pub const LINE_H: u32 = 18;
/// The map thumbnail's width (lat-long, so twice its height).
pub const THUMB_W: u32 = 256;
/// The map thumbnail's height.
pub const THUMB_H: u32 = 128;
/// Title, header lines, then the thumbnail with the colour bar beside it.
pub const HEADER_H: u32 = MARGIN + 26 + HEADER_LINES * LINE_H + 8 + THUMB_H + 22;
/// The view captions and column names above the rows.
pub const COLHEAD_H: u32 = 42;
/// The error colour bar's width.
pub const BAR_W: u32 = 256;
/// The error colour bar's height.
pub const BAR_H: u32 = 16;
/// The width the error colour bar and its title take, where the chroma bar begins after it.
pub const ERROR_BAR_SPAN: u32 = 340;
/// The width the chroma colour bar and its text take.
pub const CHROMA_SPAN: u32 = 330;
/// The narrowest sheet, to which a narrower grid of cells is widened: both colour bars (or the
/// error bar and the note saying why there are no chroma discs) and their text side by side.
pub const MIN_W: u32 = MARGIN + THUMB_W + 28 + ERROR_BAR_SPAN + CHROMA_SPAN + MARGIN;
/// The largest sheet scale (`--scale`): 8 draws a 96 px disc at 768 px.
pub const MAX_SCALE: u32 = 8;

/// The geometry of a comparison sheet: one row per encoder, three columns (reference, encoder,
/// relative error) per view, and a fourth (chroma error) when the sheet draws chroma discs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetLayout {
    /// The rows of spheres: one per encoder.
    pub rows: u32,
    /// The views of the sphere of normals: 2 for the sphere (front, top), 1 for a hemisphere.
    pub views: u32,
    /// Width of the label column at scale 1 (names and storage notes in full).
    pub label_w: u32,
    /// Every measure is this many times its scale-1 value (1..=[`MAX_SCALE`]).
    pub scale: u32,
    /// Whether each view has a fourth, chroma-error column (and the header its colour bar).
    pub chroma: bool,
}

/// The label column's width: [`LABEL_W`], or the widest measured name (bold) or storage note
/// plus 14 px of gap when that is wider, so no name is shortened.
pub fn label_width<'a>(rows: impl IntoIterator<Item = (&'a str, &'a str)>) -> u32 {
    rows.into_iter()
        .map(|(name, note)| text_width(name, NAME_PX, true).max(text_width(note, NOTE_PX, false)) + 14)
        .fold(LABEL_W, u32::max)
}

impl SheetLayout {
    /// Width × height in pixels: the scale-1 size times the scale.
    pub fn size(&self) -> (u32, u32) {
        let grid_w =
            2 * MARGIN + self.label_w + self.views * self.columns() * CELL_W + self.views.saturating_sub(1) * VIEW_GAP;
        let s = self.scale;
        (s * grid_w.max(MIN_W), s * (HEADER_H + COLHEAD_H + self.rows * ROW_H + MARGIN))
    }
    /// The columns of each view: reference, encoder, relative error, and chroma error if drawn.
    pub fn columns(&self) -> u32 {
        3 + u32::from(self.chroma)
    }
    /// Top-left pixel of the cell (row, view, column 0..[`SheetLayout::columns`]).
    pub fn cell(&self, row: u32, view: u32, col: u32) -> (u32, u32) {
        let x = MARGIN + self.label_w + view * (self.columns() * CELL_W + VIEW_GAP) + col * CELL_W;
        (self.scale * x, self.scale * (HEADER_H + COLHEAD_H + row * ROW_H))
    }
    /// Top-left pixel of the disc in the cell (row, view, column 0..3), [`DISC`]·scale across.
    pub fn disc(&self, row: u32, view: u32, col: u32) -> (u32, u32) {
        let (x, y) = self.cell(row, view, col);
        (x + self.scale * ((CELL_W - DISC) / 2), y + self.scale * ((CELL_H - DISC) / 2))
    }
    /// Top-left pixel of the colour bar.
    pub fn colour_bar(&self) -> (u32, u32) {
        (self.scale * (MARGIN + THUMB_W + 28), self.scale * (MARGIN + 26 + HEADER_LINES * LINE_H + 8 + 44))
    }
    /// Top-left pixel of the chroma colour bar, right of the error bar (where a sheet without
    /// chroma discs says why).
    pub fn chroma_bar(&self) -> (u32, u32) {
        let (x, y) = self.colour_bar();
        (x + self.scale * ERROR_BAR_SPAN, y)
    }
    /// The width, at this scale, that the chroma bar's text may take.
    pub fn chroma_text_width(&self) -> u32 {
        self.size().0 - self.scale * MARGIN - self.chroma_bar().0
    }
}

/// A text size at sheet scale `s`: the scale-1 size rounded to even pixels ([`even_px`]),
/// times `s`, so it stays even (plotters keeps glyphs on the baseline only at even sizes).
pub(super) fn text_px(size: f64, s: u32) -> f64 {
    even_px(size) * s as f64
}
