//! A long sheet split into pages: no figure is taller than [`MAX_PAGE_H`] pixels at scale 1, so
//! a sheet with more rows than fit is drawn as several pages, each with the whole header (title
//! marked "page k of n", the thumbnail, the colour bar) and an even share of the rows; and the
//! file name of each page.

use super::layout::{COLHEAD_H, HEADER_H, MARGIN, ROW_H};
use super::render::Sheet;
use crate::report::names::file_safe;

/// The tallest figure, in pixels at scale 1.
pub const MAX_PAGE_H: u32 = 2400;

/// The most rows of spheres a page holds at scale 1 under [`MAX_PAGE_H`] (at least one).
pub fn rows_per_page() -> usize {
    ((MAX_PAGE_H - HEADER_H - COLHEAD_H - MARGIN) / ROW_H).max(1) as usize
}

/// How many pages `rows` rows take, and how many rows each page holds (the rows shared evenly,
/// the earlier pages taking one more when they do not divide).
pub fn page_rows(rows: usize) -> Vec<usize> {
    let pages = rows.div_ceil(rows_per_page()).max(1);
    (0..pages).map(|p| rows / pages + usize::from(p < rows % pages)).collect()
}

/// The file of page `page` (from 1) of `pages` of the sheet of `map`: `sheet_<map>.png` for a
/// sheet of one page, else `sheet_<map>_p<page>.png`.
pub fn page_file(map: &str, page: usize, pages: usize) -> String {
    if pages <= 1 {
        format!("sheet_{}.png", file_safe(map))
    } else {
        format!("sheet_{}_p{page}.png", file_safe(map))
    }
}

/// Which of `maps` a sheet file is of, and its page (1 for a sheet of one page); None for a
/// file of no listed map.
pub fn file_page(file: &str, maps: &[String]) -> Option<(usize, usize)> {
    maps.iter().enumerate().find_map(|(i, m)| {
        let rest = file.strip_prefix(&format!("sheet_{}", file_safe(m)))?.strip_suffix(".png")?;
        if rest.is_empty() {
            return Some((i, 1));
        }
        let page = rest.strip_prefix("_p")?;
        (!page.is_empty() && page.bytes().all(|b| b.is_ascii_digit())).then(|| (i, page.parse().unwrap_or(0)))
    })
}

impl Sheet {
    /// The sheet as its pages ([`page_rows`]); a sheet that fits is its own one page.
    pub fn pages(&self) -> Vec<Sheet> {
        let split = page_rows(self.rows.len());
        if split.len() <= 1 {
            return vec![self.clone()];
        }
        let mut start = 0;
        split
            .iter()
            .enumerate()
            .map(|(p, &n)| {
                let mut page = self.clone();
                page.rows = self.rows[start..start + n].to_vec();
                page.title = format!("{} (page {} of {})", self.title, p + 1, split.len());
                start += n;
                page
            })
            .collect()
    }
}
