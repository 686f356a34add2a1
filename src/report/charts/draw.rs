//! What a chart is and how it is drawn: the [`Outcome`] (pixels and SVG, or why not), and
//! `canvas!`, which runs one drawing body on both backends. Colours come from
//! [`crate::report::style`] only.

pub use super::backend::TextBox;
use anyhow::anyhow;
use image::RgbImage;

/// A drawn chart (the same drawing as pixels and as an SVG document of the same size), or the
/// reason it was not drawn.
#[derive(Debug)]
pub enum Outcome {
    /// The chart, drawn.
    Drawn {
        /// The pixels (written as PNG).
        image: RgbImage,
        /// The same drawing as an SVG document.
        svg: String,
        /// The caption the report prints under it.
        caption: String,
        /// Every text the PNG drew, with its box (for the layout checks).
        #[cfg_attr(not(test), allow(dead_code, reason = "read by the layout tests"))]
        text: Vec<TextBox>,
        /// The boxes of the data marks labels must not cover (the cost charts' points).
        #[cfg_attr(not(test), allow(dead_code, reason = "read by the layout tests"))]
        marks: Vec<(i32, i32, i32, i32)>,
    },
    /// Not drawn: why (no data, a single point, …).
    Skipped(String),
}

/// A plotters drawing error as an error of this crate.
pub fn pe<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow!("drawing a chart: {e}")
}

/// Draws a w×h chart twice with the same body, once on each backend: into a fresh bitmap
/// buffer (the PNG's pixels) and into an SVG string (`SVGBackend::with_string`), each wrapped
/// in [`super::backend::Typeset`] (text set by `report::glyphs`). The body sees
/// `$root: &DrawingArea<DB, Shift>` for either backend, so every helper it calls is generic
/// over `DB: DrawingBackend`; it returns `Result<()>`. Evaluates to
/// `Result<(RgbImage, String, Vec<TextBox>)>`, the texts as the bitmap pass placed them. (A
/// macro, because a closure cannot be generic over the backend.)
macro_rules! canvas {
    ($w:expr, $h:expr, |$root:ident| $body:block) => {{
        let (w, h): (u32, u32) = ($w, $h);
        use ::plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};
        $crate::report::text::ensure_font();
        (|| -> ::anyhow::Result<(::image::RgbImage, String, Vec<$crate::report::charts::draw::TextBox>)> {
            use $crate::report::charts::backend::Typeset;
            let placed = ::std::rc::Rc::new(::std::cell::RefCell::new(Vec::new()));
            let mut buf = vec![255u8; (w * h * 3) as usize];
            {
                let bitmap = BitMapBackend::with_buffer(&mut buf, (w, h));
                let area = Typeset::new(bitmap, true, placed.clone()).into_drawing_area();
                let $root = &area;
                (|| -> ::anyhow::Result<()> { $body })()?;
                area.present().map_err($crate::report::charts::draw::pe)?;
            }
            let image = ::image::RgbImage::from_raw(w, h, buf).ok_or_else(|| ::anyhow::anyhow!("chart buffer size"))?;
            let text = placed.borrow().clone();
            let mut svg = String::new();
            {
                let vector = SVGBackend::with_string(&mut svg, (w, h));
                let area = Typeset::new(vector, false, Default::default()).into_drawing_area();
                let $root = &area;
                (|| -> ::anyhow::Result<()> { $body })()?;
                area.present().map_err($crate::report::charts::draw::pe)?;
            }
            Ok((image, svg, text))
        })()
    }};
}
pub(super) use canvas;
