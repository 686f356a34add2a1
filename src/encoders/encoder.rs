//! The one encoder trait. Every encoding (SH, ZH3, Geomerics, AHD/HHD, occlusion operators)
//! fits through [`Encoder::fit`] and evaluates through [`Fitted::irradiance`]; the runner,
//! reference, metrics, renders and report never name an encoder.
//!
//! Encoders do no IO and cannot fail: a degenerate input (no light, no direction) must fall
//! back to a documented answer, never NaN. The contract every registered encoder is tested
//! against (`src/tests/encoder_hard_cases.rs`, on 34 named hard cases): finite output; black in,
//! black out; no direction (L1 = 0, or an L1 whose square underflows) → no worse than pure ambient
//! (the band-0 answer); a loose sanity bound everywhere; and each promise below that the
//! encoder makes.

use crate::encoders::stored::Stored;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::reference::radiance::{RadianceSource, ShLight};
use anyhow::{bail, Context, Result};
use glam::DVec3;
use std::ops::{Bound, RangeBounds, RangeInclusive};

/// Bytes of one unquantised stored scalar: a half float (IEEE 754 binary16), the default of
/// [`Encoder::stored_bytes`].
pub const HALF_BYTES: usize = 2;

/// The largest channel weight a weighting key accepts (weights are relative).
pub const MAX_WEIGHT: f64 = 1e6;

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
    /// The light source the runner passed in.
    Source(&'a dyn RadianceSource),
    /// The fallback built from the fit's `visible_sh`.
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

/// Why an encoder named `name` that [`Encoder::needs_surface_normal`] cannot be scored on the
/// sphere; every refusal (experiments, `eval`, probe sets) starts with this and adds its fix.
pub fn surface_normal_refusal(name: &str) -> String {
    format!(
        "'{name}' needs a surface normal N: it is defined only on the hemisphere about a surface normal N \
         (its fit reads N, or bakes the light occluded by the surface about N), and the sphere has no N, so \
         it would silently return a fallback (another encoder's answer)"
    )
}

/// The family an encoding belongs to: what its basis is, so that figures can give a family one
/// hue and tell its members apart within it. Every registered encoder declares its own
/// ([`Encoder::family`]); nothing downstream infers it from a name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Family {
    /// Spherical harmonics irradiance, any band count, windowed or quantised.
    Sh,
    /// Zonal harmonics ZH3 (hallucinated, stored or solved axes).
    Zh3,
    /// Geomerics' L1 reconstruction.
    Geomerics,
    /// SH probes under occlusion (hemisphere and cone multiplies, HLSH, AO, bent normal).
    ProbeOcclusion,
    /// Lightmap encodings of the AHD model, C_a + C_d·max(0, n·d), and its IrradZ forms
    /// (FORMULAS §7).
    Ahd,
    /// Lightmap encodings of the HHD model, C_a·H(n) + C_d·max(0, n·d), and its IrradZ forms
    /// (FORMULAS §8). A family of its own so that figures give AHD and HHD different hues.
    Hhd,
    /// The ambient cube.
    AmbientCube,
    /// The ambient dice.
    AmbientDice,
    /// Spherical Gaussians.
    SphericalGaussians,
    /// The H-basis.
    HBasis,
    /// Anything that declares no family (encoders outside the registry).
    Other,
}

impl Family {
    /// Every family, in the order legends list them.
    pub const ALL: [Family; 11] = [
        Family::Sh,
        Family::Zh3,
        Family::Geomerics,
        Family::ProbeOcclusion,
        Family::Ahd,
        Family::Hhd,
        Family::AmbientCube,
        Family::AmbientDice,
        Family::SphericalGaussians,
        Family::HBasis,
        Family::Other,
    ];

