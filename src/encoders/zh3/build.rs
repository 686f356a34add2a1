//! The ZH3 encoders' TOML settings and their builders: one configuration per registered kind
//! (the registry's `build_*`), and [`configured`] for a caller that needs the concrete encoder.

use crate::encoders::encoder::{named_weights, Encoder, Params};
use crate::encoders::zh3::encoder::{Method, Zh3Encoder};
use crate::encoders::zh3::model::AxisRule;
use crate::encoders::zh3::solve::{Curve, Formulation, LineSearch, SolverSettings, Zonal};
use crate::math::colour::Rgb;
use anyhow::{bail, Context, Result};

/// Reads a weighting key: `"rec709"`, `"equal"` or `[r, g, b]` (non-negative, not all 0).
fn weights(p: &mut Params, key: &str, default: &str) -> Result<Rgb> {
    p.weights_or(key, named_weights(default)?)
}

/// Error weights must be positive: a channel whose error costs nothing has no defined fit.
fn error_weights(p: &mut Params) -> Result<Rgb> {
    let w = weights(p, "error_weights", "equal")?;
    if w.min_element() <= 0.0 {
        bail!("key 'error_weights': every weight must be positive, got {w}");
    }
    Ok(w)
}

fn curve(p: &mut Params) -> Result<Curve> {
    // f/L00 = c1 r + c2 r² + c3 r³ with r ≤ √3: the paper's coefficients are below 1, and
    // ±100 keeps every fitted coefficient (and its score) far from overflow.
    let c = [
        p.f64_in("curve_c1", 0.08, -100.0..=100.0)?,
        p.f64_in("curve_c2", 0.6, -100.0..=100.0)?,
        p.f64_in("curve_c3", 0.0, -100.0..=100.0)?,
    ];
    Ok(Curve::Poly(c))
}

/// Solver keys; `formulation` only for stored solves (hallucinated solves use the L1).
fn settings(p: &mut Params, stored: bool) -> Result<SolverSettings> {
    let d = SolverSettings::default();
    let formulation = if stored {
        match p.str_or("formulation", "axis")?.as_str() {
            "axis" => Formulation::Axis,
            "l1" => Formulation::L1,
            f => bail!("key 'formulation': expected \"axis\" or \"l1\", got '{f}'"),
        }
    } else {
        Formulation::L1
    };
    let s = SolverSettings {
        // L-BFGS converges in tens of iterations here (benches/README.md); the caps bound the
        // run time and the memory argmin allocates (`memory` correction pairs).
        max_iters: p.usize_in("max_iters", d.max_iters as usize, 1..=10_000)? as u64,
        tol_grad: p.f64_in("tol_grad", d.tol_grad, 0.0..=1.0)?,
        tol_cost: p.f64_in("tol_cost", d.tol_cost, 0.0..=1.0)?,
        memory: p.usize_in("memory", d.memory, 1..=64)?,
        starts: p.usize_in("starts", d.starts, 1..=5)?,
        formulation,
        screen: if stored { p.usize_in("screen", d.screen, 0..=10_000)? } else { 0 },
        line_search: match p.str_or("line_search", "more_thuente")?.as_str() {
            "backtracking" => LineSearch::Backtracking,
            "more_thuente" => LineSearch::MoreThuente,
            l => bail!("key 'line_search': expected \"backtracking\" or \"more_thuente\", got '{l}'"),
        },
        skip_futile: d.skip_futile,
    };
    Ok(s)
}

fn quantise_key(p: &mut Params) -> Result<bool> {
    match p.str_or("quantise", "none")?.as_str() {
        "none" => Ok(false),
        "ratio8" => Ok(true),
        q => bail!("key 'quantise': expected \"none\" or \"ratio8\", got '{q}'"),
    }
}

