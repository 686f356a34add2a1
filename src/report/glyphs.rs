//! Setting a line of text in the bundled DejaVu Sans: glyph positions with kerning at
//! fractional pixels, each glyph rasterised at its own position with its side bearing, and the
//! line's box. Every picture's text goes through here: the sheets' labels and, through
//! [`super::charts`]' backend, every chart's PNG.
//!
//! **Sizes.** A text size is plotters' size (the number given to `(FONT, size)`); its em is
//! `size / 1.24`, the `font-size` plotters' SVG backend writes, so a chart's PNG and its SVG set
//! the same glyphs at the same size. (plotters' own bitmap path scaled the glyph outlines to an
//! em of `size / 1.16`, dropped every glyph's left side bearing — "1 4" for "14" — and cut each
//! glyph's position to a whole pixel.)
//!
//! **Vertical anchors** follow the SVG backend's: the baseline is 0.76 em below a top anchor,
//! half an x-height below a centre anchor and half an x-height above a bottom anchor. A
//! line's box ([`line_box`]) runs from 0.76 em above the baseline to 0.24 em below it.

use ab_glyph::{point, Font, FontRef, GlyphId, PxScale, ScaleFont};
use plotters::style::text_anchor::{HPos, VPos};
use std::sync::OnceLock;

/// plotters' size divided by this is the em (the SVG backend's `font-size`).
pub const SIZE_PER_EM: f64 = 1.24;
/// The baseline below a top anchor, in em (the SVG backend's `dy="0.76em"`).
const TOP_TO_BASELINE: f64 = 0.76;

/// The bundled faces, parsed once.
fn face(bold: bool) -> &'static FontRef<'static> {
    static FACES: OnceLock<[FontRef<'static>; 2]> = OnceLock::new();
    let faces = FACES.get_or_init(|| {
        // The bundled fonts are valid TrueType (the `dejavu` crate ships them).
        let parse = |b: &'static [u8]| FontRef::try_from_slice(b).expect("bundled DejaVu Sans parses");
        [parse(dejavu::sans::regular()), parse(dejavu::sans::bold())]
    });
    &faces[usize::from(bold)]
}

/// The em in pixels of a text size.
pub fn em(size: f64) -> f64 {
    size / SIZE_PER_EM
}

/// ab_glyph's scale (ascent − descent in pixels) for an em of `em(size)`.
fn scale(font: &FontRef<'static>, size: f64) -> PxScale {
    let upem = font.units_per_em().unwrap_or(2048.0);
    PxScale::from((em(size) as f32) * font.height_unscaled() / upem)
}

/// Each glyph of `text` and the x of its origin, from the line's start, with kerning; and the
/// line's advance width (all in fractional pixels).
fn layout(text: &str, size: f64, bold: bool) -> (Vec<(GlyphId, f32)>, f32) {
    let font = face(bold);
    let scaled = font.as_scaled(scale(font, size));
    let mut caret = 0f32;
    let mut prev: Option<GlyphId> = None;
    let mut out = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            caret += scaled.kern(p, id);
        }
        out.push((id, caret));
        caret += scaled.h_advance(id);
        prev = Some(id);
    }
    (out, caret)
}

/// The advance width of `text` at `size`, in whole pixels (rounded up).
pub fn width(text: &str, size: f64, bold: bool) -> u32 {
    layout(text, size, bold).1.ceil() as u32
}

/// The baseline's offset below the anchor's y, in pixels, for a vertical anchor.
fn baseline(size: f64, v: VPos, bold: bool) -> f64 {
    let font = face(bold);
    let upem = font.units_per_em().unwrap_or(2048.0) as f64;
    // DejaVu Sans' x-height is 1120 units of 2048; the SVG backend's `ex`.
    let ex = 1120.0 / upem * em(size);
    match v {
        VPos::Top => TOP_TO_BASELINE * em(size),
        VPos::Center => 0.5 * ex,
        VPos::Bottom => -0.5 * ex,
    }
}

/// The box (x0, y0, x1, y1) of a line of text anchored at (x, y), unrotated: its advance width
/// across, from 0.76 em above the baseline to 0.24 em below it.
pub fn line_box(text: &str, size: f64, bold: bool, anchor: (HPos, VPos), at: (i32, i32)) -> (i32, i32, i32, i32) {
    let w = layout(text, size, bold).1 as f64;
    let x0 = at.0 as f64 - shift(anchor.0, w);
    let base = at.1 as f64 + baseline(size, anchor.1, bold);
    let e = em(size);
    (
        x0.floor() as i32,
        (base - TOP_TO_BASELINE * e).floor() as i32,
        (x0 + w).ceil() as i32,
        (base + (1.0 - TOP_TO_BASELINE) * e).ceil() as i32,
    )
}

