//! The one encoder trait. Every encoding (SH, ZH3, Geomerics, AHD/HHD, occlusion operators)
//! fits through [`Encoder::fit`] and evaluates through [`Fitted::irradiance`]; the runner,
//! reference, metrics, renders and report never name an encoder.
//!
//! Encoders do no IO and cannot fail: a degenerate input (no light, no direction) must fall
//! back to a documented answer, never NaN. The contract every registered encoder is tested
//! against (`tests/encoder_hard_cases.rs`, on 34 named hard cases): finite output; black in,
//! black out; no direction (L1 = 0, or an L1 whose square underflows) → no worse than pure ambient
//! (the band-0 answer); a loose sanity bound everywhere; and each promise below that the
//! encoder makes.

use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::reference::radiance::{RadianceSource, ShLight};
use anyhow::{bail, Result};
use glam::DVec3;

/// Everything an encoder may be fitted from. SH are radiance coefficients (FORMULAS §2),
/// exact cell integrals of the map.
#[derive(Clone, Copy, Debug)]
pub struct FitInput<'a> {
    /// L2 SH of the radiance the probe sees, with no occlusion (a world-space probe).
    pub probe_sh: &'a Sh9,
    /// L2 SH of the radiance that reaches the surface: the map under the declared effects
    /// (hemisphere about N, cone). Equals `probe_sh` when no effect is declared. This is what
    /// a lightmap bake stores.
    pub visible_sh: &'a Sh9,
    /// The surface normal N, on hemisphere domains.
    pub surface_normal: Option<DVec3>,
    /// The declared visibility cone (centre, cos α), if any.
    pub cone: Option<(DVec3, f64)>,
    /// Exact irradiance E/π at N under the declared effects (a bake's I_z), when N exists.
    pub exact_at_normal: Option<Rgb>,
    /// The albedo ρ of the surface below the horizon when the `self_bounce` effect is
    /// declared (the material's, known at shading time; not part of the bake). `None` without
    /// the effect: encoders that model the bounce then add nothing.
    pub surface_albedo: Option<f64>,
    /// The visible light itself, for encoders that need more than L2 SH: SH through band 4,
    /// the radiance in a direction and the peer tool's Halton sample set of it, the exact E/π
    /// at any normal ([`RadianceSource`]). The runner passes the map's light under the case's
    /// caps (`reference::radiance::MapLight`, lazy and cached: encoders that never ask pay
    /// nothing). `None` where only SH exist (probe sets, strips, inputs built from SH); read
    /// it through [`FitInput::light`], which then falls back to the light of `visible_sh`.
    pub radiance: Option<&'a dyn RadianceSource>,
}

/// The light of a [`FitInput`]: the runner's source, or the fallback built from `visible_sh`
/// ([`ShLight`]: radiance Σ L_i Y_i, bands 3–4 zero, E/π by cosine convolution). Dereferences
/// to [`RadianceSource`].
pub enum Light<'a> {
    Source(&'a dyn RadianceSource),
    Sh(Box<ShLight>),
}

impl<'a> std::ops::Deref for Light<'a> {
    type Target = dyn RadianceSource + 'a;
    fn deref(&self) -> &Self::Target {
        match self {
            Light::Source(s) => *s,
            Light::Sh(s) => s.as_ref(),
        }
    }
}

impl<'a> FitInput<'a> {
    /// The input for a probe on the sphere: no surface, no effects.
    pub fn sphere(sh: &'a Sh9) -> Self {
        FitInput {
            probe_sh: sh,
            visible_sh: sh,
            surface_normal: None,
            cone: None,
            exact_at_normal: None,
            surface_albedo: None,
            radiance: None,
        }
    }

