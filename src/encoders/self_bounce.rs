//! Self-bounce as a wrapper around any encoder (hemispherical-lighting talk, "surface
//! self-bounce"; FORMULAS §8): fit the wrapped encoder, then add (1 − H(n))·ρ·I_z, where
//! H(n) = (1 + n·N)/2 is the hemisphere light about the surface normal N, ρ the albedo of the
//! surface below the horizon (`FitInput::surface_albedo`, from the `self_bounce` effect) and
//! I_z the wrapped fit's own E/π at N — the value a lightmap already stores, as the talk says
//! ("we already have the IrradZ value from our lightmap").
//!
//! | key     | type             | default | meaning |
//! |---------|------------------|---------|---------|
//! | `inner` | string or table  | `"sh2"` | the wrapped encoder: a kind, or `{ kind = "…", <its settings> }` |
//!
//! Why a wrapper rather than an option of each lightmap encoder: the term needs only N, ρ and
//! the fit's value at N, so one implementation serves every encoder (HHD, AHD, SH, HLSH) and
//! the with/without comparison is the same inner fit with and without the term. The term is
//! added only when the input has both N and an albedo; otherwise the wrapper is exactly its
//! inner encoder. It stores nothing extra (ρ is the material's albedo, I_z is the inner's).

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use anyhow::{bail, Result};
use glam::DVec3;

/// `with_self_bounce`: the wrapped encoder plus the self-bounce term.
pub struct WithSelfBounce {
    inner: Box<dyn Encoder>,
}

/// Builds an encoder of a kind with its settings: the registry's `build`, handed in by the
/// registry, so that the wrapper wraps any registered encoder without importing the registry
/// that lists it.
pub type BuildInner = fn(&str, toml::Table) -> Result<Box<dyn Encoder>>;

/// Builds `with_self_bounce` from its settings, its inner encoder through `build_inner`.
pub fn build(p: &mut Params, build_inner: BuildInner) -> Result<Box<dyn Encoder>> {
    let (kind, settings) = match p.value("inner") {
        None => ("sh2".to_string(), toml::Table::new()),
        Some(toml::Value::String(k)) => (k, toml::Table::new()),
        Some(toml::Value::Table(mut t)) => match t.remove("kind") {
            Some(toml::Value::String(k)) => (k, t),
            _ => bail!("key 'inner': a table needs kind = \"<encoder>\""),
        },
        Some(v) => bail!("key 'inner': expected an encoder kind or {{ kind = \"…\", … }}, got {v}"),
    };
    if kind == "with_self_bounce" {
        bail!("key 'inner': with_self_bounce cannot wrap itself");
    }
    let inner = build_inner(&kind, settings)?;
    p.finish("with_self_bounce")?;
    Ok(Box::new(WithSelfBounce { inner }))
}

struct Fit {
    inner: Box<dyn Fitted>,
    /// (N, ρ·I_z) when the term applies.
    bounce: Option<(DVec3, Rgb)>,
}

impl Fitted for Fit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        let v = self.inner.irradiance(n);
        match self.bounce {
            Some((normal, k)) => v + k * (0.5 * (1.0 - n.dot(normal))),
            None => v,
        }
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        self.inner.diagnostics()
    }
    /// The inner fit's stored form (the wrapper stores nothing more); with the term, the
    /// product ρ·I_z and N are listed, derived (ρ is the material's, I_z the inner fit's).
    fn stored(&self) -> Stored {
        let mut s = self.inner.stored();
        if let Some((n, k)) = self.bounce {
            s.basis = format!(
                "{}; plus the self-bounce (1 - (1 + n.N)/2)*rho_I_z, rho_I_z = albedo times the fit's own E/pi at the \
                 surface normal N (docs/conventions.md section 8, self-bounce)",
                s.basis
            );
            s.push(Role::Derived, "rho_I_z", Unit::Irradiance, Value::Rgb(k));
            s.push(Role::Derived, "bounce_N", Unit::Direction, Value::Vector(n));
        }
        s
    }
}

