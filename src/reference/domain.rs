//! Output domains: the set of normals n′ an encoder is scored over, with their solid-angle
//! weights, and the surface orientations (normals N) of hemisphere experiments.

use crate::envmap::LatLong;
use crate::math::convention::direction_of;
use anyhow::{bail, Result};
use glam::{DQuat, DVec3};

/// Where the error is measured.
#[derive(Clone, Debug, PartialEq)]
pub enum Domain {
    /// Every normal of the sphere.
    Sphere,
    /// Normals n′ with n′·N > 0: a surface with normal N, normal-mapped.
    Hemisphere {
        /// The surface normal N (unit, world space).
        normal: DVec3,
    },
}

/// A set of output normals with solid-angle weights summing to the domain's solid angle.
#[derive(Clone, Debug)]
pub struct OutputGrid {
    /// Unit output normals n′, world space.
    pub normals: Vec<DVec3>,
    /// Solid-angle weight of each normal (steradians), in the order of `normals`.
    pub weights: Vec<f64>,
    /// The world-space lat-long grid these normals form, when they do (sphere domain), which
    /// lets the reference use its fast path.
    pub latlong: Option<LatLong>,
    /// Resolution of the lat-long grid the normals come from (for labels).
    pub resolution: (usize, usize),
}

impl Domain {
    /// The output normals at lat-long resolution (W, H) (pixel centres, exact cell solid
    /// angles). A hemisphere uses the upper H/2 rows of the same grid in a frame whose pole is N.
    pub fn output_grid(&self, res: (usize, usize)) -> OutputGrid {
        let g = LatLong::new(res.0, res.1);
        match self {
            Domain::Sphere => {
                let mut normals = Vec::with_capacity(res.0 * res.1);
                let mut weights = Vec::with_capacity(res.0 * res.1);
                // `g.direction(i, j)` to the bit, its sines and cosines taken once a column and
                // once a row.
                let columns: Vec<(f64, f64)> = (0..g.width).map(|i| g.theta_centre(i).sin_cos()).collect();
                for j in 0..g.height {
                    let w = g.solid_angle(j);
                    let row = g.phi_centre(j).sin_cos();
                    normals.extend(columns.iter().map(|&column| direction_of(column, row)));
                    weights.extend(std::iter::repeat_n(w, g.width));
                }
                OutputGrid { normals, weights, latlong: Some(g), resolution: res }
            }
            Domain::Hemisphere { normal } => {
                let rot = frame_to(*normal);
                let rows = g.height / 2;
                let mut normals = Vec::with_capacity(res.0 * rows);
                let mut weights = Vec::with_capacity(res.0 * rows);
                for j in 0..rows {
                    let w = g.solid_angle(j);
                    for i in 0..g.width {
                        normals.push((rot * g.direction(i, j)).normalize());
                        weights.push(w);
                    }
                }
                OutputGrid { normals, weights, latlong: None, resolution: (res.0, rows) }
            }
        }
    }
}

/// The rotation taking +Y (the lat-long pole) to `n`.
pub fn frame_to(n: DVec3) -> DQuat {
    DQuat::from_rotation_arc(DVec3::Y, n.normalize())
}

/// A named surface normal N.
#[derive(Clone, Debug, PartialEq)]
pub struct Orientation {
    /// Label used in tables: "+y", "fib32#07".
    pub label: String,
    /// The set it came from: "+y", "axes6", "fibonacci32", "up".
    pub set: String,
    /// The surface normal N (unit, world space).
    pub normal: DVec3,
}

/// Parses an axis name: +x, -x, +y, -y, +z, -z.
pub fn parse_axis(s: &str) -> Result<DVec3> {
    Ok(match s {
        "+x" | "x" => DVec3::X,
        "-x" => DVec3::NEG_X,
        "+y" | "y" => DVec3::Y,
        "-y" => DVec3::NEG_Y,
        "+z" | "z" => DVec3::Z,
        "-z" => DVec3::NEG_Z,
        _ => bail!("unknown axis '{}' (expected one of +x, -x, +y, -y, +z, -z)", crate::math::echo::value(s)),
    })
}

