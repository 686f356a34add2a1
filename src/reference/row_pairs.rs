//! What both ways of convolving the exact reference's rows share (`row_convolution`, the direct
//! path; `row_fft`, by FFT): the direct path's driver over the map's rows, in chunks on the
//! thread pool with the cancellation check between rows, and the polar nodes of one input row against one output
//! row with their clamped-cosine kernels (FORMULAS §1), and whether the CPU runs both paths' AVX2
//! copies of their per-row work.

use crate::envmap::moments::RowMoments;
use crate::envmap::PROGRESS_WIDTH;
use crate::io::progress::Progress;
use crate::math::quadrature::for_each_polar_node;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Whether this CPU runs the AVX2 copies of the row kernels (`row_convolution`, `row_fft`):
/// each path's per-input-row work is compiled twice, for baseline x86-64 and with AVX2, the
/// same operations four wide instead of two (no fused multiply-adds), so the values are the
/// same to the bit; each path's tests compare the two.
pub(crate) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Input rows are cut into this many chunks whose partial sums are added in chunk order, so
/// the result does not depend on the thread count.
const CHUNKS: usize = 8;

/// Runs `add(state, j)` for every input row j, the rows cut into [`CHUNKS`] chunks computed in
/// parallel, each with its own state from `new`; returns the states in chunk order (for the
/// caller to add their sums in that order). `stop` is checked before each row: once it says
/// stop, the rest is skipped and the sums are left partial (the caller discards them).
pub(crate) fn over_input_rows<S: Send>(
    moments: &RowMoments,
    new: impl Fn() -> S + Sync,
    add: impl Fn(&mut S, usize) + Sync,
    stop: &(dyn Fn() -> bool + Sync),
) -> Vec<S> {
    let rows = moments.height();
    let chunks = CHUNKS.min(rows);
    let per = rows.div_ceil(chunks);
    let progress = (moments.width() >= PROGRESS_WIDTH).then(|| Progress::new(rows as u64, "exact reference"));
    (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut state = new();
            for j in (c * per)..((c + 1) * per).min(rows) {
                if stop() {
                    break;
                }
                add(&mut state, j);
                if let Some(p) = &progress {
                    p.inc();
                }
            }
            state
        })
        .collect()
}

/// Calls `f(a, b, ws, t)` for each polar node of input row `(p0, p1)` against the output row at
/// polar angle `phi_o` whose kernel is not empty: on the node's parallel the kernel is
/// a·cos(θ − θₒ) + b (a = sin φₒ sin φ, b = cos φₒ cos φ) where positive, `ws` the node's weight
/// times sin φ, and t = −b/a the cosine of its half-arc Δ (t < 1; t ≤ −1 is the whole circle).
#[inline]
pub(crate) fn for_each_node(
    rule: &[(f64, f64)],
    phi_o: f64,
    (p0, p1): (f64, f64),
    mut f: impl FnMut(f64, f64, f64, f64),
) {
    let (sin_o, cos_o) = phi_o.sin_cos();
    let half_pi = 0.5 * PI;
    // Where the kernel's boundary is tangent to a parallel: the rows are split there.
    let breaks = [(phi_o - half_pi).abs(), PI - (half_pi - phi_o).abs()];
    for_each_polar_node(p0, p1, &breaks, rule, |phi, wt| {
        let (s, c) = phi.sin_cos();
        let (a, b) = (sin_o * s, cos_o * c);
        let t = if a > 1e-300 {
            -b / a
        } else if b > 0.0 {
            -2.0
        } else {
            2.0
        };
        if t < 1.0 {
            f(a, b, wt * s, t);
        }
    });
}
