//! Mergeable statistics over millions of per-probe errors: exact sums, counts, extrema and a
//! deterministic quantile sketch. Every operation is exact and commutative, so the result does
//! not depend on the order values arrive in, the thread count, the chunk size or how a set is
//! split into shards: merging the shards' states gives bit-for-bit the state of one pass.
//!
//! - [`ExactSum`]: the exact sum of f64 values as a fixed-point big integer (base-2³² digits
//!   covering every f64 from the smallest subnormal up), so addition is associative.
//! - [`Sketch`]: a log-linear histogram (HDR-histogram style) of 128 buckets per power of two
//!   over [2⁻⁶⁴, 2⁶⁴), read straight from the f64 bits (no `ln`, identical on every platform).
//!   A quantile is the midpoint of the bucket holding the nearest-rank value: its relative
//!   error is at most 1/256 ≈ 0.39% (bucket width 1/128 of the octave start). Values below
//!   2⁻⁶⁴ ≈ 5.4e-20 (including 0) share one bucket reported as 0; values at or above 2⁶⁴ share
//!   one reported as the exact maximum. Quantiles are clamped to the exact [min, max].

use serde::{Deserialize, Serialize};

/// Digits of the exact accumulator: bit positions 0..=2098 of a f64 scaled by 2¹⁰⁷⁴, plus
/// headroom for 2⁶³ additions.
const DIGITS: usize = 68;
/// Normalise carries after this many additions (each adds < 2³² to a digit held in an i64).
const CARRY_EVERY: u32 = 1 << 30;

/// The exact sum of f64 values.
#[derive(Clone, Debug)]
pub struct ExactSum {
    digits: [i64; DIGITS],
    pending: u32,
}

impl Default for ExactSum {
    fn default() -> Self {
        ExactSum { digits: [0; DIGITS], pending: 0 }
    }
}

impl PartialEq for ExactSum {
    fn eq(&self, other: &Self) -> bool {
        let (mut a, mut b) = (self.clone(), other.clone());
        a.normalize();
        b.normalize();
        a.digits == b.digits
    }
}

impl ExactSum {
    /// Adds a finite value (non-finite values are the caller's to count; they are ignored here).
    #[inline]
    pub fn add(&mut self, v: f64) {
        if !v.is_finite() || v == 0.0 {
            return;
        }
        let bits = v.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        // v = m · 2^(e − 1074) with m < 2^53 and position p = e ≥ 0.
        let (m, p) = if exp == 0 { (frac, 0) } else { (frac | (1u64 << 52), exp - 1) };
        let (d, s) = ((p / 32) as usize, (p % 32) as u32);
        let wide = (m as u128) << s;
        let sign = if v < 0.0 { -1 } else { 1 };
        for k in 0..3 {
            self.digits[d + k] += sign * ((wide >> (32 * k)) & 0xffff_ffff) as i64;
        }
        self.pending += 1;
        if self.pending >= CARRY_EVERY {
            self.normalize();
        }
    }

    /// Adds another exact sum.
    pub fn merge(&mut self, o: &ExactSum) {
        let mut o = o.clone();
        o.normalize();
        self.normalize();
        for (a, b) in self.digits.iter_mut().zip(o.digits) {
            *a += b;
        }
        self.normalize();
    }

    /// Propagates carries so every digit but the top lies in [0, 2³²).
    fn normalize(&mut self) {
        let mut carry = 0i64;
        for d in self.digits.iter_mut().take(DIGITS - 1) {
            let v = *d + carry;
            carry = v.div_euclid(1 << 32);
            *d = v.rem_euclid(1 << 32);
        }
        self.digits[DIGITS - 1] += carry;
        self.pending = 0;
    }

    /// The sum rounded to f64 (a deterministic function of the exact value: the top three
    /// digits, 64–96 significant bits, combined in f64).
    pub fn value(&self) -> f64 {
        let mut s = self.clone();
        s.normalize();
        let neg = s.digits[DIGITS - 1] < 0;
        if neg {
            for d in s.digits.iter_mut() {
                *d = -*d;
            }
            s.normalize();
        }
        let Some(top) = s.digits.iter().rposition(|&d| d != 0) else {
            return 0.0;
        };
        let mut acc = 0.0f64;
        for i in (top.saturating_sub(2)..=top).rev() {
            acc += s.digits[i] as f64 * pow2(32 * i as i32 - 1074);
        }
        if neg {
            -acc
        } else {
            acc
        }
    }

