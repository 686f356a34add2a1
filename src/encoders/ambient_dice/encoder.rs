//! The ambient dice as an encoder: the fit (moments of the exact E/π or of the L2 SH, two
//! triangular solves, scaled to order one and back), its stored form and evaluation, and the
//! registry's builders (`weights` key).

use super::design::{Design, FIT_GRID};
use super::geometry::{bezier_weights, geometry};
use super::variant::Variant;
use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::{bail, Result};
use glam::DVec3;
use nalgebra::DVector;

/// A fitted dice: per vertex, RGB value and derivatives (Bézier), Y value and derivatives
/// plus Co and Cg values (Y/Co/Cg), or RGB lobe amplitudes (SRBF).
pub struct DiceFit {
    pub(super) variant: Variant,
    /// Bézier: 36 RGB coefficients (3 per vertex). Y/Co/Cg: 36 Y in `.x`, then 12 (Co, Cg, 0).
    /// SRBF: 12 RGB amplitudes.
    pub(super) coeffs: Vec<Rgb>,
}

impl Fitted for DiceFit {
    /// Per vertex i: the Bézier value f_i and derivatives g_i, h_i along its tangent t_i and
    /// bitangent s_i (RGB, or Y alone with linear Co_i, Cg_i), or the SRBF amplitude w_i; the
    /// vertices and frames are the dice's constants, listed derived (module docs).
    fn stored(&self) -> Stored {
        let g = geometry();
        let frame = "vertices v_i (derived entries vertex_i, the peer's icosahedron orientation) and, for the Bezier \
                     basis, the tangent t_i = normalize(Y x v_i) and bitangent s_i = v_i x t_i (entries t_i, s_i); \
                     the face of n is the one whose centre is nearest and its barycentrics b solve n = sum b_i v_i \
                     (ambient_dice.rs module docs, Iwanicki & Sloan 2017); world directions, +Y up (docs/conventions.md \
                     section 1)";
        let mut s = Stored::new(match self.variant {
            Variant::Bezier => format!(
                "E/pi(n) = the hybrid cubic Bezier triangle of n's face with corner values f_i and tangential \
                 derivatives g_i (along t_i), h_i (along s_i) per channel; {frame}"
            ),
            Variant::BezierYCoCg => format!(
                "Y(n) = the hybrid cubic Bezier triangle of n's face (corner values Y_f_i, derivatives Y_g_i, Y_h_i); \
                 Co(n) = sum b_i Co_i and Cg(n) = sum b_i Cg_i over the face; R = Y + Co - Cg, G = Y + Cg, \
                 B = Y - Co - Cg; {frame}"
            ),
            Variant::Srbf => format!(
                "E/pi(n) = sum_i w_i*(0.35*c_i^2 + 0.25*c_i^4), c_i = max(0, n.v_i) (the cosine SRBF lobes); {frame}"
            ),
        });
        match self.variant {
            Variant::Bezier => {
                for v in 0..12 {
                    for (slot, letter) in ["f", "g", "h"].into_iter().enumerate() {
                        s.rgb(format!("{letter}_{v}"), Unit::Irradiance, self.coeffs[3 * v + slot]);
                    }
                }
            }
            Variant::BezierYCoCg => {
                for v in 0..12 {
                    for (slot, letter) in ["f", "g", "h"].into_iter().enumerate() {
                        s.scalar(format!("Y_{letter}_{v}"), Unit::Irradiance, self.coeffs[3 * v + slot].x);
                    }
                }
                for v in 0..12 {
                    s.scalar(format!("Co_{v}"), Unit::Irradiance, self.coeffs[36 + v].x);
                }
                for v in 0..12 {
                    s.scalar(format!("Cg_{v}"), Unit::Irradiance, self.coeffs[36 + v].y);
                }
            }
            Variant::Srbf => {
                for v in 0..12 {
                    s.rgb(format!("w_{v}"), Unit::Irradiance, self.coeffs[v]);
                }
            }
        }
        for (v, p) in g.vertices.iter().enumerate() {
            s.push(Role::Derived, format!("vertex_{v}"), Unit::Direction, Value::Vector(*p));
        }
        if self.variant != Variant::Srbf {
            for (v, (t, b)) in g.frames.iter().enumerate() {
                s.push(Role::Derived, format!("t_{v}"), Unit::Direction, Value::Vector(*t));
                s.push(Role::Derived, format!("s_{v}"), Unit::Direction, Value::Vector(*b));
            }
        }
        s
    }
    fn irradiance(&self, n: DVec3) -> Rgb {
        let g = geometry();
        match self.variant {
            Variant::Bezier => {
                let (v, w) = g.bezier(n);
                let mut e = Rgb::ZERO;
                for (vi, wi) in v.iter().zip(&w) {
                    for (slot, ws) in wi.iter().enumerate() {
                        e += self.coeffs[3 * vi + slot] * *ws;
                    }
                }
                e
            }
            Variant::BezierYCoCg => {
                let (face, b) = g.locate(n);
                let w = bezier_weights(face, b);
                let (mut y, mut co, mut cg) = (0.0, 0.0, 0.0);
                for (i, &v) in face.vertices.iter().enumerate() {
                    for (slot, ws) in w[i].iter().enumerate() {
                        y += self.coeffs[3 * v + slot].x * ws;
                    }
                    co += self.coeffs[36 + v].x * b[i];
                    cg += self.coeffs[36 + v].y * b[i];
                }
                Rgb::new(y + co - cg, y + cg, y - co - cg)
            }
            Variant::Srbf => g.srbf(n).iter().zip(&self.coeffs).fold(Rgb::ZERO, |acc, (w, c)| acc + *c * *w),
        }
    }
}