/// How far left of the anchor's x the line starts.
fn shift(h: HPos, w: f64) -> f64 {
    match h {
        HPos::Left => 0.0,
        HPos::Center => w / 2.0,
        HPos::Right => w,
    }
}

/// Rasterises a line anchored at the origin: calls `put(x, y, coverage)` for every pixel the
/// glyphs cover, (x, y) relative to the anchor point (unrotated), coverage in (0, 1].
pub fn rasterise(text: &str, size: f64, bold: bool, anchor: (HPos, VPos), mut put: impl FnMut(i32, i32, f32)) {
    let font = face(bold);
    let sc = scale(font, size);
    let (glyphs, w) = layout(text, size, bold);
    let x0 = -shift(anchor.0, w as f64) as f32;
    let base = baseline(size, anchor.1, bold) as f32;
    for (id, x) in glyphs {
        let g = id.with_scale_and_position(sc, point(x0 + x, base));
        let Some(outline) = font.outline_glyph(g) else { continue };
        let b = outline.px_bounds();
        outline.draw(|px, py, c| {
            if c > 0.0 {
                put(b.min.x as i32 + px as i32, b.min.y as i32 + py as i32, c.min(1.0));
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ink of `text` at `size` as a set of covered pixels (coverage > 0.5).
    fn ink(text: &str, size: f64) -> Vec<(i32, i32)> {
        let mut v = Vec::new();
        rasterise(text, size, false, (HPos::Left, VPos::Top), |x, y, c| {
            if c > 0.3 {
                v.push((x, y))
            }
        });
        v
    }

    /// "14" set as a word: each glyph's ink starts at its origin plus its left side bearing
    /// (the font's own metrics), within a pixel; plotters' bitmap path drew every glyph at the
    /// left edge of its cell, so the 1 (bearing 0.11 em) stood apart from the 4 ("1 4").
    #[test]
    fn digits_keep_their_side_bearings() {
        let em_px = 14.0f32;
        let size = em_px as f64 * SIZE_PER_EM;
        let font = face(false);
        let upem = font.units_per_em().unwrap();
        let (one, four) = (font.glyph_id('1'), font.glyph_id('4'));
        let px = |units: f32| units / upem * em_px;
        let one_left = px(font.h_side_bearing_unscaled(one));
        let four_left =
            px(font.h_advance_unscaled(one) + font.kern_unscaled(one, four) + font.h_side_bearing_unscaled(four));
        let ink1 = ink("1", size);
        let both = ink("14", size);
        let one_right = ink1.iter().map(|p| p.0).max().unwrap();
        let got1 = ink1.iter().map(|p| p.0).min().unwrap();
        let got4 = both.iter().filter(|p| p.0 > one_right).map(|p| p.0).min().unwrap();
        assert!((got1 as f32 - one_left).abs() <= 1.0, "1 starts at {got1}, its bearing is {one_left}");
        assert!((got4 as f32 - four_left).abs() <= 1.0, "4 starts at {got4}, expected {four_left}");
    }

    /// At any size, odd ones included, a point stands on the digits' baseline.
    #[test]
    fn points_sit_on_the_baseline_at_any_size() {
        for size in [13.0, 14.0, 15.0, 16.0, 17.5, 20.0, 33.0] {
            let one = ink("1", size);
            let all = ink("1.", size);
            let right = one.iter().map(|p| p.0).max().unwrap();
            let digit = one.iter().map(|p| p.1).max().unwrap();
            let point = all.iter().filter(|p| p.0 > right).map(|p| p.1).max().unwrap();
            assert_eq!(digit, point, "size {size}");
        }
    }

    /// The em is size / 1.24: a capital H's ink is DejaVu's cap height (1493/2048 em) tall.
    #[test]
    fn the_em_is_the_svg_font_size() {
        let size = 24.8; // an em of 20 px
        let h = ink("H", size);
        let tall = h.iter().map(|p| p.1).max().unwrap() - h.iter().map(|p| p.1).min().unwrap() + 1;
        assert!((tall as f64 - 1493.0 / 2048.0 * 20.0).abs() <= 1.0, "H is {tall} px tall");
        // The box holds the ink: top anchor, cap top below the box top, descender above its bottom.
        let (_, y0, _, y1) = line_box("Hg", size, false, (HPos::Left, VPos::Top), (0, 0));
        let g = ink("Hg", size);
        assert!(g.iter().all(|p| p.1 >= y0 && p.1 < y1), "ink within {y0}..{y1}");
        assert_eq!(width("Hg", size, false), line_box("Hg", size, false, (HPos::Left, VPos::Top), (0, 0)).2 as u32);
    }
}
