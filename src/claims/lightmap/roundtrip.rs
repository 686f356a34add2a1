//! H6, the HHD ↔ linear-SH round trip (hemispherical-lighting talk 2024: HHD solved in closed
//! form from hemispherical linear SH): random HHDs there and back, the largest errors.

use crate::claims::measure::Measure;
use crate::encoders::lightmap::{hhd_from_linear_sh, linear_sh_of, Basis, Model};
use crate::math::colour::Rgb;
use glam::DVec3;

/// The number of random HHDs of the round trip.
pub const ROUNDTRIP_SAMPLES: usize = 2000;

/// H6 (hemispherical-lighting talk: HHD solved in closed form from hemispherical linear SH):
/// [`ROUNDTRIP_SAMPLES`] random HHDs (d above the horizon) through `linear_sh_of` and back
/// through `hhd_from_linear_sh`: the largest colour error (C_a, C_d; E/π) and direction error
/// (|d′ − d|), one row each.
pub fn hhd_roundtrip() -> Measure {
    // A small deterministic generator (xorshift64*), uniform in [0, 1).
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut unit = || loop {
        let v = DVec3::new(2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0);
        if (0.01..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    };
    let (mut colour, mut dir, mut count) = (0.0f64, 0.0f64, 0);
    while count < ROUNDTRIP_SAMPLES {
        let n = unit();
        let d = unit();
        if d.dot(n) <= 0.01 {
            continue;
        }
        let c_a = Rgb::new(unit().x.abs(), unit().y.abs(), unit().z.abs());
        let c_d = Rgb::new(unit().x.abs(), unit().y.abs(), unit().z.abs()) + Rgb::splat(0.05);
        let m = Model { basis: Basis::Hhd, normal: n, c_a, c_d, d };
        let back = hhd_from_linear_sh(&linear_sh_of(&m), n);
        colour = colour.max((back.c_a - c_a).abs().max_element()).max((back.c_d - c_d).abs().max_element());
        dir = dir.max((back.d - d).length());
        count += 1;
    }
    let mut m = Measure::new(
        "hhd_roundtrip",
        "claim H6, random HHDs (N, d uniform on the sphere with d.N > 0.01; C_a, C_d in [0, 1], C_d >= 0.05) -> \
         their hemispherical linear SH (lightmap::linear_sh_of) -> HHD again (lightmap::from_sh1): max_error = the \
         largest error over the samples, of the colours (max abs over C_a, C_d and channels, E/pi) or of the direction \
         (length of d' - d)",
        &["case", "encoder", "metric", "samples", "max_error", "units"],
    );
    let case = "random_hhd";
    let enc = "hhd_from_linear_sh";
    m.row(vec![case.into(), enc.into(), "colour_max_abs".into(), count.into(), colour.into(), "E/pi".into()]);
    m.row(vec![case.into(), enc.into(), "direction_max_length".into(), count.into(), dir.into(), "unit vector".into()]);
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::measure::Cell;

    fn num(m: &Measure, row: &[Cell], col: &str) -> f64 {
        match &row[m.columns.iter().position(|c| c == col).unwrap()] {
            Cell::Num(x) => *x,
            c => panic!("{col}: {c:?}"),
        }
    }

    /// The round trip is an identity: both errors are rounding (< 1e-9; exact arithmetic
    /// gives 0), over the 2000 samples.
    #[test]
    fn hhd_roundtrip_is_exact() {
        let m = hhd_roundtrip();
        assert_eq!(m.rows.len(), 2);
        for r in &m.rows {
            assert_eq!(num(&m, r, "samples"), 2000.0);
            let e = num(&m, r, "max_error");
            assert!((0.0..1e-9).contains(&e), "{r:?}");
        }
        m.to_csv().unwrap();
    }
}