/// `n` points of a spherical Fibonacci set (Keinert et al. 2015), deterministic.
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = (1.0 + 5f64.sqrt()) / 2.0;
    (0..n)
        .map(|i| {
            let y = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = 2.0 * std::f64::consts::PI * (i as f64 / golden).fract();
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// Expands an orientation name or set: an axis (+y …), `up` (= +y), `axes6`, or
/// `fibonacciN` (e.g. fibonacci32).
pub fn expand_orientations(name: &str) -> Result<Vec<Orientation>> {
    let shown = crate::math::echo::value(name);
    let one = |label: &str, set: &str, normal| Orientation { label: label.into(), set: set.into(), normal };
    if name == "up" {
        return Ok(vec![one("+y", "up", DVec3::Y)]);
    }
    if name == "axes6" {
        return ["+x", "-x", "+y", "-y", "+z", "-z"].iter().map(|a| Ok(one(a, "axes6", parse_axis(a)?))).collect();
    }
    if let Some(n) = name.strip_prefix("fibonacci") {
        let n: usize = n.parse().map_err(|_| anyhow::anyhow!("'{shown}': expected fibonacciN, e.g. fibonacci32"))?;
        if n == 0 || n > 4096 {
            bail!("'{shown}': the Fibonacci set size must be 1..=4096");
        }
        return Ok(fibonacci_sphere(n)
            .into_iter()
            .enumerate()
            .map(|(i, v)| one(&format!("fib{n}#{i:02}"), name, v))
            .collect());
    }
    parse_axis(name).map(|v| vec![one(name, name, v)]).map_err(|_| {
        anyhow::anyhow!("unknown orientation '{shown}' (expected +x, -x, +y, -y, +z, -z, up, axes6 or fibonacciN)")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sphere_normals_are_the_grid_directions() {
        for (w, h) in [(1, 1), (5, 3), (256, 128)] {
            let g = LatLong::new(w, h);
            let grid = Domain::Sphere.output_grid((w, h));
            for (k, n) in grid.normals.iter().enumerate() {
                assert_eq!(*n, g.direction(k % w, k / w), "{w}x{h} normal {k}");
            }
            assert_eq!(grid.normals.len(), w * h);
        }
    }

    #[test]
    fn weights_sum_to_domain_solid_angle() {
        let s = Domain::Sphere.output_grid((64, 32));
        assert!((s.weights.iter().sum::<f64>() - 4.0 * PI).abs() < 1e-12);
        for n in [DVec3::Y, DVec3::NEG_Y, DVec3::X, DVec3::new(0.3, -0.4, 0.5).normalize()] {
            let h = Domain::Hemisphere { normal: n }.output_grid((64, 32));
            assert!((h.weights.iter().sum::<f64>() - 2.0 * PI).abs() < 1e-12);
            assert!(h.normals.iter().all(|v| v.dot(n) > 0.0), "{n}");
            assert!((h.normals.iter().map(|v| v.length()).fold(0.0f64, |a, b| a.max((b - 1.0).abs()))) < 1e-12);
        }
    }

    #[test]
    fn orientation_sets() {
        assert_eq!(expand_orientations("axes6").unwrap().len(), 6);
        let f = expand_orientations("fibonacci32").unwrap();
        assert_eq!(f.len(), 32);
        assert!(f.iter().all(|o| (o.normal.length() - 1.0).abs() < 1e-12));
        // Roughly uniform: the mean is near zero.
        let mean: DVec3 = f.iter().map(|o| o.normal).sum::<DVec3>() / 32.0;
        assert!(mean.length() < 0.05);
        assert!(expand_orientations("+w").is_err());
        assert!(expand_orientations("fibonacciX").is_err());
    }
}