fn make(
    p: &mut Params,
    id: &'static str,
    method: Method,
    rule: AxisRule,
    err_w: Rgb,
    settings: SolverSettings,
) -> Result<Zh3Encoder> {
    let quantise = quantise_key(p)?;
    p.finish(id)?;
    Ok(Zh3Encoder { id, method, rule, err_w, settings, quantise })
}

/// A storage format the talk names, as its own id: the encoder `configure` builds (which reads
/// the other keys), always ratio-quantised (FORMULAS §11), under `id`. Its `quantise` key is
/// rejected: the id is the format.
fn stored_format(p: &mut Params, id: &'static str, configure: Configure) -> Result<Zh3Encoder> {
    if p.value("quantise").is_some() {
        bail!("key 'quantise': '{id}' is always stored ratio-quantised; it takes no 'quantise' key");
    }
    let e = configure(p)?;
    Ok(Zh3Encoder { id, quantise: true, ..e })
}
/// Stored ZH3 in the talk's 16 bytes: the paper's solve (`zh3_solved_shared`), quantised.
fn q16_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    stored_format(p, "zh3_q16", solved_shared_encoder)
}
/// Hallucinated ZH3 in the talk's 13 bytes (the quantised L1; the zonal coefficient is the
/// shader's curve): `zh3_hallucinate`, quantised.
fn hallucinate_q13_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    stored_format(p, "zh3_hallucinate_q13", hallucinate_encoder)
}

fn hallucinate_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "rec709")?);
    let c = curve(p)?;
    make(p, "zh3_hallucinate", Method::Hallucinate(c), rule, Rgb::ZERO, SolverSettings::default())
}
fn hallucinate_channel_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let c = curve(p)?;
    make(p, "zh3_hallucinate_channel", Method::Hallucinate(c), AxisRule::Channel, Rgb::ZERO, SolverSettings::default())
}
fn hallucinate_ambdir_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "rec709")?);
    let m = Method::Hallucinate(Curve::AmbientDirectional);
    make(p, "zh3_hallucinate_ambdir", m, rule, Rgb::ZERO, SolverSettings::default())
}
fn hallucinate_sphere_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "rec709")?);
    let m = Method::Hallucinate(Curve::SphereLight);
    make(p, "zh3_hallucinate_sphere", m, rule, Rgb::ZERO, SolverSettings::default())
}
fn stored_channel_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    make(p, "zh3_stored_channel", Method::Stored, AxisRule::Channel, Rgb::ZERO, SolverSettings::default())
}
fn stored_shared_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "equal")?);
    make(p, "zh3_stored_shared", Method::Stored, rule, Rgb::ZERO, SolverSettings::default())
}
fn solved_channel_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let s = settings(p, true)?;
    make(p, "zh3_solved_channel", Method::Solved(Zonal::Stored), AxisRule::Channel, Rgb::ONE, s)
}
fn solved_shared_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "equal")?);
    let err_w = error_weights(p)?;
    let s = settings(p, true)?;
    make(p, "zh3_solved_shared", Method::Solved(Zonal::Stored), rule, err_w, s)
}
fn hallucinate_solved_encoder(p: &mut Params) -> Result<Zh3Encoder> {
    let rule = AxisRule::Shared(weights(p, "axis_weights", "equal")?);
    let err_w = error_weights(p)?;
    let c = curve(p)?;
    let s = settings(p, false)?;
    make(p, "zh3_hallucinate_solved", Method::Solved(Zonal::Hallucinated(c)), rule, err_w, s)
}

/// The ZH3 kinds and their configurations (the registry's `build_*` box these).
pub(super) type Configure = fn(&mut Params) -> Result<Zh3Encoder>;
pub(super) const KINDS: [(&str, Configure); 11] = [
    ("zh3_hallucinate", hallucinate_encoder),
    ("zh3_hallucinate_channel", hallucinate_channel_encoder),
    ("zh3_hallucinate_ambdir", hallucinate_ambdir_encoder),
    ("zh3_hallucinate_sphere", hallucinate_sphere_encoder),
    ("zh3_stored_channel", stored_channel_encoder),
    ("zh3_stored_shared", stored_shared_encoder),
    ("zh3_solved_channel", solved_channel_encoder),
    ("zh3_solved_shared", solved_shared_encoder),
    ("zh3_hallucinate_solved", hallucinate_solved_encoder),
    ("zh3_q16", q16_encoder),
    ("zh3_hallucinate_q13", hallucinate_q13_encoder),
];

