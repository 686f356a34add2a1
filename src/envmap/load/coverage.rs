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

    /// Stores a run of texels from pixel (x0, y) rightwards, recording each as delivered (a
    /// pixel delivered before is remembered as stored twice; the part of the run outside the
    /// layer is remembered as outside and dropped).
    pub(super) fn put(&mut self, x0: usize, y: usize, run: &[Texel]) {
        let height = self.texels.len() / self.width.max(1);
        let inside = if y < height && x0 < self.width { run.len().min(self.width - x0) } else { 0 };
        if inside < run.len() {
            self.outside.get_or_insert((x0 + inside, y));
        }
        if inside == 0 {
            return;
        }
        let k = y * self.width + x0;
        self.texels[k..k + inside].copy_from_slice(&run[..inside]);
        let mut bit = k;
        while bit < k + inside {
            let (word, lo) = (bit / 64, bit % 64);
            let hi = (k + inside - word * 64).min(64);
            let mask = if hi - lo == 64 { u64::MAX } else { ((1u64 << (hi - lo)) - 1) << lo };
            let again = self.seen[word] & mask;
            if again != 0 && self.twice.is_none() {
                let p = word * 64 + again.trailing_zeros() as usize;
                self.twice = Some((p % self.width, p / self.width));
            }
            self.seen[word] |= mask;
            bit = word * 64 + hi;
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn t(v: f32) -> Texel {
        [v, 0.0, 0.0]
    }

    /// Runs of any length and offset, across the 64-pixel words of the record: a 100x3 layer
    /// filled by runs of 7 and the rest, every pixel once, comes back whole and in place.
    #[test]
    fn runs_fill_the_layer_exactly_once() {
        let (w, h) = (100, 3);
        let mut c = Coverage::new(w, h);
        for y in 0..h {
            let mut x = 0;
            while x < w {
                let n = 7.min(w - x);
                let run: Vec<Texel> = (x..x + n).map(|i| t((y * w + i) as f32)).collect();
                c.put(x, y, &run);
                x += n;
            }
        }
        let texels = c.finish().unwrap();
        assert!(texels.iter().enumerate().all(|(i, v)| v[0] == i as f32));
    }

    /// A pixel stored twice is named by its first repeat; a missing one by its first gap; a run
    /// past the right edge or below the last row by its first pixel outside.
    #[test]
    fn repeats_gaps_and_overruns_are_named() {
        let mut c = Coverage::new(130, 2);
        c.put(0, 0, &[t(1.0); 130]);
        c.put(0, 1, &[t(1.0); 130]);
        c.put(70, 1, &[t(2.0); 3]);
        assert!(c.finish().unwrap_err().contains("(x=70, y=1) is stored twice"));

        let mut c = Coverage::new(130, 2);
        c.put(0, 0, &[t(1.0); 130]);
        c.put(0, 1, &[t(1.0); 64]);
        c.put(65, 1, &[t(1.0); 65]);
        assert!(c.finish().unwrap_err().contains("1 pixel(s) are in no chunk, the first at (x=64, y=1)"));

        let mut c = Coverage::new(130, 2);
        c.put(0, 0, &[t(1.0); 130]);
        c.put(100, 1, &[t(1.0); 40]);
        assert!(c.finish().unwrap_err().contains("pixel (x=130, y=1), outside"));
        let mut c = Coverage::new(130, 2);
        c.put(0, 2, &[t(1.0); 4]);
        assert!(c.finish().unwrap_err().contains("pixel (x=0, y=2), outside"));
    }
}
