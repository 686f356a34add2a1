//! The backend every chart is drawn on: plotters' bitmap or SVG backend, with its text set by
//! [`crate::report::glyphs`] (pixels for the bitmap; the SVG keeps `<text>` elements) and
//! measured the same way on both, and every text's box recorded ([`TextBox`]) so that the
//! layout can be checked: no label over another, none off the canvas.

use super::super::glyphs;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind, FontStyle,
};
use std::cell::RefCell;
use std::rc::Rc;

/// A text a chart drew: the text and its box (x0, y0, x1, y1) on the canvas, rotation applied.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextBox {
    /// The text.
    pub text: String,
    /// Its box on the canvas, in pixels: from 0.76 em above the baseline to 0.24 em below,
    /// its advance width across.
    pub rect: (i32, i32, i32, i32),
}

/// A plotters backend whose text is set by [`glyphs`] and recorded.
pub struct Typeset<B> {
    inner: B,
    /// Whether text is drawn as pixels here (bitmap) or handed to the inner backend (SVG).
    raster: bool,
    placed: Rc<RefCell<Vec<TextBox>>>,
}

impl<B: DrawingBackend> Typeset<B> {
    /// `inner`, with its text rasterised here (`raster`) or left to it, every box pushed on
    /// `placed`.
    pub fn new(inner: B, raster: bool, placed: Rc<RefCell<Vec<TextBox>>>) -> Self {
        Typeset { inner, raster, placed }
    }
}

fn bold<S: BackendTextStyle>(style: &S) -> bool {
    matches!(style.style(), FontStyle::Bold)
}

impl<B: DrawingBackend> DrawingBackend for Typeset<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<B::ErrorType>> {
        let e = glyphs::em(style.size());
        Ok((glyphs::width(text, style.size(), bold(style)), e.ceil() as u32))
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        let (size, heavy) = (style.size(), bold(style));
        let anchor = (style.anchor().h_pos, style.anchor().v_pos);
        let turn = style.transform();
        let (x0, y0, x1, y1) = glyphs::line_box(text, size, heavy, anchor, (0, 0));
        let (a, b) = (turn.transform(x0, y0), turn.transform(x1, y1));
        let rect = (pos.0 + a.0.min(b.0), pos.1 + a.1.min(b.1), pos.0 + a.0.max(b.0), pos.1 + a.1.max(b.1));
        let placed = TextBox { text: text.to_string(), rect };
        // plotters' log axes may hand the same tick label twice; drawn once.
        if self.placed.borrow().contains(&placed) {
            return Ok(());
        }
        self.placed.borrow_mut().push(placed);
        if !self.raster {
            return self.inner.draw_text(text, style, pos);
        }
        let colour = style.color();
        let mut result = Ok(());
        glyphs::rasterise(text, size, heavy, anchor, |x, y, c| {
            let (x, y) = turn.transform(x, y);
            if result.is_ok() {
                let ink = BackendColor { alpha: colour.alpha * c as f64, rgb: colour.rgb };
                result = self.inner.draw_pixel((pos.0 + x, pos.1 + y), ink);
            }
        });
        result
    }
}