/// Builds the `zh3_hallucinate` encoder from its settings: ZH3 hallucinated, curve fit, Rec.709
/// axis. An unknown or out-of-range setting is an error.
pub fn build_hallucinate(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_encoder(p)?))
}
/// Builds the `zh3_hallucinate_channel` encoder from its settings: ZH3 hallucinated, curve fit,
/// per-channel axes. An unknown or out-of-range setting is an error.
pub fn build_hallucinate_channel(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_channel_encoder(p)?))
}
/// Builds the `zh3_hallucinate_ambdir` encoder from its settings: ZH3 hallucinated,
/// ambient+directional model. An unknown or out-of-range setting is an error.
pub fn build_hallucinate_ambdir(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_ambdir_encoder(p)?))
}
/// Builds the `zh3_hallucinate_sphere` encoder from its settings: ZH3 hallucinated, sphere-light
/// model. An unknown or out-of-range setting is an error.
pub fn build_hallucinate_sphere(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_sphere_encoder(p)?))
}
/// Builds the `zh3_stored_channel` encoder from its settings: ZH3 stored, per-channel L1 axes. An
/// unknown or out-of-range setting is an error.
pub fn build_stored_channel(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(stored_channel_encoder(p)?))
}
/// Builds the `zh3_stored_shared` encoder from its settings: ZH3 stored, shared equal-weight L1
/// axis. An unknown or out-of-range setting is an error.
pub fn build_stored_shared(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(stored_shared_encoder(p)?))
}
/// Builds the `zh3_solved_channel` encoder from its settings: ZH3 stored, axis solved per channel
/// (L-BFGS). An unknown or out-of-range setting is an error.
pub fn build_solved_channel(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(solved_channel_encoder(p)?))
}
/// Builds the `zh3_solved_shared` encoder from its settings: ZH3 stored, shared axis solved
/// (L-BFGS). An unknown or out-of-range setting is an error.
pub fn build_solved_shared(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(solved_shared_encoder(p)?))
}
/// Builds the `zh3_hallucinate_solved` encoder from its settings: ZH3 hallucinated from a solved
/// L1, shared axis. An unknown or out-of-range setting is an error.
pub fn build_hallucinate_solved(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_solved_encoder(p)?))
}

/// Builds the `zh3_q16` encoder from its settings: stored ZH3 in 16 bytes (the shared solved
/// axis, ratio-quantised). An unknown or out-of-range setting is an error.
pub fn build_q16(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(q16_encoder(p)?))
}
/// Builds the `zh3_hallucinate_q13` encoder from its settings: hallucinated ZH3 in 13 bytes
/// (the quantised L1). An unknown or out-of-range setting is an error.
pub fn build_hallucinate_q13(p: &mut Params) -> Result<Box<dyn Encoder>> {
    Ok(Box::new(hallucinate_q13_encoder(p)?))
}

/// The concrete encoder of a ZH3 kind with TOML settings — what `encoders::build` boxes —
/// for a caller that needs the ZH3 itself or its stored bytes (claim Z10's byte counts).
pub fn configured(kind: &str, params: toml::Table) -> Result<Zh3Encoder> {
    let Some((_, f)) = KINDS.iter().find(|(k, _)| *k == kind) else {
        bail!("'{kind}' is not a ZH3 encoder (known: {})", KINDS.map(|k| k.0).join(", "));
    };
    let mut p = Params::new(params);
    f(&mut p).with_context(|| format!("configuring encoder '{kind}'"))
}
