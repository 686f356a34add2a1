//! Orthographic views of the sphere of normals and the pixel discs they are drawn as: the
//! normal sets at which pictures (the report's comparison sheets, the lightmap study's
//! blending strips) evaluate the reference and the encoders.
//!
//! A *lit sphere* shows the sphere of normals seen orthographically from a view: the pixel at
//! unit-disc point (x right, y up) shows E/π at the normal (x, y, √(1 − x² − y²)) of the view's
//! frame, turned into world space. The views are
//! - `front`: viewer on +Z looking towards −Z, +Y up, +X right (normals with n·Z > 0);
//! - `top`: viewer on +Y looking down, −Z up, +X right (normals with n·Y > 0);
//! - `down N`: the hemisphere about a surface normal N as a disc looking down N — the
//!   hemisphere domain of a lightmap texel; `down +Y` is `top`.

use crate::reference::domain::frame_to;
use glam::{DQuat, DVec3};
use std::f64::consts::FRAC_PI_2;

/// An orthographic view of the sphere of normals.
#[derive(Clone, Debug)]
pub struct View {
    /// What the view shows, for headings (e.g. "front: viewer on +Z, +Y up, +X right").
    pub caption: String,
    /// Local frame (x right, y up, z towards the viewer) to world.
    rot: DQuat,
}

impl View {
    /// Viewer on +Z looking towards −Z (the map's centre column), +Y up.
    pub fn front() -> Self {
        View { caption: "front: viewer on +Z, +Y up, +X right".into(), rot: DQuat::IDENTITY }
    }
    /// Viewer on +Y looking down, −Z up, +X right.
    pub fn top() -> Self {
        View { caption: "top: viewer on +Y, -Z up, +X right".into(), rot: DQuat::from_rotation_x(-FRAC_PI_2) }
    }
    /// The hemisphere about N as a disc looking down N (`down(+Y)` is [`View::top`]).
    pub fn down(n: DVec3, label: &str) -> Self {
        let rot = frame_to(n) * DQuat::from_rotation_x(-FRAC_PI_2);
        let right = axis_name(rot * DVec3::X);
        let up = axis_name(rot * DVec3::Y);
        View { caption: format!("disc looking down N = {label}: {up} up, {right} right"), rot }
    }
    /// The world normal shown at unit-disc point (x right, y up), |(x, y)| ≤ 1.
    pub fn normal(&self, x: f64, y: f64) -> DVec3 {
        let z = (1.0 - x * x - y * y).max(0.0).sqrt();
        (self.rot * DVec3::new(x, y, z)).normalize()
    }
}

/// "+X" for axis-aligned unit vectors, else the rounded components.
fn axis_name(v: DVec3) -> String {
    for (name, a) in [("+X", DVec3::X), ("-X", DVec3::NEG_X), ("+Y", DVec3::Y), ("-Y", DVec3::NEG_Y)] {
        if v.dot(a) > 1.0 - 1e-9 {
            return name.into();
        }
    }
    for (name, a) in [("+Z", DVec3::Z), ("-Z", DVec3::NEG_Z)] {
        if v.dot(a) > 1.0 - 1e-9 {
            return name.into();
        }
    }
    format!("({:.2}, {:.2}, {:.2})", v.x, v.y, v.z)
}

/// The pixels of a disc of diameter `d`: per pixel its coverage (4×4 subsamples) and the
/// index of its normal; pixels whose centre lies outside the disc take the normal at the
/// nearest point just inside the rim.
#[derive(Clone, Debug)]
pub struct Disc {
    /// Side of the square image in pixels.
    pub d: usize,
    /// Fraction of each pixel inside the disc (0 to 1, in sixteenths), row-major d × d.
    pub coverage: Vec<f32>,
    /// Per pixel (row-major), the index into `normals` of its normal; None for pixels the disc
    /// misses.
    pub index: Vec<Option<usize>>,
    /// World normals of the covered pixels, in row-major pixel order.
    pub normals: Vec<DVec3>,
}

impl Disc {
    /// Rasterises the disc of `view` at `d` × `d` pixels.
    pub fn new(view: &View, d: usize) -> Self {
        let mut coverage = vec![0.0f32; d * d];
        let mut index = vec![None; d * d];
        let mut normals = Vec::new();
        let to_disc = |p: f64| 2.0 * p / d as f64 - 1.0;
        for py in 0..d {
            for px in 0..d {
                let mut inside = 0;
                for sy in 0..4 {
                    for sx in 0..4 {
                        let x = to_disc(px as f64 + (sx as f64 + 0.5) / 4.0);
                        let y = -to_disc(py as f64 + (sy as f64 + 0.5) / 4.0);
                        if x * x + y * y <= 1.0 {
                            inside += 1;
                        }
                    }
                }
                if inside == 0 {
                    continue;
                }
                let (mut x, mut y) = (to_disc(px as f64 + 0.5), -to_disc(py as f64 + 0.5));
                let r = (x * x + y * y).sqrt();
                if r > 0.999 {
                    x *= 0.999 / r;
                    y *= 0.999 / r;
                }
                coverage[py * d + px] = inside as f32 / 16.0;
                index[py * d + px] = Some(normals.len());
                normals.push(view.normal(x, y));
            }
        }
        Disc { d, coverage, index, normals }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_show_the_normals_they_claim() {
        // Centre of the front view faces the viewer (+Z); of the top view, +Y.
        assert!((View::front().normal(0.0, 0.0) - DVec3::Z).length() < 1e-12);
        assert!((View::top().normal(0.0, 0.0) - DVec3::Y).length() < 1e-12);
        // Top view: screen up is −Z, screen right +X.
        assert!((View::top().normal(0.0, 0.999_999) - DVec3::NEG_Z).length() < 1e-2);
        assert!((View::top().normal(0.999_999, 0.0) - DVec3::X).length() < 1e-2);
        // Looking down N shows exactly the hemisphere about N.
        let n = DVec3::new(1.0, 2.0, -0.5).normalize();
        let v = View::down(n, "n");
        assert!((v.normal(0.0, 0.0) - n).length() < 1e-12);
        let d = Disc::new(&v, 24);
        assert!(d.normals.iter().all(|m| m.dot(n) > 0.0));
    }
}
