//! Analytic lighting: a sum of lights (ambient, hemisphere lights, uniform caps, a sky
//! gradient, delta lights), each with its closed-form L2 SH and closed-form E/π; the part of
//! the lighting that passes visibility caps (the hemisphere and cone effects, `math::cap`); and
//! the lighting turned by a rotation. The one model of analytic lighting: the generated scenes
//! (`scenes`), the constructed scenes of the claims and the tests' analytic cases are built
//! from it.
//!
//! Units (FORMULAS §1): radiance L, and E/π(n) = (1/π)∫ L(ω)·max(0, n·ω) dω, so an ambient
//! radiance c gives c everywhere. A delta light π·C·δ(ω − d) gives E/π = C·max(0, n·d): C is
//! its E/π facing it (the HHD's C_d, FORMULAS §8).
//!
//! The SH of a light symmetric about an axis a is zonal: with z_l = ∫ f(ω·a)·Y_l0 dω its
//! coefficients are c_lm = z_l·√(4π/(2l+1))·Y_lm(a) (FORMULAS §2 basis).

#[cfg(test)]
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::math::sh::{band_of, basis, constant, delta_light, Sh9};
#[cfg(test)]
use glam::DQuat;
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// One analytic light.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Radiance c from every direction.
    Ambient(Rgb),
    /// A hemisphere light: radiance c from the hemisphere ω·axis > 0 (unit axis), 0 from the
    /// other; E/π = c·H(n) with H(n) = (1 + n·axis)/2 (FORMULAS §8).
    Hemisphere {
        /// Unit axis the lit hemisphere is centred on.
        axis: DVec3,
        /// Radiance c of the lit half.
        radiance: Rgb,
    },
    /// A uniform spherical cap ("disc" light, or a cone light) of radiance c, half-angle α
    /// (radians, 0 < α ≤ π) about the unit axis.
    Cap {
        /// Unit axis of the cap.
        axis: DVec3,
        /// Angular radius α in radians.
        half_angle: f64,
        /// Radiance c inside the cap.
        radiance: Rgb,
    },
    /// A sky gradient c0 + c1·y over the whole sphere (non-negative when c0 ≥ |c1|); +y is up
    /// (`math::convention`).
    Gradient {
        /// Radiance at the horizon (y = 0).
        c0: Rgb,
        /// Change of radiance per unit of y (c0 + c1 at the zenith, c0 − c1 at the nadir).
        c1: Rgb,
    },
    /// A directional (delta) light π·facing·δ(ω − dir) (unit dir): E/π facing it is `facing`.
    #[cfg_attr(not(test), allow(dead_code, reason = "the unit tests' delta lights"))]
    Delta {
        /// Unit direction the light arrives from.
        dir: DVec3,
        /// E/π of a surface facing the light.
        facing: Rgb,
    },
}

/// A sum of lights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lighting(pub Vec<Light>);

/// E/π of a uniform cap of unit radiance and half-angle σ whose axis makes cos θ with the
/// normal, including the part clipped by the horizon (the sphere-light form factor of
/// Snyder 1996, as given in Lagarde & de Rousiers, "Moving Frostbite to PBR", 2014, eq. 15,
/// divided by π).
pub fn cap_irradiance(cos_theta: f64, sin_sigma_sq: f64) -> f64 {
    let ct = cos_theta.clamp(-1.0, 1.0);
    let e = if ct * ct > sin_sigma_sq {
        PI * sin_sigma_sq * ct.max(0.0)
    } else {
        let st = (1.0 - ct * ct).max(0.0).sqrt();
        let x = (1.0 / sin_sigma_sq - 1.0).max(0.0).sqrt();
        let y = if st > 0.0 { (-x * ct / st).clamp(-1.0, 1.0) } else { 0.0 };
        let sy = st * (1.0 - y * y).max(0.0).sqrt();
        let base = (ct * y.acos() - x * sy) * sin_sigma_sq;
        base + if x > 0.0 { (sy / x).atan() } else { 0.5 * PI * sy.signum() }
    };
    e.max(0.0) / PI
}

