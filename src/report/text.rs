//! Text in the pictures: the bundled font (DejaVu Sans, so no system font is needed), text
//! labels drawn into an image with plotters, and shortening a line to a width.

use anyhow::{anyhow, Result};
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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
    pub text: String,
    pub x: i32,
    pub y: i32,
    pub size: f64,
    pub bold: bool,
    pub anchor: HPos,
    pub color: RGBColor,
}

impl Label {
    pub fn new(text: impl Into<String>, x: u32, y: u32, size: f64) -> Self {
        Label { text: text.into(), x: x as i32, y: y as i32, size, bold: false, anchor: HPos::Left, color: INK }
    }
    pub fn bold(mut self) -> Self {
        self.bold = true;
        self
    }
    pub fn centre(mut self) -> Self {
        self.anchor = HPos::Center;
        self
    }
    pub fn grey(mut self) -> Self {
        self.color = GREY_INK;
        self
    }
}

/// Draws text into an RGB image with plotters (the image's pixels are the backend's buffer).
pub fn draw_labels(img: &mut RgbImage, labels: &[Label]) -> Result<()> {
    ensure_font();
    let (w, h) = img.dimensions();
    let buf: &mut [u8] = std::ops::DerefMut::deref_mut(img);
    let root = BitMapBackend::with_buffer(buf, (w, h)).into_drawing_area();
    for l in labels {
        let style = TextStyle::from((FONT, l.size, if l.bold { FontStyle::Bold } else { FontStyle::Normal }))
            .color(&l.color)
            .pos(Pos::new(l.anchor, VPos::Top));
        root.draw_text(&l.text, &style, (l.x, l.y)).map_err(|e| anyhow!("drawing text '{}': {e}", l.text))?;
    }
    root.present().map_err(|e| anyhow!("drawing text: {e}"))?;
    Ok(())
}

/// `text` shortened with "..." to at most `max_w` pixels at `size` (regular weight).
pub fn fit_text(text: &str, max_w: u32, size: f64) -> String {
    ensure_font();
    let font = FontDesc::new(FontFamily::Name(FONT), size, FontStyle::Normal);
    let width = |s: &str| font.box_size(s).map(|b| b.0).unwrap_or(0);
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
}