    /// The family's name in a legend.
    pub fn label(self) -> &'static str {
        match self {
            Family::Sh => "SH",
            Family::Zh3 => "ZH3",
            Family::Geomerics => "Geomerics L1",
            Family::ProbeOcclusion => "probe occlusion",
            Family::Ahd => "AHD",
            Family::Hhd => "HHD",
            Family::AmbientCube => "ambient cube",
            Family::AmbientDice => "ambient dice",
            Family::SphericalGaussians => "spherical Gaussians",
            Family::HBasis => "H-basis",
            Family::Other => "other",
        }
    }

    /// The family's place in [`Family::ALL`].
    pub fn index(self) -> usize {
        Family::ALL.iter().position(|f| *f == self).unwrap_or(Family::ALL.len() - 1)
    }
}

/// An encoding method with its settings.
pub trait Encoder: Send + Sync {
    /// The stable short id used in tables, on the command line and in file names.
    fn id(&self) -> &str;
    /// The family of the encoding ([`Family`]), for figures. Every registered encoder declares
    /// its own (a test checks that none is [`Family::Other`]).
    fn family(&self) -> Family {
        Family::Other
    }
    /// Scalars stored per probe or texel (RGB counts 3).
    fn stored_scalars(&self) -> usize;
    /// Bytes stored per probe or texel: by default [`HALF_BYTES`] per stored scalar (each an
    /// IEEE 754 binary16 half float, the usual GPU storage of an unquantised probe); quantised
    /// encodings give their serialised length instead (FORMULAS §11: 13, 16, 28 bytes), the
    /// length their encoder writes. Per-point data beside the probe (a cone, an AO term) is not
    /// counted, as in `stored_scalars`.
    fn stored_bytes(&self) -> usize {
        HALF_BYTES * self.stored_scalars()
    }
    /// What the encoding stores for the fit of `input`, in words for a figure's label: by
    /// default "`stored_scalars` scalars". An encoding that also needs data kept per shaded
    /// point beside the probe (a visibility cone, an AO term) says so, e.g. "27 per probe + cone
    /// (4) per point"; the table's `stored_scalars` column keeps counting the probe's alone.
    fn storage(&self, input: &FitInput) -> String {
        let _ = input;
        format!("{} scalars", self.stored_scalars())
    }
    /// The scalars the encoding reads per shaded point beside the probe for the fit of `input`
    /// (a visibility cone, an AO term), the ones [`Encoder::storage`] names; the surface normal
    /// N, the surface's own, is not counted. 0 by default.
    fn scalars_per_point(&self, input: &FitInput) -> usize {
        let _ = input;
        0
    }
    /// Fits the encoding.
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted>;
    /// Fits each of `probes` on the sphere, as [`Encoder::fit`] of [`FitInput::sphere`] does,
    /// and hands each fit with its index to `visit`, in order: the batch form probe sets score
    /// through. By default one boxed fit at a time; an encoder may override it to build the
    /// same fits without allocating ([`fit_each_unboxed`]).
    fn fit_sphere_each(&self, probes: &[Sh9], visit: &mut dyn FnMut(usize, &dyn Fitted)) {
        for (i, p) in probes.iter().enumerate() {
            visit(i, self.fit(&FitInput::sphere(p)).as_ref());
        }
    }
    /// The closed-form sphere error ([`Fitted::sphere_sq_error`]) of the sphere fit of each of
    /// `probes` against its E/π SH3 `irradiance[i]`, which must be `probes[i].convolve_cosine()`,
    /// written to `out[i]`: the numbers of the fits, bit for bit, without handing each fit to a
    /// visitor (probe sets score through it). False (the default) when the encoder has no such
    /// batch; `out` is then to be ignored and the caller fits each probe.
    fn sphere_sq_errors(&self, probes: &[Sh9], irradiance: &[Sh9], out: &mut [f64]) -> bool {
        let _ = (probes, irradiance, out);
        false
    }
    /// Whether the peer tool clamps this encoder's output at zero before scoring
    /// (FORMULAS §10); only `--metric probulator` reads this.
    fn peer_clamps(&self) -> bool {
        true
    }
    /// Whether the fit reads the light beyond its L2 SH, through [`FitInput::radiance`]
    /// (SH bands 3–4, radiance samples or the exact E/π at given normals). A probe set stores
    /// L2 SH only, so `probes` leaves these out of `--encoders all` and refuses them by name:
    /// fitted to the band-limited radiance of an L2 probe they would measure something else.
    fn reads_radiance(&self) -> bool {
        false
    }
    /// Whether the fit runs an iterative solver (a nonlinear least-squares or optimisation
    /// loop) rather than a closed form. `probelab check` gives iterative encoders the looser
    /// tolerances of `tolerances.toml` (`class = "iterative"`).
    fn is_iterative(&self) -> bool {
        false
    }
    /// Whether the encoding is defined only on the hemisphere about a surface normal N: its fit
    /// reads `FitInput::surface_normal` and its output means something only for n′·N ≥ 0. The
    /// experiment loader refuses such an encoder unless the domain is `hemisphere`, naming the
    /// file and the encoder (`pipeline::experiment::check_surface_encoders`), and probe sets
    /// (spheres, no N) refuse it or leave it out of `all`; so it is never scored where it is
    /// not defined. The H-basis, the AHD/HHD lightmap encoders (all, `hhd_from_sh1` too), every
    /// probe-occlusion operator except the unoccluded leak baseline, and `with_self_bounce`
    /// around any of these say so. Without N, `fit` must still return a documented answer
    /// (encoders cannot fail). [`surface_normal_refusal`] is the reason the refusals give.
    fn needs_surface_normal(&self) -> bool {
        false
    }
    /// True for encodings that deliberately lose or bias information — quantised storage, or a
    /// peer tool's biased variant kept for cross-checks. They are exempt from the hard cases'
    /// "no usable direction → no worse than pure ambient" bound; every other check applies.
    fn degrades_input(&self) -> bool {
        false
    }