/// The SH of a function of ω·axis with zonal coefficients z_l (see the module doc), times c.
fn zonal(axis: DVec3, z: [f64; 3], c: Rgb) -> Sh9 {
    let y = basis(axis);
    Sh9(std::array::from_fn(|i| {
        let l = band_of(i);
        c * (z[l] * (4.0 * PI / (2 * l + 1) as f64).sqrt() * y[i])
    }))
}

/// The angle between two unit vectors, accurate near 0 and π.
#[cfg(test)]
fn angle(a: DVec3, b: DVec3) -> f64 {
    2.0 * ((a - b).length() * 0.5).clamp(0.0, 1.0).asin()
}

/// The half-angle of a visibility cap.
#[cfg(test)]
fn half_angle_of(m: &Cap) -> f64 {
    m.cos.clamp(-1.0, 1.0).acos()
}

/// Whether the cap of half-angle `half` about `axis` lies inside the mask (to 1e-12 rad).
#[cfg(test)]
fn inside(m: &Cap, axis: DVec3, half: f64) -> bool {
    angle(axis, m.axis) + half <= half_angle_of(m) + 1e-12
}

/// Whether the cap of half-angle `half` about `axis` lies outside the mask (to 1e-12 rad).
#[cfg(test)]
fn outside(m: &Cap, axis: DVec3, half: f64) -> bool {
    angle(axis, m.axis) >= half_angle_of(m) + half - 1e-12
}

impl Light {
    /// Closed-form L2 SH projection of the radiance.
    pub fn sh(&self) -> Sh9 {
        match self {
            Light::Ambient(c) => constant(*c),
            // ∫_{t>0} Y_l0(t): l=0: 2π·½√(1/π); l=1: 2π√(3/4π)·½; l=2: 0.
            Light::Hemisphere { axis, radiance } => {
                zonal(*axis, [PI * (1.0 / PI).sqrt(), PI * (3.0 / (4.0 * PI)).sqrt(), 0.0], *radiance)
            }
            // ∫_{t>cos α} Y_l0: 2π(1−c)·½√(1/π); π√(3/4π)·sin²α; √(5/4π)·π·(c − c³).
            Light::Cap { axis, half_angle, radiance } => {
                let c = half_angle.cos();
                let s2 = 1.0 - c * c;
                zonal(
                    *axis,
                    [
                        TAU * (1.0 - c) * 0.5 * (1.0 / PI).sqrt(),
                        PI * (3.0 / (4.0 * PI)).sqrt() * s2,
                        (5.0 / (4.0 * PI)).sqrt() * PI * c * s2,
                    ],
                    *radiance,
                )
            }
            // c0 + c1·y: y = −Y₁₋₁/√(3/4π).
            Light::Gradient { c0, c1 } => {
                let mut s = constant(*c0);
                s.0[1] = *c1 * (-(4.0 * PI / 3.0).sqrt());
                s
            }
            // c_i = π·facing·Y_i(dir).
            Light::Delta { dir, facing } => delta_light(*dir, *facing * PI),
        }
    }

