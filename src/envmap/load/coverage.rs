//! Every pixel of an OpenEXR layer stored exactly once: a duplicated, missing or misplaced
//! chunk is refused, never read as default-filled pixels.

use crate::envmap::map::Texel;

/// The pixels of an OpenEXR layer as the decoder delivers them, with a record of which were
/// delivered: every pixel must come exactly once. The `exr` crate reads whatever chunk each
/// offset-table entry points at and places it by the y (or tile) coordinate stored in the chunk,
/// and leaves pixels no chunk covered at their initial value; so a duplicated or corrupt
/// offset, or a chunk whose coordinate was changed, would otherwise read as black rows.
pub(super) struct Coverage {
    width: usize,
    texels: Vec<Texel>,
    /// One bit per pixel: delivered at least once.
    seen: Vec<u64>,
    /// The first pixel delivered twice.
    twice: Option<(usize, usize)>,
    /// The first pixel delivered outside the layer, and how many were.
    outside: Option<(usize, usize)>,
}

impl Coverage {
    pub(super) fn new(width: usize, height: usize) -> Self {
        let n = width * height;
        Coverage { width, texels: vec![[0.0; 3]; n], seen: vec![0; n.div_ceil(64)], twice: None, outside: None }
    }

    pub(super) fn set(&mut self, x: usize, y: usize, t: Texel) {
        let k = y.checked_mul(self.width).and_then(|k| k.checked_add(x)).filter(|_| x < self.width);
        let Some(slot) = k.and_then(|k| self.texels.get_mut(k).map(|s| (k, s))) else {
            self.outside.get_or_insert((x, y));
            return;
        };
        let (k, s) = slot;
        *s = t;
        let (word, bit) = (k / 64, 1u64 << (k % 64));
        if self.seen[word] & bit != 0 {
            self.twice.get_or_insert((x, y));
        }
        self.seen[word] |= bit;
    }

    /// The texels, if every pixel was delivered exactly once; else what went wrong.
    pub(super) fn finish(self) -> Result<Vec<Texel>, String> {
        if let Some((x, y)) = self.twice {
            return Err(format!(
                "pixel (x={x}, y={y}) is stored twice (a duplicated chunk: two offset-table entries point at \
                 one chunk, or a chunk's coordinate is corrupt)"
            ));
        }
        if let Some((x, y)) = self.outside {
            return Err(format!("a chunk holds pixel (x={x}, y={y}), outside the data window"));
        }
        let ones: u64 = self.seen.iter().map(|w| w.count_ones() as u64).sum();
        let missing = self.texels.len() as u64 - ones;
        if missing > 0 {
            let k = (0..self.texels.len()).find(|&k| self.seen[k / 64] & (1 << (k % 64)) == 0).unwrap_or(0);
            let (x, y) = (k % self.width.max(1), k / self.width.max(1));
            return Err(format!(
                "{missing} pixel(s) are in no chunk, the first at (x={x}, y={y}) (a chunk is missing or \
                 its offset or coordinate is corrupt)"
            ));
        }
        Ok(self.texels)
    }
}