    // Promises. Each is false (or `None`) unless the encoder overrides it, and each one an
    // encoder makes is checked for it on every hard case (`src/tests/encoder_hard_cases.rs`) and on
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
    /// The stored form of this fit ([`Stored`]): the values a bake would ship, named as the
    /// papers name them, with units and the reconstruction they feed (FORMULAS §1–2 for units,
    /// directions and the SH convention). Its stored scalars number exactly
    /// [`Encoder::stored_scalars`] of the encoder that made the fit; derived entries (axes,
    /// decoded colours, fixed lobes) are listed too, marked derived and not counted.
    fn stored(&self) -> Stored;
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
        Some(sh3_sq_error(&self.sh3()?, reference))
    }
}

/// ∫ over the sphere of |E_c(n) − E_r(n)|² dω summed over RGB, for two E/π SH3 `c` and `r`:
/// Σ_i |c_i − r_i|² (Parseval).
pub fn sh3_sq_error(c: &Sh9, r: &Sh9) -> f64 {
    (0..crate::math::sh::N_SH).map(|i| (c[i] - r[i]).length_squared()).sum()
}

/// [`Encoder::fit_sphere_each`] for an encoder whose sphere fit of a probe is `fit(probe)`, a
/// value: each fit lives on the stack while `visit` reads it.
pub fn fit_each_unboxed<F: Fitted>(probes: &[Sh9], visit: &mut dyn FnMut(usize, &dyn Fitted), fit: impl Fn(&Sh9) -> F) {
    for (i, p) in probes.iter().enumerate() {
        visit(i, &fit(p));
    }
}

/// [`Encoder::sphere_sq_errors`] for an encoder whose sphere fit of a probe is `fit(probe)`, a
/// value with a closed-form error: each fit lives on the stack, its error called statically.
/// False as soon as a fit has no closed form.
pub fn sq_errors_unboxed<F: Fitted>(
    probes: &[Sh9],
    irradiance: &[Sh9],
    out: &mut [f64],
    fit: impl Fn(&Sh9) -> F,
) -> bool {
    for ((p, r), o) in probes.iter().zip(irradiance).zip(out) {
        match fit(p).sphere_sq_error(r) {
            Some(e) => *o = e,
            None => return false,
        }
    }
    true
}

