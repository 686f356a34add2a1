//! The ambient cube (Valve, McTaggart 2004, "Half-Life 2 / Source Shading"): six colours on the
//! ±x, ±y, ±z axes, E/π(n) = Σ_axes n_a² · C_{sign(n_a), a}. The peer tool's `AC` and `ACPROJ`
//! (Probulator `ExperimentAmbientCube.cpp`).
//!
//! | id | fit | stored scalars |
//! |---|---|---|
//! | `ambient_cube` | non-negative least squares of E/π over the sphere of normals | 18 |
//! | `ambient_cube_proj` | each colour is E/π at its axis | 18 |
//!
//! The peer fits its cube to its own Monte Carlo irradiance image (5000 importance samples per
//! pixel), and samples that image at the axes for the projection. Here the target is the exact
//! E/π of the visible light ([`crate::reference::radiance::RadianceSource`]): for the
//! least-squares fit, at the pixel centres of a 128×64 lat-long grid of normals with their
//! exact solid angles (the `exact` metric's weighting; `weights = "pixel"` gives every pixel the
//! same weight, the peer's objective, which over-weights the poles). The minimiser is found
//! exactly, per channel: of the 2⁶ supports, the one whose unconstrained solution is
//! non-negative and meets the KKT conditions (the 6×6 normal matrix is positive definite, so it
//! is unique); deterministic, no iteration.
//!
//! On a hemisphere domain the cube is still fitted over the whole sphere of normals, to the
//! light visible under the case's caps. Degenerate inputs: black in, black out; a target that is
//! not finite gives black. The least-squares target is divided by its largest magnitude before
//! the solve (a 1e-300 light must not underflow) and the colours scaled back. The projection
//! clamps its colours at zero (the fallback light of L2 SH alone can have negative E/π; exact
//! E/π never has).
//!
//! TOML keys: `weights` (`ambient_cube` only: `solid_angle`, default, or `pixel`).

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Stored, Unit};
use crate::math::colour::Rgb;
use crate::reference::radiance::latlong_normals;
use anyhow::{bail, Result};
use glam::DVec3;

/// The fitting grid of the least-squares cube (lat-long pixel centres).
pub const FIT_GRID: (usize, usize) = (128, 64);

/// The six basis functions at n: n_x² on the −x or +x column, etc. (the peer's order:
/// −x, +x, −y, +y, −z, +z).
fn weights(n: DVec3) -> [f64; 6] {
    let mut w = [0.0; 6];
    for (a, v) in [n.x, n.y, n.z].into_iter().enumerate() {
        w[2 * a + usize::from(v >= 0.0)] = v * v;
    }
    w
}

/// A fitted cube.
pub struct AmbientCube(pub [Rgb; 6]);

/// The names of the six colours, in the stored (the peer's) order.
pub const FACES: [&str; 6] = ["C_-x", "C_+x", "C_-y", "C_+y", "C_-z", "C_+z"];

impl Fitted for AmbientCube {
    fn irradiance(&self, n: DVec3) -> Rgb {
        weights(n).iter().zip(&self.0).fold(Rgb::ZERO, |acc, (w, c)| acc + *c * *w)
    }
    /// The six colours, E/π, in the order −x, +x, −y, +y, −z, +z: 18 scalars.
    fn stored(&self) -> Stored {
        let mut s = Stored::new(
            "E/pi(n) = n_x^2*C_(sign n_x)x + n_y^2*C_(sign n_y)y + n_z^2*C_(sign n_z)z (McTaggart 2004, the ambient \
             cube): each axis takes the colour of the face its component points to (a zero component contributes \
             nothing); world axes, +Y up (docs/conventions.md section 1)",
        );
        for (name, c) in FACES.iter().zip(&self.0) {
            s.rgb(*name, Unit::Irradiance, *c);
        }
        s
    }
}

/// The ambient cube encoder.
pub struct AmbientCubeEncoder {
    projection: bool,
    pixel_weights: bool,
}

/// Solves min ‖A x − b‖² over x ≥ 0 from the normal equations G x = r (G = AᵀA positive
/// definite, 6×6) by trying every support: the unique KKT point.
fn nnls6(g: &[[f64; 6]; 6], r: &[f64; 6]) -> [f64; 6] {
    let mut best = [0.0; 6];
    let mut best_obj = 0.0; // objective ½xᵀGx − rᵀx at x = 0
    for mask in 1u32..64 {
        let idx: Vec<usize> = (0..6).filter(|i| mask & (1 << i) != 0).collect();
        let k = idx.len();
        // Gaussian elimination with partial pivoting on the k×k sub-system.
        let mut m = vec![vec![0.0; k + 1]; k];
        for (a, &i) in idx.iter().enumerate() {
            for (b, &j) in idx.iter().enumerate() {
                m[a][b] = g[i][j];
            }
            m[a][k] = r[i];
        }
        let mut ok = true;
        for c in 0..k {
            let p = (c..k).max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs())).unwrap_or(c);
            if m[p][c].abs() <= 1e-300 {
                ok = false;
                break;
            }
            m.swap(c, p);
            let (top, rest) = m.split_at_mut(c + 1);
            let pivot = &top[c];
            for row in rest.iter_mut() {
                let f = row[c] / pivot[c];
                for (x, p) in row[c..=k].iter_mut().zip(&pivot[c..=k]) {
                    *x -= f * p;
                }
            }
        }
        if !ok {
            continue;
        }
        let mut xs = vec![0.0; k];
        for a in (0..k).rev() {
            let s: f64 = (a + 1..k).map(|b| m[a][b] * xs[b]).sum();
            xs[a] = (m[a][k] - s) / m[a][a];
        }
        if xs.iter().any(|v| v.is_nan() || *v < 0.0) {
            continue;
        }
        let mut x = [0.0; 6];
        for (a, &i) in idx.iter().enumerate() {
            x[i] = xs[a];
        }
        let gx: [f64; 6] = std::array::from_fn(|i| (0..6).map(|j| g[i][j] * x[j]).sum());
        let obj: f64 = (0..6).map(|i| 0.5 * x[i] * gx[i] - r[i] * x[i]).sum();
        if obj < best_obj {
            best_obj = obj;
            best = x;
        }
    }
    best
}

