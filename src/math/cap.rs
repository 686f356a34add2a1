//! Spherical caps and their footprints on the rows of a lat-long grid.
//!
//! Every visibility effect probelab simulates is an intersection of caps: the clamped-cosine
//! lobe about a normal n is the cap {ω·n > 0}, the hemisphere effect about a surface normal N is
//! {ω·N > 0}, and the cone effect is {ω·C > cos α}. On the parallel of polar angle φ a cap is
//! one arc of azimuth (possibly empty or the full circle), which is what lets the reference and
//! the SH projection integrate exactly in azimuth.

use crate::math::convention::angles;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// The open cap {ω : ω·axis > cos}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cap {
    /// Unit axis at the cap's centre.
    pub axis: DVec3,
    /// Cosine of the cap's angular radius: the cap holds the directions with ω·axis above it.
    pub cos: f64,
    theta: f64,
    sin_phi: f64,
    cos_phi: f64,
    /// Polar angles where the cap's boundary circle touches a parallel: its arcs change shape
    /// there, so polar quadrature splits rows at these angles.
    breaks: [f64; 2],
}

/// An arc of azimuth [lo, lo + len], len in [0, 2π].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Start azimuth θ in radians.
    pub lo: f64,
    /// Angular length in radians, in [0, 2π].
    pub len: f64,
}

impl Arc {
    /// The whole circle: azimuths [−π, π].
    pub const FULL: Arc = Arc { lo: -PI, len: TAU };
    /// End azimuth in radians, `lo + len` (not wrapped back into [−π, π]).
    pub fn hi(&self) -> f64 {
        self.lo + self.len
    }
}

/// A small set of disjoint arcs (the intersection of caps on one parallel).
#[derive(Clone, Copy, Debug)]
pub struct Arcs {
    arcs: [Arc; 4],
    n: usize,
}

impl Arcs {
    /// The whole circle, as a single arc.
    pub fn full() -> Self {
        Arcs { arcs: [Arc::FULL; 4], n: 1 }
    }
    /// No arc at all.
    pub fn empty() -> Self {
        Arcs { arcs: [Arc::FULL; 4], n: 0 }
    }
    /// The arcs held, in the order they were added.
    pub fn as_slice(&self) -> &[Arc] {
        &self.arcs[..self.n]
    }
    /// Whether no arc is held (the parallel misses the intersection of caps entirely).
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
    fn push(&mut self, a: Arc) {
        if a.len > 0.0 {
            debug_assert!(self.n < 4, "arc set overflow");
            if self.n < 4 {
                self.arcs[self.n] = a;
                self.n += 1;
            }
        }
    }
    /// Intersects every arc of the set with `b`.
    pub fn intersect(&self, b: Option<Arc>) -> Arcs {
        let Some(b) = b else { return Arcs::empty() };
        if b.len >= TAU {
            return *self;
        }
        let mut out = Arcs::empty();
        for a in self.as_slice() {
            if a.len >= TAU {
                out.push(b);
                continue;
            }
            // Work in a's frame: a covers [0, a.len]; b starts at d in [0, 2π).
            let d = (b.lo - a.lo).rem_euclid(TAU);
            if d < a.len {
                out.push(Arc { lo: a.lo + d, len: (d + b.len).min(a.len) - d });
            }
            let wrapped_end = d + b.len - TAU;
            if wrapped_end > 0.0 {
                out.push(Arc { lo: a.lo, len: wrapped_end.min(a.len) });
            }
        }
        out
    }
}

impl Cap {
    /// The cap {ω·axis > cos}. `axis` must be a unit vector.
    pub fn new(axis: DVec3, cos: f64) -> Self {
        debug_assert!((axis.length() - 1.0).abs() < 1e-9, "cap axis must be unit");
        let (theta, phi) = angles(axis);
        let alpha = cos.clamp(-1.0, 1.0).acos();
        let lo = (phi - alpha).abs();
        let hi = PI - (PI - phi - alpha).abs();
        Cap { axis, cos, theta, sin_phi: phi.sin(), cos_phi: phi.cos(), breaks: [lo, hi] }
    }