    /// The visible light as a [`RadianceSource`]: `radiance` if the caller passed one, else
    /// the light of `visible_sh` alone (so an encoder that reads it cannot fail; the fallback's
    /// samples cost one L2 evaluation each, computed on first use).
    pub fn light(&self) -> Light<'a> {
        match self.radiance {
            Some(s) => Light::Source(s),
            None => Light::Sh(Box::new(ShLight::new(self.visible_sh))),
        }
    }
}

/// An encoding method with its settings.
pub trait Encoder: Send + Sync {
    /// The stable short id used in tables, on the command line and in file names.
    fn id(&self) -> &str;
    /// Scalars stored per probe or texel (RGB counts 3).
    fn stored_scalars(&self) -> usize;
    /// Fits the encoding.
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted>;
    /// Whether the peer tool clamps this encoder's output at zero before scoring
    /// (FORMULAS §10); only `--metric probulator` reads this.
    fn peer_clamps(&self) -> bool {
        true
    }
    /// Whether the fit runs an iterative solver (a nonlinear least-squares or optimisation
    /// loop) rather than a closed form. `probelab check` gives iterative encoders the looser
    /// tolerances of `tolerances.toml` (`class = "iterative"`).
    fn is_iterative(&self) -> bool {
        false
    }
    /// True for encodings that deliberately lose or bias information — quantised storage, or a
    /// peer tool's biased variant kept for cross-checks. They are exempt from the hard cases'
    /// "no usable direction → no worse than pure ambient" bound; every other check applies.
    fn degrades_input(&self) -> bool {
        false
    }

    // Promises. Each is false (or `None`) unless the encoder overrides it, and each one an
    // encoder makes is checked for it on every hard case (`tests/encoder_hard_cases.rs`) and on
    // random lighting (`tests/encoder_properties.rs`). Promise only what holds for every input,
    // including the degenerate ones.

    /// E/π ≥ 0 at every normal whenever the input radiance is non-negative.
    fn promises_non_negative(&self) -> bool {
        false
    }
    /// Scaling the input (every SH coefficient and `exact_at_normal`) by k > 0 scales the
    /// output by k, for k from 1e-30 to 1e30, to 1e-7 of the largest output (room for an
    /// iterative solver's tolerance; a closed form meets it to rounding).
    fn is_scale_covariant(&self) -> bool {
        false
    }
    /// Rotating the input (the light, the surface normal and the cone together) by R rotates
    /// the output: fit(R·input)(R n) = fit(input)(n), to 1e-7 of the largest output.
    fn is_rotation_covariant(&self) -> bool {
        false
    }
    /// `Some(l)` if the fitted E/π is never farther, in the solid-angle RMSE over the whole
    /// sphere from the irradiance of the visible radiance, than the SH projection through band
    /// l: the model contains that projection and the fit minimises the sphere error over a
    /// family that includes it (sh1 → 1; a least-squares ZH3 → 1).
    fn sphere_error_at_most_sh(&self) -> Option<usize> {
        None
    }
}

/// A fitted encoding: evaluates E/π at a normal.
pub trait Fitted: Send + Sync {
    /// E/π at unit normal `n`.
    fn irradiance(&self, n: DVec3) -> Rgb;
    /// Solver statistics and similar per-fit figures, reported in the `diagnostics` column.
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// This fit's E/π as SH through band 2, when it is exactly that (SH, ZH3 expanded to SH3):
    /// lets probe-set errors use the closed form instead of quadrature (`probes.rs`). None
    /// (the default) for anything else, e.g. clamped or non-polynomial reconstructions.
    fn sh3(&self) -> Option<Sh9> {
        None
    }
    /// ∫ over the sphere of |E_fit(n) − E_ref(n)|² dω, summed over RGB, against the E/π SH3
    /// `reference`, when this fit has it in closed form: by default from [`Fitted::sh3`]
    /// (Parseval, Σ_i |c_i − r_i|²); zonal reconstructions override it (Funk–Hecke, e.g.
    /// Geomerics). None: probe-set errors fall back to quadrature (`pipeline::probeset::score`).
    fn sphere_sq_error(&self, reference: &Sh9) -> Option<f64> {
        let c = self.sh3()?;
        Some((0..crate::math::sh::N_SH).map(|i| (c[i] - reference[i]).length_squared()).sum())
    }
}