impl Encoder for AmbientCubeEncoder {
    fn reads_radiance(&self) -> bool {
        true
    }

    fn id(&self) -> &str {
        if self.projection {
            "ambient_cube_proj"
        } else {
            "ambient_cube"
        }
    }
    fn family(&self) -> Family {
        Family::AmbientCube
    }
    fn stored_scalars(&self) -> usize {
        18
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let light = input.light();
        if self.projection {
            let axes = [DVec3::NEG_X, DVec3::X, DVec3::NEG_Y, DVec3::Y, DVec3::NEG_Z, DVec3::Z];
            // Clamped at zero: exact E/π never is negative, but the fallback light of L2 SH alone
            // can dip below zero (the peer's Monte Carlo image cannot).
            let v = light.irradiance_many(&axes);
            return Box::new(AmbientCube(std::array::from_fn(|i| {
                if v[i].is_finite() {
                    v[i].max(Rgb::ZERO)
                } else {
                    Rgb::ZERO
                }
            })));
        }
        let (w, h) = FIT_GRID;
        let target = light.irradiance_latlong(w, h);
        // NNLS is scale covariant: solve for the target divided by its largest magnitude, so that
        // a 1e-300 light does not underflow in the products below.
        let scale = target.iter().map(|e| e.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return Box::new(AmbientCube([Rgb::ZERO; 6]));
        }
        let normals = latlong_normals(w, h);
        let mut g = [[0.0; 6]; 6];
        let mut r = [[0.0; 6]; 3];
        for j in 0..h {
            // The exact solid angle of a pixel of row j: (2π/W)(cos φ_j − cos φ_{j+1}).
            let edge = |k: usize| (std::f64::consts::PI * k as f64 / h as f64).cos();
            let wt = if self.pixel_weights { 1.0 } else { std::f64::consts::TAU / w as f64 * (edge(j) - edge(j + 1)) };
            for i in 0..w {
                let bw = weights(normals[j * w + i]);
                let e = target[j * w + i] / scale;
                for a in 0..6 {
                    if bw[a] == 0.0 {
                        continue;
                    }
                    for b in 0..6 {
                        g[a][b] += wt * bw[a] * bw[b];
                    }
                    for c in 0..3 {
                        r[c][a] += wt * bw[a] * e[c];
                    }
                }
            }
        }
        let x: [[f64; 6]; 3] = std::array::from_fn(|c| nnls6(&g, &r[c]));
        Box::new(AmbientCube(std::array::from_fn(|k| Rgb::new(x[0][k], x[1][k], x[2][k]) * scale)))
    }
    /// Non-negative colours and non-negative weights (NNLS; the projection clamps at zero).
    fn promises_non_negative(&self) -> bool {
        true
    }
    fn is_scale_covariant(&self) -> bool {
        true
    }
}

/// Builds the `ambient_cube` encoder from its settings: ambient cube, NNLS to exact E/pi (peer AC).
/// An unknown or out-of-range setting is an error.
pub fn build_ambient_cube(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let w = p.str_or("weights", "solid_angle")?;
    let pixel_weights = match w.as_str() {
        "solid_angle" => false,
        "pixel" => true,
        _ => bail!("key 'weights': expected 'solid_angle' or 'pixel', got '{w}'"),
    };
    p.finish("ambient_cube")?;
    Ok(Box::new(AmbientCubeEncoder { projection: false, pixel_weights }))
}
/// Builds the `ambient_cube_proj` encoder from its settings: ambient cube, exact E/pi at the axes
/// (peer ACPROJ). An unknown or out-of-range setting is an error.
pub fn build_ambient_cube_proj(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("ambient_cube_proj")?;
    Ok(Box::new(AmbientCubeEncoder { projection: true, pixel_weights: false }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::constant;

    /// A constant radiance A gives E/π = A everywhere; the cube reproduces it exactly (all six
    /// colours A, since Σ n_a² = 1), by both fits.
    #[test]
    fn constant_light_is_exact() {
        let a = Rgb::new(0.5, 1.0, 2.0);
        let sh = constant(a);
        for enc in [
            AmbientCubeEncoder { projection: false, pixel_weights: false },
            AmbientCubeEncoder { projection: false, pixel_weights: true },
            AmbientCubeEncoder { projection: true, pixel_weights: false },
        ] {
            let f = enc.fit(&FitInput::sphere(&sh));
            for n in [DVec3::X, DVec3::new(0.3, -0.5, 0.81).normalize()] {
                assert!((f.irradiance(n) - a).abs().max_element() < 1e-12, "{}", enc.id());
            }
        }
    }

    /// NNLS by hand: G = I, r = (1, −2, 3, 0, −1, 4) → x = max(r, 0).
    #[test]
    fn nnls_of_the_identity_clamps() {
        let mut g = [[0.0; 6]; 6];
        for (i, row) in g.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        assert_eq!(nnls6(&g, &[1.0, -2.0, 3.0, 0.0, -1.0, 4.0]), [1.0, 0.0, 3.0, 0.0, 0.0, 4.0]);
    }
}
