//! Text in the pictures: the bundled font (DejaVu Sans, so no system font is needed), text
//! labels drawn into an image (set by [`super::glyphs`]), their measured boxes, shortening a
//! line to a width, and the sizes every picture uses.
//!
//! **Sizes** are plotters' sizes (em = size / 1.24, see [`super::glyphs`]), even pixel counts
//! ([`even_px`]) so that a sheet drawn at scale N keeps whole-pixel measures. No text is smaller
//! than [`BODY`]: an em of 11.3 px at scale 1.

use super::glyphs;
use anyhow::Result;
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// The smallest text of every picture (tick labels, captions, notes, legends): an em of
/// 14 / 1.24 = 11.3 px at scale 1.
pub const BODY: f64 = 14.0;
/// Row names and panel titles.
pub const HEADING: f64 = 16.0;
/// A picture's title.
pub const TITLE: f64 = 18.0;

/// The font family every picture uses; registered from the `dejavu` crate by [`ensure_font`].
pub const FONT: &str = "sans-serif";

/// Registers DejaVu Sans (regular and bold) with plotters, once.
pub fn ensure_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled fonts are valid TrueType; if registration failed, drawing text would
        // report FontUnavailable, which every caller propagates as an error.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

/// The colour of text.
const INK: RGBColor = RGBColor(20, 20, 20);
/// The colour of secondary text (captions, notes).
const GREY_INK: RGBColor = RGBColor(90, 90, 90);

/// A text item to draw.
#[derive(Clone)]
pub struct Label {
    /// The text, one line.
    pub text: String,
    /// The anchor's x in pixels: the left end, centre or right end of the line per `anchor`.
    pub x: i32,
    /// The top edge of the line, in pixels from the image's top.
    pub y: i32,
    /// The font size in pixels (an even count when built by [`Label::new`]).
    pub size: f64,
    /// Whether the bold face is used.
    pub bold: bool,
    /// Which point of the line `x` is: left end, centre or right end.
    pub anchor: HPos,
    /// The text colour (near-black ink unless [`Label::grey`]).
    pub color: RGBColor,
}

impl Label {
    /// A label at (x, y) (its top edge; left end unless centred or right-aligned); the size is
    /// rounded to an even pixel count ([`even_px`]).
    pub fn new(text: impl Into<String>, x: u32, y: u32, size: f64) -> Self {
        let size = even_px(size);
        Label { text: text.into(), x: x as i32, y: y as i32, size, bold: false, anchor: HPos::Left, color: INK }
    }
    /// The label in the bold face.
    pub fn bold(mut self) -> Self {
        self.bold = true;
        self
    }
    /// The label centred on its x.
    pub fn centre(mut self) -> Self {
        self.anchor = HPos::Center;
        self
    }
    /// The label in grey, the colour of secondary text (captions, notes).
    pub fn grey(mut self) -> Self {
        self.color = GREY_INK;
        self
    }
    /// The label right-aligned on its x.
    #[cfg(test)]
    pub fn right(mut self) -> Self {
        self.anchor = HPos::Right;
        self
    }
    /// The box the label's line takes: (x0, y0, x1, y1) in pixels, x from its measured width
    /// and anchor, y from its top to one size below (ascent and descent of the font's line).
    #[cfg(test)]
    pub fn bounds(&self) -> (i32, i32, i32, i32) {
        glyphs::line_box(&self.text, self.size, self.bold, (self.anchor, VPos::Top), (self.x, self.y))
    }
}

/// A font size rounded to the nearest even whole pixel count, at least 2 (so a sheet at scale
/// N has every text size N times an even size).
pub fn even_px(size: f64) -> f64 {
    if size.is_finite() {
        ((size / 2.0).round() * 2.0).max(2.0)
    } else {
        12.0
    }
}

/// The width in pixels of `text` at `size` (its advance width, as [`super::glyphs`] sets it).
pub fn text_width(text: &str, size: f64, bold: bool) -> u32 {
    glyphs::width(text, even_px(size), bold)
}

/// Draws text into an RGB image: each label's glyphs blended over the pixels by coverage.
pub fn draw_labels(img: &mut RgbImage, labels: &[Label]) -> Result<()> {
    let (w, h) = (img.width() as i32, img.height() as i32);
    for l in labels {
        let ink = [l.color.0, l.color.1, l.color.2].map(f32::from);
        glyphs::rasterise(&l.text, l.size, l.bold, (l.anchor, VPos::Top), |dx, dy, c| {
            let (x, y) = (l.x + dx, l.y + dy);
            if x >= 0 && y >= 0 && x < w && y < h {
                let p = img.get_pixel_mut(x as u32, y as u32);
                for (ch, ink) in p.0.iter_mut().zip(ink) {
                    *ch = (*ch as f32 * (1.0 - c) + ink * c).round() as u8;
                }
            }
        });
    }
    Ok(())
}

/// `text` shortened with "..." to at most `max_w` pixels at `size` (regular weight).
pub fn fit_text(text: &str, max_w: u32, size: f64) -> String {
    let width = |s: &str| text_width(s, size, false);
    if width(text) <= max_w {
        return text.to_string();
    }
    let chars: Vec<char> = text.chars().collect();
    let mut n = chars.len();
    while n > 0 {
        n -= 1;
        let t: String = chars[..n].iter().collect::<String>() + "...";
        if width(&t) <= max_w {
            return t;
        }
    }
    String::new()
}

/// A header line broken at spaces into lines at most `max_w` wide at `size` (continuations
/// indented); a word wider than that stays whole (and is shortened when drawn).
pub fn wrap(line: &str, max_w: u32, size: f64) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    for word in line.split(' ') {
        let next = if cur.is_empty() { word.to_string() } else { format!("{cur} {word}") };
        if cur.is_empty() || text_width(&next, size, false) <= max_w {
            cur = next;
        } else {
            out.push(std::mem::take(&mut cur));
            cur = format!("    {word}");
        }
    }
    out.push(cur);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_text_is_shortened_to_fit() {
        let long = "a very long header line ".repeat(20);
        let t = fit_text(&long, 300, 11.5);
        assert!(t.ends_with("...") && t.len() < long.len());
        assert_eq!(fit_text("short", 300, 11.5), "short");
    }

    #[test]
    fn sizes_are_rounded_to_even_pixels() {
        assert_eq!(even_px(11.0), 12.0);
        assert_eq!(even_px(11.5), 12.0);
        assert_eq!(even_px(13.0), 14.0);
        assert_eq!(even_px(10.0), 10.0);
        assert_eq!(even_px(0.3), 2.0);
        assert_eq!(Label::new("x", 0, 0, 17.0).size, 18.0);
        // Label boxes follow the anchor: a right-aligned label ends at x.
        let l = Label::new("abc", 100, 10, 12.0).right();
        let (x0, y0, x1, y1) = l.bounds();
        assert_eq!(x1, 100);
        assert!(y0 <= 10 && y1 >= 10 + (12.0 / 1.24) as i32, "{y0}..{y1}");
        assert_eq!((x1 - x0) as u32, text_width("abc", 12.0, false));
    }
}