    /// Closed-form E/π at unit normal n on the whole sphere (no occlusion).
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        match self {
            Light::Ambient(c) => *c,
            Light::Hemisphere { axis, radiance } => *radiance * (0.5 * (1.0 + n.dot(*axis))),
            // A cap wider than a hemisphere is the sphere less the opposite cap (half-angle π − α).
            Light::Cap { axis, half_angle, radiance } if *half_angle > FRAC_PI_2 => {
                *radiance * (1.0 - cap_irradiance(-n.dot(*axis), half_angle.sin().powi(2)))
            }
            Light::Cap { axis, half_angle, radiance } => {
                *radiance * cap_irradiance(n.dot(*axis), half_angle.sin().powi(2))
            }
            // A band-1 function: E/π = c0 + (2/3)·c1·n_y (FORMULAS §3).
            Light::Gradient { c0, c1 } => *c0 + *c1 * (2.0 / 3.0 * n.y),
            Light::Delta { dir, facing } => *facing * n.dot(*dir).max(0.0),
        }
    }

    /// The part of this light that passes every mask: the caps {ω·axis ≥ cos} of a surface's
    /// visibility effects (the hemisphere about N, a cone). The masks are taken closed, so a
    /// delta light exactly on a boundary (a light at the horizon, d·N = 0) passes. Ambient light
    /// under nested masks becomes the innermost mask's hemisphere light (cos = 0) or cap; a
    /// hemisphere light or cap must lie wholly inside or outside the masks.
    ///
    /// Panics on a configuration with no closed form here (a construction error): a cap
    /// straddling a mask, ambient under masks that are not nested, a gradient under a mask.
    #[cfg(test)]
    pub fn visible(&self, masks: &[Cap]) -> Option<Light> {
        if masks.is_empty() {
            return Some(self.clone());
        }
        let cap_like = |axis: DVec3, half: f64| {
            if masks.iter().any(|m| outside(m, axis, half)) {
                None
            } else {
                assert!(masks.iter().all(|m| inside(m, axis, half)), "a light straddling a mask has no closed form");
                Some(self.clone())
            }
        };
        match self {
            Light::Delta { dir, .. } => masks.iter().all(|m| dir.dot(m.axis) >= m.cos).then(|| self.clone()),
            Light::Ambient(c) => {
                let inner = masks
                    .iter()
                    .find(|m| masks.iter().all(|o| inside(o, m.axis, half_angle_of(m))))
                    .expect("ambient light under masks that are not nested has no closed form");
                Some(if inner.cos <= -1.0 {
                    Light::Ambient(*c)
                } else if inner.cos == 0.0 {
                    Light::Hemisphere { axis: inner.axis, radiance: *c }
                } else {
                    Light::Cap { axis: inner.axis, half_angle: half_angle_of(inner), radiance: *c }
                })
            }
            Light::Hemisphere { axis, .. } => cap_like(*axis, 0.5 * PI),
            Light::Cap { axis, half_angle, .. } => cap_like(*axis, *half_angle),
            Light::Gradient { .. } => panic!("a gradient under a mask has no closed form here"),
        }
    }

    /// The light turned by the rotation q (the lighting g(ω) = f(q⁻¹ω)). Panics on a gradient,
    /// which is about +y only.
    #[cfg(test)]
    pub fn rotated(&self, q: DQuat) -> Light {
        match self {
            Light::Ambient(c) => Light::Ambient(*c),
            Light::Hemisphere { axis, radiance } => {
                Light::Hemisphere { axis: (q * *axis).normalize(), radiance: *radiance }
            }
            Light::Cap { axis, half_angle, radiance } => {
                Light::Cap { axis: (q * *axis).normalize(), half_angle: *half_angle, radiance: *radiance }
            }
            Light::Gradient { .. } => panic!("a gradient is about +y: its rotation is not modelled"),
            Light::Delta { dir, facing } => Light::Delta { dir: (q * *dir).normalize(), facing: *facing },
        }
    }

    /// The light with its radiance (a delta: its E/π facing it) scaled by k.
    #[cfg(test)]
    pub fn scaled(&self, k: f64) -> Light {
        match self {
            Light::Ambient(c) => Light::Ambient(*c * k),
            Light::Hemisphere { axis, radiance } => Light::Hemisphere { axis: *axis, radiance: *radiance * k },
            Light::Cap { axis, half_angle, radiance } => {
                Light::Cap { axis: *axis, half_angle: *half_angle, radiance: *radiance * k }
            }
            Light::Gradient { c0, c1 } => Light::Gradient { c0: *c0 * k, c1: *c1 * k },
            Light::Delta { dir, facing } => Light::Delta { dir: *dir, facing: *facing * k },
        }
    }
}

impl Lighting {
    /// Closed-form L2 SH of the radiance.
    pub fn sh(&self) -> Sh9 {
        self.0.iter().fold(Sh9::ZERO, |a, l| a + l.sh())
    }