/// Encoder settings from an experiment file or the command line. Every key must be read:
/// [`Params::finish`] rejects the ones no encoder asked for (pbrt's `ReportUnused`). Every
/// numeric setting declares its valid range where it is read ([`Params::f64_in`],
/// [`Params::usize_in`], [`Params::weights_or`]): this is the one place settings are checked,
/// so no NaN, infinity or out-of-range value reaches a fit.
#[derive(Clone, Debug, Default)]
pub struct Params {
    table: toml::Table,
    used: Vec<String>,
}

impl Params {
    /// Wraps a settings table; no key counts as read yet.
    pub fn new(table: toml::Table) -> Self {
        Params { table, used: Vec::new() }
    }

    /// An optional float with a default, which must lie in `range` (its declared valid range;
    /// NaN and ±Inf never do). TOML integers are read as floats. The error names the key, the
    /// range and the value: `key 'tolerance_rad': expected a number in (0, 3.14], got 0`.
    pub fn f64_in(&mut self, key: &str, default: f64, range: impl RangeBounds<f64>) -> Result<f64> {
        debug_assert!(range.contains(&default), "key '{key}': the default {default} is outside its range");
        self.used.push(key.into());
        let v = match self.table.get(key) {
            None => return Ok(default),
            Some(toml::Value::Float(f)) => *f,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(v) => bail!("key '{key}': expected a number in {}, got {}", interval(&range), echo(v)),
        };
        if !v.is_finite() || !range.contains(&v) {
            bail!("key '{key}': expected a number in {}, got {}", interval(&range), short(v));
        }
        Ok(v)
    }

    /// An optional integer with a default, which must lie in `range` (its declared valid
    /// range). The error names the key, the range and the value.
    pub fn usize_in(&mut self, key: &str, default: usize, range: RangeInclusive<usize>) -> Result<usize> {
        debug_assert!(range.contains(&default), "key '{key}': the default {default} is outside its range");
        self.used.push(key.into());
        let bad = |v: &dyn std::fmt::Display| {
            anyhow::anyhow!("key '{key}': expected an integer in [{}, {}], got {}", range.start(), range.end(), echo(v))
        };
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(i)) => match usize::try_from(*i) {
                Ok(u) if range.contains(&u) => Ok(u),
                _ => Err(bad(i)),
            },
            Some(v) => Err(bad(v)),
        }
    }

    /// An optional string with a default.
    pub fn str_or(&mut self, key: &str, default: &str) -> Result<String> {
        self.used.push(key.into());
        match self.table.get(key) {
            None => Ok(default.to_string()),
            Some(toml::Value::String(s)) => Ok(s.clone()),
            Some(v) => bail!("key '{key}': expected a string, got {}", echo(v)),
        }
    }

    /// An optional channel weighting with a default: a named weighting (`rec709`, `equal`) or
    /// `[r, g, b]`, each weight in [0, 1e6] and the largest positive. Channel weights are
    /// relative, so the upper bound loses nothing and keeps every weighted sum finite.
    pub fn weights_or(&mut self, key: &str, default: Rgb) -> Result<Rgb> {
        self.used.push(key.into());
        let range = "[r, g, b] with each weight in [0, 1e6] and not all 0, or 'rec709'/'equal'";
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::String(s)) => named_weights(s).with_context(|| format!("key '{key}'")),
            Some(toml::Value::Array(a)) if a.len() == 3 => {
                let mut v = [0.0; 3];
                for (o, x) in v.iter_mut().zip(a) {
                    *o = match x {
                        toml::Value::Float(f) => *f,
                        toml::Value::Integer(i) => *i as f64,
                        _ => bail!("key '{key}': expected {range}, got {}", echo(x)),
                    };
                }
                if v.iter().any(|w| !(0.0..=MAX_WEIGHT).contains(w)) || v.iter().all(|w| *w == 0.0) {
                    bail!("key '{key}': expected {range}, got [{}, {}, {}]", short(v[0]), short(v[1]), short(v[2]));
                }
                Ok(Rgb::from_array(v))
            }
            Some(v) => bail!("key '{key}': expected {range}, got {}", echo(v)),
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
                unused.iter().map(|s| format!("'{}'", echo(s))).collect::<Vec<_>>().join(", "),
                if known.is_empty() { "no keys".to_string() } else { known.join(", ") }
            );
        }
        Ok(())
    }
}