    /// The hemisphere {ω·n > 0}: the support of the clamped cosine about n.
    pub fn hemisphere(n: DVec3) -> Self {
        Self::new(n, 0.0)
    }

    /// Polar angles at which the cap's arcs change shape (rows are split there).
    pub fn breakpoints(&self) -> [f64; 2] {
        self.breaks
    }

    /// Azimuth of the axis.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// ω·axis = a cos(θ − θ_axis) + b on the parallel of polar angle φ; returns (a, b).
    #[inline]
    pub fn dot_coefficients(&self, sin_phi: f64, cos_phi: f64) -> (f64, f64) {
        (sin_phi * self.sin_phi, cos_phi * self.cos_phi)
    }

    /// The arc of the parallel φ inside the cap; `None` if it is empty.
    #[inline]
    pub fn arc(&self, sin_phi: f64, cos_phi: f64) -> Option<Arc> {
        let (a, b) = self.dot_coefficients(sin_phi, cos_phi);
        // a cos(Δ) + b > c  ⇔  cos Δ > (c − b)/a
        if a <= 1e-300 {
            return if b > self.cos { Some(Arc::FULL) } else { None };
        }
        let t = (self.cos - b) / a;
        if t <= -1.0 {
            Some(Arc::FULL)
        } else if t >= 1.0 {
            None
        } else {
            let half = t.acos();
            Some(Arc { lo: self.theta - half, len: 2.0 * half })
        }
    }

    /// True if the direction is inside the cap.
    pub fn contains(&self, d: DVec3) -> bool {
        d.dot(self.axis) > self.cos
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::convention::direction;

    fn arc_contains(arcs: &Arcs, theta: f64) -> bool {
        arcs.as_slice().iter().any(|a| {
            let d = (theta - a.lo).rem_euclid(TAU);
            d < a.len || a.len >= TAU
        })
    }

    /// The arcs agree with a direct point-in-cap test on a dense grid of directions.
    #[test]
    fn arcs_match_point_membership() {
        let caps = [
            Cap::new(DVec3::new(0.3, 0.5, 0.81).normalize(), 0.0),
            Cap::new(DVec3::new(-0.9, -0.1, 0.2).normalize(), 0.6),
            Cap::new(DVec3::Y, 0.2),
            Cap::new(DVec3::NEG_Y, -0.5),
            Cap::new(DVec3::new(0.0, 0.2, -1.0).normalize(), -0.7),
        ];
        for i in 0..caps.len() {
            for j in 0..caps.len() {
                for pj in 1..60 {
                    let phi = PI * pj as f64 / 60.0 + 0.001;
                    let (s, c) = phi.sin_cos();
                    let arcs = Arcs::full().intersect(caps[i].arc(s, c)).intersect(caps[j].arc(s, c));
                    for ti in 0..200 {
                        let th = -PI + TAU * (ti as f64 + 0.37) / 200.0;
                        let d = direction(th, phi);
                        let want = caps[i].contains(d) && caps[j].contains(d);
                        // Skip points within rounding of a boundary.
                        let margin =
                            (d.dot(caps[i].axis) - caps[i].cos).abs().min((d.dot(caps[j].axis) - caps[j].cos).abs());
                        if margin > 1e-9 {
                            assert_eq!(arc_contains(&arcs, th), want, "caps {i},{j} phi {phi} th {th}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn breakpoints_bound_the_circle() {
        let cap = Cap::new(DVec3::new(0.6, 0.8, 0.0), 0.9);
        let [lo, hi] = cap.breakpoints();
        // Inside (lo, hi) the parallel meets the cap in a proper arc; outside it is full or empty.
        for k in 1..100 {
            let phi = PI * k as f64 / 100.0;
            let arc = cap.arc(phi.sin(), phi.cos());
            let proper = matches!(arc, Some(a) if a.len < TAU);
            assert_eq!(proper, phi > lo && phi < hi, "phi {phi}");
        }
    }
}