    /// Closed-form E/π at unit normal n on the whole sphere.
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        self.0.iter().map(|l| l.irradiance(n)).sum()
    }

    /// The light that passes the masks ([`Light::visible`]).
    #[cfg(test)]
    pub fn visible(&self, masks: &[Cap]) -> Lighting {
        Lighting(self.0.iter().filter_map(|l| l.visible(masks)).collect())
    }

    /// The lighting turned by q ([`Light::rotated`]).
    #[cfg(test)]
    pub fn rotated(&self, q: DQuat) -> Lighting {
        Lighting(self.0.iter().map(|l| l.rotated(q)).collect())
    }

    /// The lighting scaled by k.
    #[cfg(test)]
    pub fn scaled(&self, k: f64) -> Lighting {
        Lighting(self.0.iter().map(|l| l.scaled(k)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::convention::direction;
    use crate::math::quadrature::gauss_legendre;

    /// An orthonormal frame (u, v) perpendicular to the unit vector a.
    fn frame(a: DVec3) -> (DVec3, DVec3) {
        let u = a.any_orthonormal_vector();
        (u, a.cross(u))
    }

    /// ∫ g(ω) dω over the cap {ω·a > c} by Gauss–Legendre in t = ω·a and the trapezoid rule in
    /// azimuth: exact to rounding for the polynomials of degree ≤ 4 in ω.
    fn cap_integral<T: std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>>(
        a: DVec3,
        c: f64,
        zero: T,
        g: impl Fn(DVec3) -> T,
    ) -> T {
        let (u, v) = frame(a);
        let mut s = zero;
        for (x, w) in gauss_legendre(12) {
            let t = 0.5 * (1.0 - c) * x + 0.5 * (1.0 + c);
            let r = (1.0 - t * t).max(0.0).sqrt();
            for p in 0..16 {
                let phi = TAU * p as f64 / 16.0;
                s = s + g(a * t + (u * phi.cos() + v * phi.sin()) * r) * (0.5 * (1.0 - c) * w * TAU / 16.0);
            }
        }
        s
    }

    fn max_sh_diff(a: &Sh9, b: &Sh9) -> f64 {
        (0..9).map(|i| (a[i] - b[i]).abs().max_element()).fold(0.0, f64::max)
    }

    /// The SH of the radiance by quadrature: ∫ L(ω)·Y_i(ω) dω.
    fn project(light: &Light) -> Sh9 {
        let by = |a: DVec3, c: f64, l: &dyn Fn(DVec3) -> Rgb| {
            let y = |w: DVec3| {
                let b = basis(w);
                Sh9(std::array::from_fn(|i| l(w) * b[i]))
            };
            cap_integral(a, c, Sh9::ZERO, y)
        };
        match light {
            Light::Ambient(c) => by(DVec3::Y, -1.0, &|_| *c),
            Light::Hemisphere { axis, radiance } => by(*axis, 0.0, &|_| *radiance),
            Light::Cap { axis, half_angle, radiance } => by(*axis, half_angle.cos(), &|_| *radiance),
            Light::Gradient { c0, c1 } => by(DVec3::Y, -1.0, &|w| *c0 + *c1 * w.y),
            Light::Delta { .. } => unreachable!("a delta light has no radiance to integrate"),
        }
    }

    fn lights() -> Vec<Light> {
        let tilted = DVec3::new(0.3, 0.8, -0.52).normalize();
        vec![
            Light::Ambient(Rgb::new(0.3, 0.4, 0.5)),
            Light::Hemisphere { axis: DVec3::Y, radiance: Rgb::new(1.0, 2.0, 3.0) },
            Light::Hemisphere { axis: tilted, radiance: Rgb::new(0.5, 0.25, 2.0) },
            Light::Cap { axis: tilted, half_angle: 0.4, radiance: Rgb::new(3.0, 2.0, 1.0) },
            Light::Cap { axis: DVec3::NEG_X, half_angle: 2.2, radiance: Rgb::splat(0.7) },
            Light::Gradient { c0: Rgb::new(0.45, 0.55, 0.8), c1: Rgb::new(0.3, -0.35, 0.5) },
        ]
    }

    /// The closed-form SH of every light with a radiance against quadrature of its projection.
    #[test]
    fn closed_form_sh_matches_quadrature() {
        for l in lights() {
            let d = max_sh_diff(&l.sh(), &project(&l));
            assert!(d < 1e-13, "{l:?}: {d}");
        }
    }

    /// The closed-form E/π against quadrature of (1/π)∫ L·max(0, n·ω) over the light, at normals
    /// facing it, edge-on and facing away (dense midpoint rule: the integrand has a kink).
    #[test]
    fn closed_form_irradiance_matches_quadrature() {
        let e_by = |a: DVec3, c: f64, l: &dyn Fn(DVec3) -> Rgb, n: DVec3| {
            let (u, v) = frame(a);
            let (nt, np) = (400, 720);
            let mut s = Rgb::ZERO;
            for i in 0..nt {
                let t = c + (1.0 - c) * (i as f64 + 0.5) / nt as f64;
                let r = (1.0 - t * t).sqrt();
                for p in 0..np {
                    let phi = TAU * (p as f64 + 0.5) / np as f64;
                    let w = a * t + (u * phi.cos() + v * phi.sin()) * r;
                    s += l(w) * w.dot(n).max(0.0);
                }
            }
            s * ((1.0 - c) / nt as f64 * TAU / np as f64 / PI)
        };
        for l in lights() {
            for n in [DVec3::Y, DVec3::NEG_Y, DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.2, 0.3, 0.93).normalize()] {
                let want = match &l {
                    Light::Ambient(c) => e_by(DVec3::Y, -1.0, &|_| *c, n),
                    Light::Hemisphere { axis, radiance } => e_by(*axis, 0.0, &|_| *radiance, n),
                    Light::Cap { axis, half_angle, radiance } => e_by(*axis, half_angle.cos(), &|_| *radiance, n),
                    Light::Gradient { c0, c1 } => e_by(DVec3::Y, -1.0, &|w| *c0 + *c1 * w.y, n),
                    Light::Delta { .. } => unreachable!(),
                };
                let got = l.irradiance(n);
                assert!(
                    (got - want).abs().max_element() < 1e-4 * want.max_element().max(1.0),
                    "{l:?} at {n}: {got} vs {want}"
                );
            }
        }
    }

    /// The cap form factor against brute-force quadrature of max(0, n·ω) over the cap,
    /// including horizon-clipped cases.
    #[test]
    fn cap_irradiance_matches_quadrature() {
        let sigma: f64 = 0.4;
        for &theta in &[0.0f64, 0.5, 1.0, 1.3, 1.5, 1.7, 1.9, 2.5] {
            let n = DVec3::new(theta.sin(), theta.cos(), 0.0);
            let (np, nt) = (2000, 400);
            let mut e = 0.0;
            for j in 0..np {
                let (a0, a1) = (sigma * j as f64 / np as f64, sigma * (j + 1) as f64 / np as f64);
                let w = (TAU / nt as f64) * (a0.cos() - a1.cos());
                for i in 0..nt {
                    // cap about +Y
                    let d = direction(TAU * (i as f64 + 0.5) / nt as f64, 0.5 * (a0 + a1));
                    e += w * n.dot(d).max(0.0);
                }
            }
            let want = e / PI;
            let got = cap_irradiance(theta.cos(), sigma.sin().powi(2));
            assert!((got - want).abs() < 2e-6, "theta {theta}: {got} vs {want}");
        }
    }

    /// A delta light is the limit of small caps of the same E/π facing them (radiance
    /// facing/sin²α): SH and E/π converge to the delta's, the E/π as O(α²) off the terminator.
    #[test]
    fn a_delta_light_is_the_limit_of_small_caps() {
        let (dir, facing) = (DVec3::new(0.6, 0.0, 0.8), Rgb::new(1.0, 2.0, 0.5));
        let delta = Light::Delta { dir, facing };
        assert_eq!(delta.irradiance(DVec3::new(0.6, 0.8, 0.0)), facing * (0.6 * 0.6));
        assert_eq!(delta.irradiance(-dir), Rgb::ZERO);
        let cap = |a: f64| Light::Cap { axis: dir, half_angle: a, radiance: facing / a.sin().powi(2) };
        let n = DVec3::new(0.2, 0.9, 0.4).normalize();
        for a in [1e-2, 1e-3] {
            let c = cap(a);
            assert!(max_sh_diff(&c.sh(), &delta.sh()) < a * a * 10.0, "{a}");
            assert!((c.irradiance(n) - delta.irradiance(n)).abs().max_element() < a * a * 10.0, "{a}");
        }
    }

    /// Ambient light under the hemisphere about N is the hemisphere light about N (its SH is
    /// the Gram multiply of the constant, FORMULAS §9); under a cone nested in the hemisphere it
    /// is the cone's cap; a delta light at the horizon passes, one below does not; a cap is kept
    /// or dropped whole.
    #[test]
    fn visibility_under_masks() {
        let n = DVec3::new(0.2, 0.9, -0.3).normalize();
        let a = Rgb::new(1.0, 0.8, 0.6);
        let hemi = [Cap::hemisphere(n)];
        let v = Light::Ambient(a).visible(&hemi).unwrap();
        assert_eq!(v, Light::Hemisphere { axis: n, radiance: a });
        let gram = crate::math::gram::multiply_full(&constant(a), 0.0, n);
        assert!(max_sh_diff(&v.sh(), &gram) < 1e-14);
        let (u, _) = frame(n);
        let centre = (n * 30f64.to_radians().cos() + u * 30f64.to_radians().sin()).normalize();
        let nested = [Cap::hemisphere(n), Cap::new(centre, 0.5)];
        let v = Light::Ambient(a).visible(&nested).unwrap();
        assert!(max_sh_diff(&v.sh(), &crate::math::gram::multiply_full(&constant(a), 0.5, centre)) < 1e-14);
        let horizon = Light::Delta { dir: DVec3::X, facing: Rgb::ONE };
        assert_eq!(horizon.visible(&[Cap::hemisphere(DVec3::Y)]), Some(horizon.clone()));
        assert_eq!(Light::Delta { dir: -n, facing: Rgb::ONE }.visible(&hemi), None);
        let small = |axis| Light::Cap { axis, half_angle: 0.1, radiance: Rgb::ONE };
        let away = (n * 45f64.to_radians().cos() - u * 45f64.to_radians().sin()).normalize();
        assert_eq!(small(away).visible(&nested), None, "outside the cone");
        assert_eq!(small(away).visible(&hemi), Some(small(away)));
        assert_eq!(small(centre).visible(&nested), Some(small(centre)));
        assert_eq!(small(-n).visible(&hemi), None);
    }

    #[test]
    #[should_panic(expected = "straddling")]
    fn a_cap_straddling_a_mask_has_no_closed_form() {
        Light::Cap { axis: DVec3::X, half_angle: 0.2, radiance: Rgb::ONE }.visible(&[Cap::hemisphere(DVec3::Y)]);
    }

    /// Turning the lighting by q turns its SH (`gram::rotate`) and moves its E/π: the E/π of the
    /// turned lighting at q·n is the E/π at n.
    #[test]
    fn rotation_turns_sh_and_irradiance() {
        let q = DQuat::from_axis_angle(DVec3::new(0.2, -0.5, 0.84).normalize(), 1.234);
        let mut ls: Vec<Light> = lights().into_iter().filter(|l| !matches!(l, Light::Gradient { .. })).collect();
        ls.push(Light::Delta { dir: DVec3::new(0.3, -0.5, 0.81).normalize(), facing: Rgb::new(1.0, 0.5, 2.0) });
        let lighting = Lighting(ls);
        let turned = lighting.rotated(q);
        let want = crate::math::gram::rotate(&lighting.sh(), glam::DMat3::from_quat(q));
        assert!(max_sh_diff(&turned.sh(), &want) < 1e-13);
        for n in [DVec3::X, DVec3::new(-0.2, 0.3, 0.93).normalize()] {
            assert!((turned.irradiance(q * n) - lighting.irradiance(n)).abs().max_element() < 1e-13);
        }
    }

    /// `math::sh_rotation` turns a cap's closed-form SH into the closed-form SH of the cap about
    /// the turned axis (exact: both are closed forms).
    #[test]
    fn sh_rotation_moves_a_caps_axis() {
        use crate::math::sh_rotation::{uniform_rotation, ShRotation};
        let axis = DVec3::new(-0.4, 0.6, 0.69).normalize();
        let cap = |a| Light::Cap { axis: a, half_angle: 0.4, radiance: Rgb::new(3.0, 2.0, 1.0) }.sh();
        let mut rotations = vec![glam::DMat3::from_rotation_x(0.7), glam::DMat3::from_rotation_y(-1.9)];
        rotations.extend((1..6).map(|i| {
            let f = |k: f64| (i as f64 * k).fract();
            glam::DMat3::from_quat(uniform_rotation(
                f(0.618_033_988_749_895),
                f(0.414_213_562_373_095),
                f(0.732_050_807_568_877),
            ))
        }));
        for r in rotations {
            assert!(max_sh_diff(&ShRotation::new(r).apply(&cap(axis)), &cap(r * axis)) < 1e-13);
        }
    }
}