/// The ambient dice encoder.
pub struct AmbientDiceEncoder {
    variant: Variant,
    pixel_weights: bool,
}

impl AmbientDiceEncoder {
    /// The dice of `variant`, fitted with per-pixel weights (the peer's) when `pixel_weights`,
    /// solid-angle weights otherwise.
    pub fn new(variant: Variant, pixel_weights: bool) -> Self {
        AmbientDiceEncoder { variant, pixel_weights }
    }

    /// The least-squares fit to E/π on the fitting grid (`target`, row-major, [`FIT_GRID`]).
    pub fn fit_target(&self, target: &[Rgb]) -> DiceFit {
        // Least squares is scale covariant: solve for the target divided by its largest
        // magnitude, so that a 1e-300 light does not underflow in the products below.
        let scale = target.iter().map(|e| e.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return self.zero();
        }
        let design = Design::get(self.variant, self.pixel_weights);
        self.solve(design, &design.moments(self.variant.functions(), target, scale), scale)
    }

    /// The same fit when the target is the E/π of L2 SH `e` (the light of SH alone, where no
    /// radiance source is given): E/π = Σ_i e_i Y_i is linear in the nine coefficients, so the
    /// grid moments are `Design::sh_moments` times e, with no grid to evaluate (probe sets fit
    /// millions of these). Equal to [`AmbientDiceEncoder::fit_target`] of the grid to rounding
    /// (tested).
    pub fn fit_sh(&self, e: &Sh9) -> DiceFit {
        let scale = e.0.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return self.zero();
        }
        let design = Design::get(self.variant, self.pixel_weights);
        let m: Vec<Rgb> = design
            .sh_moments
            .iter()
            .map(|q| q.iter().zip(&e.0).fold(Rgb::ZERO, |acc, (qi, ei)| acc + *ei / scale * *qi))
            .collect();
        self.solve(design, &m, scale)
    }

    fn zero(&self) -> DiceFit {
        DiceFit { variant: self.variant, coeffs: vec![Rgb::ZERO; self.variant.functions()] }
    }

    /// The coefficients from the moments of the target divided by `scale`.
    fn solve(&self, design: &Design, m: &[Rgb], scale: f64) -> DiceFit {
        let coeffs = match self.variant {
            Variant::Bezier | Variant::Srbf => {
                let mut out = vec![Rgb::ZERO; m.len()];
                for c in 0..3 {
                    let x = design.normal.solve(&DVector::from_iterator(m.len(), m.iter().map(|v| v[c])));
                    for (o, v) in out.iter_mut().zip(x.iter()) {
                        o[c] = v * scale;
                    }
                }
                out
            }
            Variant::BezierYCoCg => {
                // Right-hand side: Bᵀ(E_R + E_G + E_B), Lᵀ(E_R − E_B), Lᵀ(−E_R + E_G − E_B).
                let mut rhs = DVector::<f64>::zeros(60);
                for j in 0..36 {
                    rhs[j] = m[j].x + m[j].y + m[j].z;
                }
                for j in 0..12 {
                    let l = m[36 + j];
                    rhs[36 + j] = l.x - l.z;
                    rhs[48 + j] = -l.x + l.y - l.z;
                }
                let x = design.normal.solve(&rhs);
                let mut out = vec![Rgb::ZERO; 48];
                for j in 0..36 {
                    out[j] = Rgb::new(x[j] * scale, 0.0, 0.0);
                }
                for j in 0..12 {
                    out[36 + j] = Rgb::new(x[36 + j] * scale, x[48 + j] * scale, 0.0);
                }
                out
            }
        };
        if coeffs.iter().all(|c| c.is_finite()) {
            DiceFit { variant: self.variant, coeffs }
        } else {
            self.zero()
        }
    }
}