    /// Non-zero digits of the normalised state, as (index, digit) pairs (for serialisation).
    pub fn to_sparse(&self) -> Vec<(u32, i64)> {
        let mut s = self.clone();
        s.normalize();
        s.digits.iter().enumerate().filter(|(_, &d)| d != 0).map(|(i, &d)| (i as u32, d)).collect()
    }

    /// The inverse of [`Self::to_sparse`]. Accepts exactly what `to_sparse` writes: indices
    /// strictly increasing and below the digit count, every digit but the top one in
    /// [1, 2³²), the top one non-zero and below 2³¹ in magnitude; anything else is an error
    /// naming the pair (a corrupt digit would silently change the sum).
    pub fn from_sparse(v: &[(u32, i64)]) -> anyhow::Result<Self> {
        let mut s = ExactSum::default();
        let mut last = None;
        for &(i, d) in v {
            let i = i as usize;
            anyhow::ensure!(i < DIGITS, "exact-sum digit index {i} out of range (0..{DIGITS})");
            anyhow::ensure!(last.is_none_or(|l| i > l), "exact-sum digit indices must be strictly increasing (at {i})");
            let ok = if i == DIGITS - 1 { d != 0 && d.unsigned_abs() < 1 << 31 } else { (1..1 << 32).contains(&d) };
            anyhow::ensure!(ok, "exact-sum digit {i} = {d} is not a normalised base-2^32 digit");
            s.digits[i] = d;
            last = Some(i);
        }
        Ok(s)
    }

    /// Whether the sum is negative.
    pub fn is_negative(&self) -> bool {
        let mut s = self.clone();
        s.normalize();
        s.digits[DIGITS - 1] < 0
    }
}

/// 2^e as f64, for e in the f64 range (subnormal results allowed).
fn pow2(e: i32) -> f64 {
    // Split so neither factor overflows or flushes to zero early.
    let half = e / 2;
    2f64.powi(half) * 2f64.powi(e - half)
}

/// Sub-buckets per power of two.
const SUB_BITS: u32 = 7;
const SUB: usize = 1 << SUB_BITS;
/// Exponent range of the bucketed values: [2^E_MIN, 2^E_MAX).
const E_MIN: i32 = -64;
const E_MAX: i32 = 64;
const BUCKETS: usize = (E_MAX - E_MIN) as usize * SUB;

/// The bound on the relative error of [`Sketch::quantile`] for values in [2⁻⁶⁴, 2⁶⁴).
#[cfg(test)]
pub const SKETCH_RELATIVE_ERROR: f64 = 1.0 / (2 * SUB) as f64;

/// A mergeable quantile sketch of non-negative values (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Sketch {
    counts: Vec<u64>,
    /// Values below 2^E_MIN (including 0).
    under: u64,
    /// Values at or above 2^E_MAX.
    over: u64,
}

impl Default for Sketch {
    fn default() -> Self {
        Sketch { counts: vec![0; BUCKETS], under: 0, over: 0 }
    }
}

impl Sketch {
    /// The bucket of a finite non-negative value: None for the under/overflow buckets.
    fn bucket(v: f64) -> Result<usize, bool> {
        let bits = v.to_bits();
        let e = ((bits >> 52) & 0x7ff) as i32 - 1023;
        if v < pow2(E_MIN) {
            return Err(false);
        }
        if e >= E_MAX {
            return Err(true);
        }
        let sub = ((bits >> (52 - SUB_BITS)) as usize) & (SUB - 1);
        Ok((e - E_MIN) as usize * SUB + sub)
    }

    /// The midpoint of bucket `i`.
    fn representative(i: usize) -> f64 {
        let e = (i / SUB) as i32 + E_MIN;
        let sub = (i % SUB) as f64;
        pow2(e) * (1.0 + (sub + 0.5) / SUB as f64)
    }

    /// Adds a finite non-negative value (the caller counts anything else).
    #[inline]
    pub fn add(&mut self, v: f64) {
        match Self::bucket(v) {
            Ok(i) => self.counts[i] += 1,
            Err(false) => self.under += 1,
            Err(true) => self.over += 1,
        }
    }

    /// Adds another sketch's counts; an error (and no change) if a count would overflow.
    pub fn merge(&mut self, o: &Sketch) -> anyhow::Result<()> {
        let overflow = || anyhow::anyhow!("sketch counts overflow 64 bits");
        let mut counts = self.counts.clone();
        for (a, b) in counts.iter_mut().zip(&o.counts) {
            *a = a.checked_add(*b).ok_or_else(overflow)?;
        }
        let under = self.under.checked_add(o.under).ok_or_else(overflow)?;
        let over = self.over.checked_add(o.over).ok_or_else(overflow)?;
        *self = Sketch { counts, under, over };
        Ok(())
    }