/// Encoder settings from an experiment file or the command line. Every key must be read:
/// [`Params::finish`] rejects the ones no encoder asked for (pbrt's `ReportUnused`).
#[derive(Clone, Debug, Default)]
pub struct Params {
    table: toml::Table,
    used: Vec<String>,
}

impl Params {
    pub fn new(table: toml::Table) -> Self {
        Params { table, used: Vec::new() }
    }

    /// An optional float with a default.
    pub fn f64_or(&mut self, key: &str, default: f64) -> Result<f64> {
        self.used.push(key.into());
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::Float(f)) if f.is_finite() => Ok(*f),
            Some(toml::Value::Integer(i)) => Ok(*i as f64),
            Some(v) => bail!("key '{key}': expected a finite number, got {v}"),
        }
    }

    /// An optional integer with a default.
    pub fn usize_or(&mut self, key: &str, default: usize) -> Result<usize> {
        self.used.push(key.into());
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(i)) if *i >= 0 => Ok(*i as usize),
            Some(v) => bail!("key '{key}': expected a non-negative integer, got {v}"),
        }
    }

    /// An optional string with a default.
    pub fn str_or(&mut self, key: &str, default: &str) -> Result<String> {
        self.used.push(key.into());
        match self.table.get(key) {
            None => Ok(default.to_string()),
            Some(toml::Value::String(s)) => Ok(s.clone()),
            Some(v) => bail!("key '{key}': expected a string, got {v}"),
        }
    }

    /// An optional RGB triple with a default (a 3-element array), or a named weighting
    /// (`rec709`, `equal`).
    pub fn rgb_or(&mut self, key: &str, default: Rgb) -> Result<Rgb> {
        self.used.push(key.into());
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::String(s)) => named_weights(s),
            Some(toml::Value::Array(a)) if a.len() == 3 => {
                let mut v = [0.0; 3];
                for (o, x) in v.iter_mut().zip(a) {
                    *o = match x {
                        toml::Value::Float(f) => *f,
                        toml::Value::Integer(i) => *i as f64,
                        _ => bail!("key '{key}': expected three numbers"),
                    };
                }
                Ok(Rgb::from_array(v))
            }
            Some(v) => bail!("key '{key}': expected [r, g, b] or 'rec709'/'equal', got {v}"),
        }
    }

    /// The raw value of an optional key (for settings that are themselves tables, such as a
    /// wrapped encoder), marking it read.
    pub fn value(&mut self, key: &str) -> Option<toml::Value> {
        self.used.push(key.into());
        self.table.get(key).cloned()
    }

    /// Fails if any key was not read.
    pub fn finish(&self, kind: &str) -> Result<()> {
        let unused: Vec<&String> = self.table.keys().filter(|k| !self.used.contains(k)).collect();
        if !unused.is_empty() {
            let known: Vec<&str> = self.used.iter().map(|s| s.as_str()).collect();
            bail!(
                "encoder '{kind}': unknown key(s) {}; it accepts: {}",
                unused.iter().map(|s| format!("'{s}'")).collect::<Vec<_>>().join(", "),
                if known.is_empty() { "no keys".to_string() } else { known.join(", ") }
            );
        }
        Ok(())
    }
}

/// Channel weightings by name: `rec709` (0.2126, 0.7152, 0.0722) or `equal` (⅓ each).
pub fn named_weights(s: &str) -> Result<Rgb> {
    match s {
        "rec709" => Ok(crate::math::colour::REC709),
        "equal" => Ok(Rgb::splat(1.0 / 3.0)),
        _ => bail!("unknown weighting '{s}' (expected rec709, equal or [r, g, b])"),
    }
}
