//! What accuracy costs in time: the `fit_ns` and `eval_ns` columns of every table, measured in a
//! separate pass after scoring (so timing never perturbs the numbers, and the numbers never
//! depend on timing).
//!
//! - `fit_ns`: the median time of one `Encoder::fit` on the case's inputs (one probe or texel),
//!   including allocating and dropping the fitted encoding.
//! - `eval_ns`: the median time of one `Fitted::irradiance`, per normal, over (a subsample of at
//!   most 1024 of) the normals the row was scored on.
//!
//! Method: a call is batched k times, k growing until a batch takes ≥ 25 µs (timer resolution,
//! tens of ns, is then ≤ 0.2%); then the median over R batches (5 ≤ R ≤ 15, as many as fit in
//! about 0.15 ms), divided by k. A measurement costs about 0.2 ms for fast encoders (and 7 fits
//! for slow ones), so the pass stays small next to scoring. Measurements run on the calling thread, one at a time, after the
//! parallel scoring has finished. They are wall-clock figures on a shared machine: they vary
//! run to run, which is why the regression check ignores [`TIMING_COLUMNS`](crate::pipeline::table::TIMING_COLUMNS).
//! `--no-timing` leaves the columns empty (`RunSettings::timing`).

use crate::encoders::encoder::{Encoder, FitInput};
use glam::DVec3;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// A batch must last at least this long.
const MIN_BATCH: Duration = Duration::from_micros(25);
/// Aim for about this much time in the repeated batches of one measurement.
const BUDGET: Duration = Duration::from_micros(150);
const MIN_REPEATS: usize = 5;
const MAX_REPEATS: usize = 15;
/// Normals per eval measurement, at most.
pub const EVAL_NORMALS: usize = 1024;

/// The median time of one call of `f`, in ns (see the module doc for the method).
pub fn median_ns(mut f: impl FnMut()) -> f64 {
    median_ns_with(&mut f, MIN_BATCH, BUDGET)
}

/// [`median_ns`] with explicit batch floor and budget (sweeps time slow operations with a larger
/// budget).
pub fn median_ns_with(f: &mut dyn FnMut(), min_batch: Duration, budget: Duration) -> f64 {
    f(); // warm caches and lazy allocations
    let run = |f: &mut dyn FnMut(), k: u64| {
        let t = Instant::now();
        for _ in 0..k {
            f();
        }
        t.elapsed()
    };
    let mut k = 1u64;
    let mut t = run(f, k);
    while t < min_batch && k < (1 << 24) {
        // Grow towards the floor, at most ×16 a step (a first batch may be unusually fast).
        let grow = ((min_batch.as_secs_f64() / t.as_secs_f64().max(1e-9)).ceil() as u64).clamp(2, 16);
        k *= grow;
        t = run(f, k);
    }
    let repeats = ((budget.as_secs_f64() / t.as_secs_f64().max(1e-12)) as usize).clamp(MIN_REPEATS, MAX_REPEATS);
    let mut times: Vec<f64> = (0..repeats).map(|_| run(f, k).as_secs_f64()).collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2] * 1e9 / k as f64
}

/// Evenly spaced subsample of at most `max` normals (every ⌈n/max⌉-th, in order).
pub fn subsample(normals: &[DVec3], max: usize) -> Vec<DVec3> {
    let step = normals.len().div_ceil(max.max(1)).max(1);
    normals.iter().step_by(step).copied().collect()
}

/// The median ns per normal of evaluating `fit` over `normals`.
pub fn eval_ns(fit: &dyn crate::encoders::encoder::Fitted, normals: &[DVec3]) -> f64 {
    if normals.is_empty() {
        return 0.0;
    }
    let per_batch = median_ns(|| {
        let mut acc = crate::math::colour::Rgb::ZERO;
        for &n in normals {
            acc += fit.irradiance(black_box(n));
        }
        black_box(acc);
    });
    per_batch / normals.len() as f64
}

/// The `fit_ns` and `eval_ns` of one encoder on one case: the median time of one fit from
/// `input`, and the median time per normal of evaluating that fit over `normals` (the caller
/// passes at most [`EVAL_NORMALS`] of the normals the row was scored on, see [`subsample`]).
pub fn measure(encoder: &dyn Encoder, input: &FitInput, normals: &[DVec3]) -> (f64, f64) {
    let fit_ns = median_ns(|| {
        black_box(encoder.fit(black_box(input)));
    });
    let fitted = encoder.fit(input);
    (fit_ns, eval_ns(fitted.as_ref(), normals))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A call that spins for a known time is measured at about that time (generous bounds:
    /// a shared machine), and batching makes a tiny call measurable.
    #[test]
    fn measures_known_durations() {
        let spin = |d: Duration| {
            let t = Instant::now();
            while t.elapsed() < d {
                std::hint::spin_loop();
            }
        };
        let ns = median_ns(|| spin(Duration::from_micros(20)));
        assert!((20_000.0..200_000.0).contains(&ns), "{ns}");
        let tiny = median_ns(|| {
            black_box(1.0f64.sqrt());
        });
        assert!(tiny > 0.0 && tiny < 1000.0, "{tiny}");
    }

    #[test]
    fn subsample_keeps_order_and_bound() {
        let v: Vec<DVec3> = (0..10_000).map(|i| DVec3::splat(i as f64)).collect();
        let s = subsample(&v, 4096);
        assert!(s.len() <= 4096 && s.len() >= 3000);
        assert_eq!(s[0], v[0]);
        assert!(s.windows(2).all(|w| w[0].x < w[1].x));
        assert_eq!(subsample(&v[..10], 4096).len(), 10);
    }
}