/// A number as a message shows it: shortest round trip, in exponent form when large or small.
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A range in interval notation: `[0, 1]`, `(0, 90)`, `[1, inf)`.
fn interval(r: &impl RangeBounds<f64>) -> String {
    let lo = match r.start_bound() {
        Bound::Included(a) => format!("[{a}"),
        Bound::Excluded(a) => format!("({a}"),
        Bound::Unbounded => "(-inf".to_string(),
    };
    let hi = match r.end_bound() {
        Bound::Included(b) => format!("{b}]"),
        Bound::Excluded(b) => format!("{b})"),
        Bound::Unbounded => "inf)".to_string(),
    };
    format!("{lo}, {hi}")
}

/// A value from a settings table as an error echoes it (`math::echo`).
fn echo(v: &dyn std::fmt::Display) -> String {
    crate::math::echo::value(&v.to_string())
}

/// Channel weightings by name: `rec709` (0.2126, 0.7152, 0.0722) or `equal` (⅓ each).
pub fn named_weights(s: &str) -> Result<Rgb> {
    match s {
        "rec709" => Ok(crate::math::colour::REC709),
        "equal" => Ok(Rgb::splat(1.0 / 3.0)),
        _ => bail!("unknown weighting '{}' (expected rec709, equal or [r, g, b])", echo(&s)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(text: &str) -> Params {
        Params::new(toml::from_str(text).unwrap())
    }

    /// Every numeric setting is checked against its declared range, in one place; NaN and
    /// ±Inf (TOML `nan`, `inf`) are never in range; the error names key, range and value.
    #[test]
    fn numeric_settings_are_range_checked() {
        let err =
            |text: &str, f: &dyn Fn(&mut Params) -> Result<f64>| format!("{:#}", f(&mut params(text)).unwrap_err());
        let f = |p: &mut Params| p.f64_in("x", 1.0, (Bound::Excluded(0.0), Bound::Included(2.0)));
        assert_eq!(f(&mut params("")).unwrap(), 1.0);
        assert_eq!(f(&mut params("x = 2")).unwrap(), 2.0);
        assert_eq!(f(&mut params("x = 0.5")).unwrap(), 0.5);
        for bad in ["x = nan", "x = inf", "x = -inf", "x = 0.0", "x = 2.0000001", "x = 1e308", "x = 'a'"] {
            let e = err(bad, &f);
            assert!(e.starts_with("key 'x': expected a number in (0, 2], got "), "{bad}: {e}");
        }
        assert!(err("x = 1e308", &f).ends_with("got 1e308"));
        let u = |p: &mut Params| p.usize_in("m", 5, 1..=64).map(|v| v as f64);
        assert_eq!(u(&mut params("m = 64")).unwrap(), 64.0);
        for bad in ["m = 0", "m = 65", "m = -1", "m = 1000000000000000000", "m = 1.0", "m = nan"] {
            let e = err(bad, &u);
            assert!(e.starts_with("key 'm': expected an integer in [1, 64], got "), "{bad}: {e}");
        }
    }

    #[test]
    fn weights_are_finite_bounded_and_not_all_zero() {
        let w = |text: &str| params(text).weights_or("w", Rgb::ONE);
        assert_eq!(w("").unwrap(), Rgb::ONE);
        assert_eq!(w("w = [1, 0, 2.5]").unwrap(), Rgb::new(1.0, 0.0, 2.5));
        assert_eq!(w("w = 'rec709'").unwrap(), crate::math::colour::REC709);
        for bad in [
            "w = [nan, 1, 1]",
            "w = [inf, 1, 1]",
            "w = [0, 0, 0]",
            "w = [-1, 1, 1]",
            "w = [1e7, 1, 1]",
            "w = [1, 1]",
            "w = 'red'",
        ] {
            let e = format!("{:#}", w(bad).unwrap_err());
            assert!(e.starts_with("key 'w'"), "{bad}: {e}");
        }
    }
}