    /// The number of values; None if it exceeds 64 bits (only a corrupt state can).
    pub fn count(&self) -> Option<u64> {
        self.counts.iter().try_fold(self.under.checked_add(self.over)?, |a, &c| a.checked_add(c))
    }

    /// The nearest-rank q-quantile (rank ⌈q·n⌉, at least 1), as a bucket midpoint clamped to
    /// [min, max] (ranks 1 and n give min and max exactly); None when empty.
    pub fn quantile(&self, q: f64, min: f64, max: f64) -> Option<f64> {
        let n = self.count()?;
        if n == 0 {
            return None;
        }
        let rank = ((q.clamp(0.0, 1.0) * n as f64).ceil() as u64).max(1);
        // The extreme ranks are known exactly.
        if rank == n {
            return Some(max);
        }
        if rank == 1 {
            return Some(min);
        }
        let mut seen = self.under;
        if seen >= rank {
            return Some(min.max(0.0).min(max));
        }
        for (i, &c) in self.counts.iter().enumerate() {
            seen += c;
            if seen >= rank {
                return Some(Self::representative(i).clamp(min, max));
            }
        }
        Some(max)
    }

    /// Non-empty buckets as (index, count) pairs, then the under/overflow counts.
    pub fn to_sparse(&self) -> (Vec<(u32, u64)>, u64, u64) {
        let v = self.counts.iter().enumerate().filter(|(_, &c)| c > 0).map(|(i, &c)| (i as u32, c)).collect();
        (v, self.under, self.over)
    }

    /// The inverse of [`Self::to_sparse`]: bucket indices strictly increasing and in range,
    /// counts non-zero, the total within 64 bits.
    pub fn from_sparse(v: &[(u32, u64)], under: u64, over: u64) -> anyhow::Result<Self> {
        let mut s = Sketch { under, over, ..Default::default() };
        let mut last = None;
        for &(i, c) in v {
            let i = i as usize;
            anyhow::ensure!(i < BUCKETS, "sketch bucket {i} out of range (0..{BUCKETS})");
            anyhow::ensure!(last.is_none_or(|l| i > l), "sketch buckets must be strictly increasing (at {i})");
            anyhow::ensure!(c > 0, "sketch bucket {i} has count 0 (empty buckets are not written)");
            s.counts[i] = c;
            last = Some(i);
        }
        anyhow::ensure!(s.count().is_some(), "sketch counts overflow 64 bits");
        Ok(s)
    }
}

/// Count, exact sum, extrema and quantile sketch of one non-negative quantity.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Summary {
    /// Finite values seen.
    pub count: u64,
    /// Non-finite or negative values seen (a bug upstream; reported, never folded into the
    /// figures).
    pub invalid: u64,
    /// The exact sum of the valid values.
    pub sum: ExactSum,
    /// Smallest valid value seen (0 while none has been).
    pub min: f64,
    /// Largest valid value seen (0 while none has been).
    pub max: f64,
    /// Quantile sketch of the valid values.
    pub sketch: Sketch,
}

impl Summary {
    /// Adds one value: finite non-negative values are folded in, anything else only counted in
    /// `invalid`.
    #[inline]
    pub fn add(&mut self, v: f64) {
        if !v.is_finite() || v < 0.0 {
            self.invalid += 1;
            return;
        }
        if self.count == 0 {
            self.min = v;
            self.max = v;
        } else {
            self.min = self.min.min(v);
            self.max = self.max.max(v);
        }
        self.count += 1;
        self.sum.add(v);
        self.sketch.add(v);
    }

    /// Adds another summary; an error (and no change) if a count would overflow.
    pub fn merge(&mut self, o: &Summary) -> anyhow::Result<()> {
        let count = self.count.checked_add(o.count).ok_or_else(|| anyhow::anyhow!("value count overflows 64 bits"))?;
        let invalid =
            self.invalid.checked_add(o.invalid).ok_or_else(|| anyhow::anyhow!("invalid count overflows 64 bits"))?;
        self.sketch.merge(&o.sketch)?;
        if o.count > 0 {
            if self.count == 0 {
                self.min = o.min;
                self.max = o.max;
            } else {
                self.min = self.min.min(o.min);
                self.max = self.max.max(o.max);
            }
        }
        self.count = count;
        self.invalid = invalid;
        self.sum.merge(&o.sum);
        Ok(())
    }

