//! The one pseudo-random generator of the unit tests (xorshift64): deterministic inputs, the
//! same on every machine. Test-only; the probe synthesiser has its own generator
//! (`pipeline::probeset::synth::SplitMix64`), which is part of the product.

use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use glam::{DMat3, DQuat, DVec3};
use std::f64::consts::PI;

/// Deterministic pseudo-random numbers in [−1, 1) (xorshift), for test inputs.
pub struct Rng(u64);
impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    /// Uniform in [0, 1).
    pub fn uniform01(&mut self) -> f64 {
        0.5 * (self.next() + 1.0)
    }
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.next(), self.next(), self.next());
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
    pub fn sh(&mut self) -> Sh9 {
        Sh9(std::array::from_fn(|_| Rgb::new(self.next(), self.next(), self.next())))
    }
    pub fn rotation(&mut self) -> DMat3 {
        DMat3::from_quat(DQuat::from_axis_angle(self.unit(), PI * self.next()))
    }
}