impl Encoder for AmbientDiceEncoder {
    fn id(&self) -> &str {
        self.variant.id()
    }
    fn family(&self) -> Family {
        Family::AmbientDice
    }
    fn stored_scalars(&self) -> usize {
        match self.variant {
            Variant::Bezier => 108,
            Variant::BezierYCoCg => 60,
            Variant::Srbf => 36,
        }
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        match input.radiance {
            Some(light) => {
                let (w, h) = FIT_GRID;
                Box::new(self.fit_target(&light.irradiance_latlong(w, h)))
            }
            // The fallback light of the visible SH alone (`FitInput::light`): its E/π is the
            // cosine-convolved SH, fitted in closed form.
            None => Box::new(self.fit_sh(&input.visible_sh.convolve_cosine())),
        }
    }
    /// The peer scores its dice unclamped (PEER.md).
    fn peer_clamps(&self) -> bool {
        false
    }
    /// Linear least squares of a target that scales with the input.
    fn is_scale_covariant(&self) -> bool {
        true
    }
    /// The Bézier basis (both variants using it) does not contain the constant, so with no
    /// usable direction it cannot match pure ambient: a constant is fitted to 4.1% at worst
    /// (module docs). The SRBF lobes sum to 1 and make no such exception.
    fn degrades_input(&self) -> bool {
        self.variant != Variant::Srbf
    }
}

/// The `weights` setting: `solid_angle` (false, the default) or `pixel` (true).
pub(super) fn weights_key(p: &mut Params) -> Result<bool> {
    let w = p.str_or("weights", "solid_angle")?;
    match w.as_str() {
        "solid_angle" => Ok(false),
        "pixel" => Ok(true),
        _ => bail!("key 'weights': expected 'solid_angle' or 'pixel', got '{w}'"),
    }
}

/// `ambient_dice`: the Bézier dice (settings: `weights`).
pub fn build_ambient_dice(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::Bezier, pixel)))
}

/// `ambient_dice_ycocg`: Y in the Bézier basis, Co and Cg in the linear one (settings: `weights`).
pub fn build_ambient_dice_ycocg(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice_ycocg")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::BezierYCoCg, pixel)))
}

/// `ambient_dice_srbf`: the cosine SRBF lobes (settings: `weights`).
pub fn build_ambient_dice_srbf(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice_srbf")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::Srbf, pixel)))
}