    /// The mean (exact sum rounded, divided by the count); None when no valid value was seen
    /// (a statistic over nothing is empty, never 0), or when the sum of valid values exceeds
    /// the f64 range.
    pub fn mean(&self) -> Option<f64> {
        if self.count == 0 {
            return None;
        }
        let m = self.sum.value() / self.count as f64;
        m.is_finite().then_some(m)
    }

    /// The exact minimum and maximum of the valid values; None when there were none.
    pub fn extrema(&self) -> Option<(f64, f64)> {
        (self.count > 0).then_some((self.min, self.max))
    }

    /// The nearest-rank q-quantile of the valid values (q in [0, 1]), clamped to the exact extrema;
    /// None when no valid value was seen. See [`Sketch::quantile`].
    pub fn quantile(&self, q: f64) -> Option<f64> {
        self.sketch.quantile(q, self.min, self.max)
    }
}

/// The serialised form of a [`Summary`] (TOML-friendly: sparse digits and buckets; floats are
/// written in Rust's shortest round-trip form).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SummaryState {
    /// Valid (finite, non-negative) values summarised.
    pub count: u64,
    /// Non-finite or negative values seen and left out.
    pub invalid: u64,
    /// Smallest valid value (0 when there were none).
    pub min: f64,
    /// Largest valid value (0 when there were none).
    pub max: f64,
    /// The exact sum: (digit index, base-2³² digit) pairs of the value scaled by 2¹⁰⁷⁴.
    pub sum_digits: Vec<(u32, i64)>,
    /// Sketch buckets: (index, count) pairs.
    pub buckets: Vec<(u32, u64)>,
    /// Sketch values below the bucketed range (including 0).
    pub under: u64,
    /// Sketch values at or above the bucketed range.
    pub over: u64,
}

impl From<&Summary> for SummaryState {
    fn from(s: &Summary) -> Self {
        let (buckets, under, over) = s.sketch.to_sparse();
        SummaryState {
            count: s.count,
            invalid: s.invalid,
            min: s.min,
            max: s.max,
            sum_digits: s.sum.to_sparse(),
            buckets,
            under,
            over,
        }
    }
}

impl SummaryState {
    /// The summary this state describes, checked for consistency: a sketch holding exactly
    /// `count` values, with its under/overflow buckets matching the extrema; 0 ≤ min ≤ max, both
    /// finite (0 and 0 when empty); a non-negative exact sum between count·min and count·max
    /// (every value lies between them). A state that fails any check is corrupt, not merged.
    pub fn to_summary(&self) -> anyhow::Result<Summary> {
        let sketch = Sketch::from_sparse(&self.buckets, self.under, self.over)?;
        let held = sketch.count().unwrap_or(u64::MAX);
        anyhow::ensure!(held == self.count, "sketch holds {held} values but count is {}", self.count);
        let sum = ExactSum::from_sparse(&self.sum_digits)?;
        let (min, max) = (self.min, self.max);
        if self.count == 0 {
            anyhow::ensure!(min == 0.0 && max == 0.0 && self.sum_digits.is_empty(), "no values, but a min, max or sum");
        } else {
            anyhow::ensure!(
                min.is_finite() && max.is_finite() && 0.0 <= min && min <= max,
                "min {min} and max {max} must be finite with 0 <= min <= max"
            );
            anyhow::ensure!(!sum.is_negative(), "the sum of non-negative values is negative");
            let (n, v) = (self.count as f64, sum.value());
            // The f64 sum is within a relative 2⁻⁶³ of the exact one; n·min, n·max within 2⁻⁵².
            let slack = 1.0 + 1e-12;
            anyhow::ensure!(
                v >= n * min / slack && v <= n * max * slack,
                "the sum {v:e} of {} values is outside count*min..count*max ({:e}..{:e})",
                self.count,
                n * min,
                n * max
            );
            anyhow::ensure!(
                (self.under > 0) == (min < pow2(E_MIN)),
                "the sketch's underflow count {} does not match min {min}",
                self.under
            );
            anyhow::ensure!(
                (self.over > 0) == (max >= pow2(E_MAX)),
                "the sketch's overflow count {} does not match max {max}",
                self.over
            );
        }
        Ok(Summary { count: self.count, invalid: self.invalid, sum, min, max, sketch })
    }
}