impl Encoder for WithSelfBounce {
    fn id(&self) -> &str {
        "with_self_bounce"
    }
    fn family(&self) -> Family {
        self.inner.family()
    }
    fn stored_scalars(&self) -> usize {
        self.inner.stored_scalars()
    }
    fn stored_bytes(&self) -> usize {
        self.inner.stored_bytes()
    }
    /// The inner encoder's storage: the term stores nothing extra (see the module doc).
    fn storage(&self, input: &FitInput) -> String {
        self.inner.storage(input)
    }
    fn scalars_per_point(&self, input: &FitInput) -> usize {
        self.inner.scalars_per_point(input)
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let inner = self.inner.fit(input);
        let bounce = match (input.surface_normal, input.surface_albedo) {
            (Some(n), Some(rho)) if rho > 0.0 => {
                // I_z of the fit itself; a negative I_z (an overshooting encoder) reflects nothing.
                let iz = inner.irradiance(n).max(Rgb::ZERO);
                Some((n, iz * rho))
            }
            _ => None,
        };
        Box::new(Fit { inner, bounce })
    }
    fn peer_clamps(&self) -> bool {
        self.inner.peer_clamps()
    }
    fn is_iterative(&self) -> bool {
        self.inner.is_iterative()
    }
    /// The bounce term needs N, but without it the wrapper is its inner encoder, so it needs N
    /// exactly when the inner encoder does.
    fn needs_surface_normal(&self) -> bool {
        self.inner.needs_surface_normal()
    }
    fn degrades_input(&self) -> bool {
        self.inner.degrades_input()
    }
    // The term is ≥ 0 (1 − H ∈ [0, 1], ρ ≥ 0, I_z clamped), scales with the input and rotates
    // with N, so these promises carry over from the inner encoder.
    fn promises_non_negative(&self) -> bool {
        self.inner.promises_non_negative()
    }
    fn is_scale_covariant(&self) -> bool {
        self.inner.is_scale_covariant()
    }
    fn is_rotation_covariant(&self) -> bool {
        self.inner.is_rotation_covariant()
    }
    fn sphere_error_at_most_sh(&self) -> Option<usize> {
        // Without an albedo the wrapper is its inner encoder; with one it models a different
        // reference, so the sphere bound is not promised.
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::{constant, Sh9};

    fn enc(settings: &str) -> Box<dyn Encoder> {
        crate::encoders::build("with_self_bounce", None, toml::from_str(settings).unwrap()).unwrap().encoder
    }

    /// Constant radiance A over the upper hemisphere about N (the visible SH of a constant
    /// map): the L2 SH irradiance is exactly A·H(n) (the even bands ≥ 2 of a hemisphere step
    /// vanish), I_z = A, so the wrapper gives A·(H + ρ(1 − H)) in closed form.
    #[test]
    fn adds_the_bounce_in_closed_form() {
        let n = DVec3::new(0.3, 0.8, -0.52).normalize();
        let a = Rgb::new(1.0, 0.5, 0.25);
        // Visible SH of A·[ω·N > 0]: the constant times the hemisphere cap (FORMULAS §9),
        // which is exact here because the product is a band-0 input times the cap's Gram.
        let full: Sh9 = constant(a);
        let visible = crate::math::gram::multiply_full(&full, 0.0, n);
        let rho = 0.8;
        let input = FitInput {
            probe_sh: &full,
            visible_sh: &visible,
            surface_normal: Some(n),
            cone: None,
            exact_at_normal: Some(a),
            surface_albedo: Some(rho),
            radiance: None,
        };
        let fit = enc("inner = 'sh2'").fit(&input);
        for m in [n, -n, DVec3::X, DVec3::Y, DVec3::new(0.6, 0.0, 0.8)] {
            let h = 0.5 * (1.0 + m.dot(n));
            let want = a * (h + rho * (1.0 - h));
            let got = fit.irradiance(m);
            assert!((got - want).abs().max_element() < 1e-12, "{m}: {got} vs {want}");
        }
        // Without an albedo (no effect declared) the wrapper is exactly the inner encoder.
        let plain = crate::encoders::build("sh2", None, toml::Table::new()).unwrap().encoder.fit(&input);
        let no_albedo = FitInput { surface_albedo: None, ..input };
        let w = enc("").fit(&no_albedo);
        for m in [n, -n, DVec3::X] {
            assert_eq!(w.irradiance(m), plain.irradiance(m));
        }
    }

    #[test]
    fn settings_are_checked() {
        let e = |s: &str| {
            format!("{:#}", crate::encoders::build("with_self_bounce", None, toml::from_str(s).unwrap()).err().unwrap())
        };
        assert!(e("inner = 'nope'").contains("unknown encoder 'nope'"));
        assert!(e("inner = 3").contains("key 'inner'"));
        assert!(e("inner = 'sh2'\nbogus = 1").contains("bogus"));
        assert!(e("inner = { kind = 'sh2', bogus = 1 }").contains("bogus"));
        assert!(e("inner = 'with_self_bounce'").contains("itself"));
        assert!(enc("inner = { kind = 'sh2' }").id() == "with_self_bounce");
    }
}