/// The median of `v` (the mean of the two middle values for an even count); `None` when `v`
/// is empty. The one median of the crate: summaries, claims ratios and sweep charts use it.
pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    Some(if n % 2 == 1 { s[n / 2] } else { 0.5 * (s[n / 2 - 1] + s[n / 2]) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic values spanning many octaves, some tiny, some huge.
    fn values(n: usize) -> Vec<f64> {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let u = (x >> 11) as f64 / (1u64 << 53) as f64;
                10f64.powf(-12.0 + 20.0 * u)
            })
            .collect()
    }

    #[test]
    fn exact_sum_is_order_independent_and_matches_integers() {
        let v = values(5000);
        let (mut a, mut b) = (ExactSum::default(), ExactSum::default());
        v.iter().for_each(|&x| a.add(x));
        v.iter().rev().for_each(|&x| b.add(x));
        assert_eq!(a, b);
        assert_eq!(a.value().to_bits(), b.value().to_bits());
        // Cancellation that f64 summation gets wrong: 1e16 + 1 − 1e16 = 1.
        let mut c = ExactSum::default();
        for x in [1e16, 1.0, -1e16] {
            c.add(x);
        }
        assert_eq!(c.value(), 1.0);
        assert_eq!((1e16 + 1.0) - 1e16, 0.0, "f64 loses it");
        // Integers sum exactly; extremes of the range round-trip.
        let mut d = ExactSum::default();
        (1..=1000).for_each(|i| d.add(i as f64));
        assert_eq!(d.value(), 500_500.0);
        for x in [f64::MIN_POSITIVE, 5e-324, f64::MAX, 1.0 / 3.0, -2.5] {
            let mut e = ExactSum::default();
            e.add(x);
            assert_eq!(e.value(), x, "{x:e}");
            assert_eq!(ExactSum::from_sparse(&e.to_sparse()).unwrap(), e);
        }
    }

    #[test]
    fn exact_sum_is_close_to_the_true_sum() {
        let v = values(1000);
        let mut s = ExactSum::default();
        v.iter().for_each(|&x| s.add(x));
        // Compensated reference (Neumaier) is accurate to a few ulps here.
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for &x in &v {
            let t = sum + x;
            comp += if sum.abs() >= x.abs() { (sum - t) + x } else { (x - t) + sum };
            sum = t;
        }
        let want = sum + comp;
        assert!((s.value() - want).abs() <= 4.0 * f64::EPSILON * want, "{} vs {want}", s.value());
    }

    #[test]
    fn sketch_quantiles_within_the_stated_error() {
        let v = values(20_001);
        let mut s = Summary::default();
        v.iter().for_each(|&x| s.add(x));
        let mut sorted = v.clone();
        sorted.sort_by(f64::total_cmp);
        for q in [0.0, 0.01, 0.25, 0.5, 0.9, 0.95, 0.99, 1.0] {
            let rank = ((q * v.len() as f64).ceil() as usize).max(1);
            let exact = sorted[rank - 1];
            let got = s.quantile(q).unwrap();
            assert!((got - exact).abs() <= SKETCH_RELATIVE_ERROR * exact, "q={q}: {got} vs {exact}");
        }
        assert_eq!(s.quantile(1.0), Some(*sorted.last().unwrap()));
        assert_eq!(s.min, sorted[0]);
    }

    #[test]
    fn zeros_huge_and_invalid_values() {
        let mut s = Summary::default();
        for v in [0.0, 0.0, 1e-30, 3.0, 1e25, f64::NAN, f64::INFINITY, -1.0] {
            s.add(v);
        }
        assert_eq!((s.count, s.invalid), (5, 3));
        assert_eq!(s.quantile(0.2), Some(0.0));
        assert_eq!(s.quantile(0.6), Some(0.0), "1e-30 is in the under bucket, reported as 0");
        assert_eq!(s.quantile(1.0), Some(1e25));
        assert!((s.quantile(0.8).unwrap() - 3.0).abs() <= 3.0 * SKETCH_RELATIVE_ERROR);
    }

    /// Splitting a set in two and merging gives exactly the one-pass state, for any split.
    #[test]
    fn merging_is_exact() {
        let v = values(3000);
        let mut whole = Summary::default();
        v.iter().for_each(|&x| whole.add(x));
        for cut in [0, 1, 1234, 2999, 3000] {
            let (mut a, mut b) = (Summary::default(), Summary::default());
            v[..cut].iter().for_each(|&x| a.add(x));
            v[cut..].iter().for_each(|&x| b.add(x));
            a.merge(&b).unwrap();
            assert_eq!(a, whole, "cut {cut}");
            assert_eq!(a.mean().unwrap().to_bits(), whole.mean().unwrap().to_bits());
        }
        let state = SummaryState::from(&whole);
        let text = toml::to_string(&state).unwrap();
        let back: SummaryState = toml::from_str(&text).unwrap();
        assert_eq!(back, state);
        assert_eq!(back.to_summary().unwrap(), whole);
    }
}
