//! SH probes under occlusion: the light-probe half of the hemispherical-lighting talk
//! (Roughton, Sloan, Silvennoinen, Shirley, SIGGRAPH 2024 Advances; `../shared/papers/
//! hemispherical-lighting-insights-talk-2024.txt`, the part after "light probes"), FORMULAS §8–9.
//!
//! A probe stores world-space L2 SH of radiance (`probe_sh`). A surface with vertex normal N
//! samples it at normal-mapped normals n′; light below N's horizon must be occluded or normal
//! maps glow. Every operator here is fitted from the probe SH and the surface normal N (and the
//! visibility cone, if one is declared), never from the reference.
//!
//! | id                 | what | per-normal payload |
//! |--------------------|------|--------------------|
//! | `probe_unoccluded` | L2 SH irradiance at n′, ignoring the surface: the light-leak baseline | 27 |
//! | `probe_hemi_full`  | radiance × hemisphere about N by the full L2 hemispherical Gram rotated to N (rotate to tangent space, multiply, rotate back); L2 output | 27 |
//! | `probe_cone_full`  | the same with the cone Gram about the cone centre (hemisphere about N if no cone is declared) | 27 |
//! | `probe_hemi_q2l`   | the talk's world-space quadratic-to-linear hemisphere multiply: no SH rotation, linear output | 12 |
//! | `hlsh`             | HLSH: linear over the hemisphere about N with the value at N pinned to I_z | 12 |
//! | `probe_hhd_lum`    | the low-end path: q2l multiply, then a luminance HHD solve from linear SH (§8), tinted by the RGB I_z | 6 |
//! | `cone_multiply`    | HLSH with the cone Gram for cos α about the cone centre C; cos α = 0 about N is `hlsh` | 12 |
//! | `ao_scale`         | L2 SH irradiance at n′ × the cone's cosine-weighted visibility about N (the usual AO) | 28 |
//! | `bent_normal`      | L2 SH irradiance at the cone centre (the bent normal) × the same visibility; constant in n′ | 3 |
//!
//! The payload is what the per-normal evaluation reads after the per-N fit. Every operator
//! stores the same probe, so `stored_scalars` is 27 for all of them; what each reads per
//! shaded point beside the probe (N; the cone C and cos α, 4 scalars, for `probe_cone_full`
//! and `cone_multiply`; the visibility, 1, for `ao_scale`; bent normal and visibility, 4, for
//! `bent_normal`) is in its `Encoder::storage`, which the sheets print.
//!
//! TOML keys: `probe_hemi_full` and `probe_cone_full` take `output_bands` (1 or 2, default 2;
//! 1 truncates the output to the linear band, which is what `probe_hemi_q2l` equals);
//! `probe_hhd_lum` takes `weights` (`rec709` default, `equal`, or `[r, g, b]`) for luminance;
//! `hlsh` and `cone_multiply` take `iz` (`pinned`, default: HLSH; `fitted`: the value at the axis
//! is fitted by least squares too, an ablation that shows what the I_z pin costs or gains).
//!
//! **HLSH as implemented (derived; the talk's ShaderToy was not available).** In the frame of
//! the axis A (N, or the cone centre C: "we always take the normal for the multiply to be the
//! cone centre") with z′ = n′·A, the model is E(n′) = I_z·z′ + a·(1 − z′) + t·n′ with t ⊥ A:
//! linear in n′, its value at A is I_z ("the weight for the z basis function is always given by
//! IrradZ"). I_z = (1/π)∫_V L₂(ω)(ω·A)dω is the exact irradiance at A of the visible part V of
//! the L2 radiance (visible part ∩ A's hemisphere when cos α < 0), read from the exact first
//! moments of the multiply. a and t minimise the solid-angle-weighted squared error over A's
//! hemisphere against the irradiance of the full L2 multiply (radiance × V projected to L2,
//! cosine-convolved), which is the exact irradiance of the visible L2 radiance up to its bands
//! ≥ 4 (Â₄ = −1/24). Only the m = 0 and m = ±1 parts about A enter (`gram::axial_parts`), so
//! the fit is a few dot products in world space, like the quadratic-to-linear multiply.
//!
//! **Fallbacks** (encoders cannot fail): with no surface normal (a sphere domain) every
//! operator is `probe_unoccluded` and reports `no_normal=1`; with no declared cone the cone
//! operators use the hemisphere about N (cos α = 0, C = N, visibility 1).

use crate::encoders::encoder::{named_weights, Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::lightmap::from_sh1::solve_channel;
use crate::encoders::sh::ShIrradiance;
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::gram::{axial_parts, multiply_full, multiply_to_linear, AxialGram, AxialParts};
use crate::math::sh::{k, Sh9};
use anyhow::{bail, Result};
use glam::DVec3;
use std::f64::consts::PI;

/// Which operator.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Unoccluded,
    Full { cone: bool, bands: usize },
    Q2l,
    Hlsh { cone: bool, pin_iz: bool },
    HhdLum { weights: Rgb },
    AoScale,
    BentNormal,
}

/// An occlusion operator on a world-space L2 radiance probe.
pub struct ProbeOp {
    id: &'static str,
    op: Op,
    /// HLSH for the hemisphere (cos α = 0), built once.
    hemi: HlshOperator,
    /// The hemisphere's axial Gram, built once.
    hemi_gram: AxialGram,
}

impl ProbeOp {
    fn new(id: &'static str, op: Op) -> Self {
        let pin_iz = !matches!(op, Op::Hlsh { pin_iz: false, .. });
        ProbeOp { id, op, hemi: HlshOperator::new(0.0, pin_iz), hemi_gram: AxialGram::cone(0.0) }
    }
}

/// The visibility the operator multiplies by about the surface normal `n`: (axis, cos α), the
/// declared cone when `use_cone` and there is one, else the hemisphere about `n`.
fn visibility(n: DVec3, input: &FitInput, use_cone: bool) -> (DVec3, f64) {
    match input.cone {
        Some((c, cos_alpha)) if use_cone => (c.normalize(), cos_alpha),
        _ => (n, 0.0),
    }
}

impl ProbeOp {
    /// What the operator reads per shaded point beside the probe, and how many scalars (the
    /// module doc's table): the cone operators the declared cone, centre C and cos α (4);
    /// `ao_scale` its cosine-weighted visibility (1); `bent_normal` the bent normal C and that
    /// visibility (4). Without a declared cone they fall back to the hemisphere about N and read
    /// nothing but N (0); without N, or as `probe_unoccluded`, nothing is read per point (None).
    fn per_point(&self, input: &FitInput) -> Option<(&'static str, usize)> {
        if input.surface_normal.is_none() || self.op == Op::Unoccluded {
            return None;
        }
        let cone = input.cone.is_some();
        Some(match self.op {
            Op::Full { cone: true, .. } | Op::Hlsh { cone: true, .. } if cone => ("cone", 4),
            Op::AoScale if cone => ("AO", 1),
            Op::BentNormal if cone => ("bent normal, AO", 4),
            _ => ("N", 0),
        })
    }
}

impl Encoder for ProbeOp {
    fn id(&self) -> &str {
        self.id
    }
    fn family(&self) -> Family {
        Family::ProbeOcclusion
    }
    fn stored_scalars(&self) -> usize {
        27
    }
    /// The probe's 27 SH coefficients, plus what the operator reads per shaded point beside N
    /// (`ProbeOp::per_point`).
    fn storage(&self, input: &FitInput) -> String {
        let probe = "27 per probe";
        match self.per_point(input) {
            None => probe.into(),
            Some((_, 0)) => format!("{probe}, N per point"),
            Some((what, n)) => format!("{probe} + {what} ({n}) per point"),
        }
    }
    fn scalars_per_point(&self, input: &FitInput) -> usize {
        self.per_point(input).map_or(0, |(_, n)| n)
    }
    /// Every operator but `probe_unoccluded` multiplies the probe by the visibility about the
    /// surface normal N (or the cone about it); without N it is `probe_unoccluded` in disguise.
    /// `probe_unoccluded` ignores the surface by definition (the leak baseline) and is defined
    /// on the whole sphere.
    fn needs_surface_normal(&self) -> bool {
        self.op != Op::Unoccluded
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let f = input.probe_sh;
        let Some(n) = input.surface_normal.map(|n| n.normalize()) else {
            return self.fitted(f, Payload::Fallback(ShIrradiance(f.convolve_cosine(), 2)));
        };
        let payload = match self.op {
            Op::Unoccluded => Payload::Sh(ShIrradiance(f.convolve_cosine(), 2)),
            Op::Full { cone, bands } => {
                let (axis, c) = visibility(n, input, cone);
                Payload::Sh(ShIrradiance(multiply_full(f, c, axis).truncate(bands).convolve_cosine(), bands))
            }
            Op::Q2l => {
                Payload::Linear(Linear::from_linear_sh(&multiply_to_linear(&axial_parts(f, n), &self.hemi_gram)))
            }
            Op::Hlsh { cone, pin_iz } => {
                let (axis, c) = visibility(n, input, cone);
                let parts = axial_parts(f, axis);
                let fit = if c == 0.0 { self.hemi.fit(&parts) } else { HlshOperator::new(c, pin_iz).fit(&parts) };
                Payload::Linear(fit)
            }
            Op::HhdLum { weights } => {
                let lin = multiply_to_linear(&axial_parts(f, n), &self.hemi_gram);
                Payload::HhdLum(HhdLum::fit(&lin, n, weights))
            }
            Op::AoScale => {
                let (c, cos_alpha) = visibility(n, input, true);
                let ao = cone_visibility(n, c, cos_alpha);
                Payload::Sh(ShIrradiance(f.convolve_cosine() * ao, 2))
            }
            Op::BentNormal => {
                let (c, cos_alpha) = visibility(n, input, true);
                let ao = cone_visibility(n, c, cos_alpha);
                Payload::Constant(Constant(f.convolve_cosine().eval(c) * ao))
            }
        };
        self.fitted(f, payload)
    }
}

impl ProbeOp {
    /// The fit: the stored probe and the operator's per-normal payload.
    fn fitted(&self, probe: &Sh9, payload: Payload) -> Box<dyn Fitted> {
        Box::new(OccludedProbe { id: self.id, probe: *probe, payload })
    }
}

/// What an operator evaluates per normal after its per-N fit.
enum Payload {
    /// No surface normal: `probe_unoccluded` in place of the operator (reports `no_normal`).
    Fallback(ShIrradiance),
    Sh(ShIrradiance),
    Linear(Linear),
    HhdLum(HhdLum),
    Constant(Constant),
}

/// A fitted operator: the probe it stores (27 scalars of radiance SH, the same for every
/// operator) and the payload it evaluates.
struct OccludedProbe {
    id: &'static str,
    probe: Sh9,
    payload: Payload,
}

impl OccludedProbe {
    fn payload(&self) -> &dyn Fitted {
        match &self.payload {
            Payload::Fallback(p) | Payload::Sh(p) => p,
            Payload::Linear(p) => p,
            Payload::HhdLum(p) => p,
            Payload::Constant(p) => p,
        }
    }
}

impl Fitted for OccludedProbe {
    #[inline]
    fn irradiance(&self, n: DVec3) -> Rgb {
        match &self.payload {
            Payload::Fallback(p) | Payload::Sh(p) => p.irradiance(n),
            Payload::Linear(p) => p.irradiance(n),
            Payload::HhdLum(p) => p.irradiance(n),
            Payload::Constant(p) => p.irradiance(n),
        }
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        match &self.payload {
            Payload::Fallback(_) => vec![("no_normal", 1.0)],
            _ => self.payload().diagnostics(),
        }
    }
    /// An SH payload is exactly its SH3 (the no-normal fallback is scored by quadrature).
    fn sh3(&self) -> Option<Sh9> {
        match &self.payload {
            Payload::Sh(p) => p.sh3(),
            _ => None,
        }
    }
    /// The probe's L2 radiance SH, stored (27 scalars, FORMULAS §2); the payload the operator
    /// computes from it at N, derived (`payload_*`).
    fn stored(&self) -> Stored {
        let inner = self.payload().stored();
        let mut s = Stored::new(format!(
            "the probe stores world-space L2 radiance SH (entries L{{l}}_{{m}}: the real orthonormal SH of \
             docs/conventions.md section 2); at a surface normal N the operator {} computes from it a per-normal \
             payload (the derived entries payload_*), which evaluates as: {}",
            self.id, inner.basis
        ));
        s.sh(Role::Stored, Unit::Radiance, &self.probe.0);
        s.entries.extend(inner.as_derived("payload_"));
        s
    }
}

/// E/π linear in the normal: dc + (g_r·n, g_g·n, g_b·n). Linear SH irradiance, HLSH.
#[derive(Clone, Copy, Debug)]
pub struct Linear {
    /// The constant term (E/π).
    pub dc: Rgb,
    /// Per channel, the gradient g such that the channel's E/π is dc + g·n.
    pub grad: [DVec3; 3],
}

impl Linear {
    /// The irradiance of a linear radiance SH: L₀₀Y₀₀ + (2/3)·√(3/4π)·b·n (FORMULAS §2–3).
    pub fn from_linear_sh(s: &Sh9) -> Self {
        let g = 2.0 / 3.0 * k::Y1;
        Linear { dc: s[0] * k::Y00, grad: std::array::from_fn(|ch| s.l1_vector(ch) * g) }
    }
}

impl Fitted for Linear {
    #[inline]
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.dc + Rgb::new(self.grad[0].dot(n), self.grad[1].dot(n), self.grad[2].dot(n))
    }
    /// dc and the gradient's x, y, z components (RGB each): 12 scalars.
    fn stored(&self) -> Stored {
        let g = &self.grad;
        let mut s = Stored::new("E/pi(n) = dc + grad_x*n_x + grad_y*n_y + grad_z*n_z per channel; world axes, +Y up");
        s.rgb("dc", Unit::Irradiance, self.dc)
            .rgb("grad_x", Unit::Irradiance, Rgb::new(g[0].x, g[1].x, g[2].x))
            .rgb("grad_y", Unit::Irradiance, Rgb::new(g[0].y, g[1].y, g[2].y))
            .rgb("grad_z", Unit::Irradiance, Rgb::new(g[0].z, g[1].z, g[2].z));
        s
    }
}

/// A constant E/π (the bent-normal lookup).
struct Constant(Rgb);

impl Fitted for Constant {
    fn irradiance(&self, _n: DVec3) -> Rgb {
        self.0
    }
    fn stored(&self) -> Stored {
        let mut s = Stored::new("E/pi(n) = E at every normal");
        s.rgb("E", Unit::Irradiance, self.0);
        s
    }
}

/// HLSH for a visibility cone of cos α = c about the axis (see the module doc). The fitted
/// E(n′) = dc + s·(n′·A) + t·n′ has dc and s linear in the m = 0 parts and t = β₁·b⊥ + β₂·q⊥.
#[derive(Clone, Copy, Debug)]
pub struct HlshOperator {
    /// dc and s as linear functions of the zonal parts (f₀, b·A, zonal band 2).
    w_dc: [f64; 3],
    w_s: [f64; 3],
    beta: [f64; 2],
}

impl HlshOperator {
    /// Builds the operator for cos α = c (c = 0: the hemisphere). With `pin_iz` the value at
    /// the axis is I_z (HLSH); without it, dc and s are fitted freely too (an ablation: the
    /// plain least-squares linear fit over the hemisphere).
    pub fn new(c: f64, pin_iz: bool) -> Self {
        let gv = AxialGram::cone(c);
        let gh = AxialGram::cone(0.0);
        let giz = AxialGram::cone(c.max(0.0));
        let scale = [1.0, 2.0 / 3.0, 0.25]; // Â on the zonal indices (0, 2, 6)
        let (mut w_int, mut w_intz, mut w_iz) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for j in 0..3 {
            // Response of ∫T, ∫T·z′ and I_z to the unit zonal input e_j.
            let o: [f64; 3] = std::array::from_fn(|i| gv.m0[i][j] * scale[i]);
            let mu0: f64 = (0..3).map(|i| gh.m0[0][i] * o[i]).sum();
            let mu2: f64 = (0..3).map(|i| gh.m0[1][i] * o[i]).sum();
            w_int[j] = mu0 / k::Y00;
            w_intz[j] = mu2 / k::Y1;
            w_iz[j] = giz.m0[1][j] / (k::Y1 * PI);
        }
        // a = (3/2π)(∫T − ∫T z′) − I_z/2, from the normal equations over the hemisphere with
        // ∫(1 − z′)² = 2π/3 and ∫z′(1 − z′) = π/3.
        let w_a: [f64; 3] = std::array::from_fn(|j| 1.5 / PI * (w_int[j] - w_intz[j]) - 0.5 * w_iz[j]);
        // E = I_z·z′ + a·(1 − z′): dc = a, s = I_z − a. Unpinned, the normal equations of
        // (dc, s) over the hemisphere, [[2π, π], [π, 2π/3]], give dc = (2∫T − 3∫T z′)/π and
        // s = (6∫T z′ − 3∫T)/π.
        let (w_dc, w_s) = if pin_iz {
            (w_a, std::array::from_fn(|j| w_iz[j] - w_a[j]))
        } else {
            (
                std::array::from_fn(|j| (2.0 * w_int[j] - 3.0 * w_intz[j]) / PI),
                std::array::from_fn(|j| (6.0 * w_intz[j] - 3.0 * w_int[j]) / PI),
            )
        };
        // t = ∫T·n′⊥ / (2π/3), with ∫T·(x′, y′) = (m = ±1 moments)/√(3/4π).
        let o1 = [gv.m1[0][0] * 2.0 / 3.0, gv.m1[1][0] * 0.25]; // response to b⊥
        let o2 = [gv.m1[0][1] * 2.0 / 3.0, gv.m1[1][1] * 0.25]; // response to q⊥
        let to_t = 1.5 / (PI * k::Y1);
        let beta =
            [(gh.m1[0][0] * o1[0] + gh.m1[0][1] * o1[1]) * to_t, (gh.m1[0][0] * o2[0] + gh.m1[0][1] * o2[1]) * to_t];
        HlshOperator { w_dc, w_s, beta }
    }

    /// The HLSH irradiance of the SH whose parts about the axis are `p`.
    pub fn fit(&self, p: &AxialParts) -> Linear {
        let z = &p.zonal;
        let dc = z[0] * self.w_dc[0] + z[1] * self.w_dc[1] + z[2] * self.w_dc[2];
        let s = z[0] * self.w_s[0] + z[1] * self.w_s[1] + z[2] * self.w_s[2];
        let grad = std::array::from_fn(|ch| p.axis * s[ch] + p.b_perp[ch] * self.beta[0] + p.q_perp[ch] * self.beta[1]);
        Linear { dc, grad }
    }
}

/// HHD (FORMULAS §8): a hemisphere light of radiance C_a about N plus a delta light
/// π·C_d·δ(ω − d); E/π(n) = C_a·(1 + n·N)/2 + C_d·max(0, n·d).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hhd {
    /// Radiance C_a of the hemisphere light (one channel).
    pub ca: f64,
    /// C_d: E/π of the delta light facing it (one channel).
    pub cd: f64,
    /// Unit direction d of the delta light (N when C_d = 0).
    pub d: DVec3,
}

/// What the probe path had to repair after the closed form.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HhdFlags {
    /// C_a fell outside [0, I_z] and was clamped, keeping I_z exact and d above the horizon.
    pub ca_clamped: bool,
}

/// The single-channel HHD of the probe path, from the linear radiance SH (l₀, band-1 vector
/// (−l₁,₁, −l₁,₋₁, l₁,₀)) of light over the hemisphere about N: the talk's closed form
/// ([`solve_channel`], FORMULAS §8), then C_d = |b − C_a·N|, d = (b − C_a·N)/C_d.
/// Where the slide is silent: C_a is clamped to [0, max(I_z, 0)] (so d·N ≥ 0 and b·N = I_z
/// stays exact); C_d = 0 gives d = N.
pub fn clamped_hhd(l0: f64, l1: DVec3, n: DVec3) -> (Hhd, HhdFlags) {
    let ch = solve_channel(l0, l1, n);
    let mut flags = HhdFlags::default();
    let mut ca = ch.c_a;
    let hi = ch.i_z.max(0.0);
    if !(0.0..=hi).contains(&ca) {
        ca = ca.clamp(0.0, hi);
        flags.ca_clamped = true;
    }
    let v = ch.b - n * ca;
    let cd = v.length();
    let d = if cd > 1e-300 { v / cd } else { n };
    (Hhd { ca, cd, d }, flags)
}

impl Hhd {
    /// E/π at n for the surface normal N.
    #[inline]
    pub fn irradiance(&self, n: DVec3, normal: DVec3) -> f64 {
        self.ca * 0.5 * (1.0 + n.dot(normal)) + self.cd * n.dot(self.d).max(0.0)
    }
}

/// Luminance HHD tinted by the RGB irradiance at N: E_c(n) = (I_z,c / I_z,Y)·HHD_Y(n). At N it
/// returns the RGB I_z exactly (the IrradZ luminance-ratio idea of the 2018 brief, §7).
struct HhdLum {
    hhd: Hhd,
    normal: DVec3,
    tint: Rgb,
    flags: HhdFlags,
    dark: bool,
}

impl HhdLum {
    /// From the linear radiance SH `lin` of the light over N's hemisphere.
    fn fit(lin: &Sh9, n: DVec3, w: Rgb) -> Self {
        let l0 = lin[0].dot(w);
        let l1 = lin.l1_vector_weighted(w);
        let (hhd, flags) = clamped_hhd(l0, l1, n);
        // I_z per channel from the same linear SH: b·N = (2/√(3π))·l₁·N.
        let to_iz = 2.0 / (3.0 * PI).sqrt();
        let iz = Rgb::new(lin.l1_vector(0).dot(n), lin.l1_vector(1).dot(n), lin.l1_vector(2).dot(n)) * to_iz;
        let iz_lum = iz.dot(w);
        let dark = iz_lum <= 1e-300;
        let tint = if dark { Rgb::ZERO } else { iz / iz_lum };
        HhdLum { hhd, normal: n, tint, flags, dark }
    }
}

impl Fitted for HhdLum {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.tint * self.hhd.irradiance(n, self.normal)
    }
    /// The luminance HHD (C_a, C_d, d) and the RGB tint; N is the surface's, derived.
    fn stored(&self) -> Stored {
        let mut s = Stored::new(
            "E/pi(n) = tint*(C_a*(1 + n.N)/2 + C_d*max(0, n.d)), a luminance HHD (docs/conventions.md section 8) \
             tinted by tint = I_z/luminance(I_z); d a world direction",
        );
        s.scalar("C_a", Unit::Irradiance, self.hhd.ca).scalar("C_d", Unit::Irradiance, self.hhd.cd);
        s.push(Role::Stored, "d", Unit::Direction, Value::Vector(self.hhd.d));
        s.rgb("tint", Unit::Unitless, self.tint);
        s.push(Role::Derived, "N", Unit::Direction, Value::Vector(self.normal));
        s
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        let mut d = Vec::new();
        if self.flags.ca_clamped {
            d.push(("ca_clamped", 1.0));
        }
        if self.dark {
            d.push(("dark", 1.0));
        }
        d
    }
}

/// The cosine-weighted visibility seen from the surface normal N of the cone {ω·C > cos α}:
/// (1/π)∫_cone max(0, ω·N) dω, i.e. the AO value. It is the sphere-light form factor
/// (`lighting::cap_irradiance`) for cos α ≥ 0, and 1 minus that of the complementary cone for
/// cos α < 0. 1 − cos²α for a cone about N.
pub fn cone_visibility(n: DVec3, centre: DVec3, cos_alpha: f64) -> f64 {
    let c = cos_alpha.clamp(-1.0, 1.0);
    let s2 = 1.0 - c * c;
    if s2 <= 0.0 {
        return if c > 0.0 { 0.0 } else { 1.0 };
    }
    if c >= 0.0 {
        crate::reference::lighting::cap_irradiance(n.dot(centre), s2)
    } else {
        1.0 - crate::reference::lighting::cap_irradiance(-n.dot(centre), s2)
    }
}

fn build(p: &mut Params, id: &'static str, op: Op) -> Result<Box<dyn Encoder>> {
    p.finish(id)?;
    Ok(Box::new(ProbeOp::new(id, op)))
}

fn output_bands(p: &mut Params) -> Result<usize> {
    // 1 (linear) or 2 (quadratic).
    p.usize_in("output_bands", 2, 1..=2)
}

/// Builds the `probe_unoccluded` encoder from its settings: L2 probe, unoccluded (leaks). An
/// unknown or out-of-range setting is an error.
pub fn build_unoccluded(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, "probe_unoccluded", Op::Unoccluded)
}
/// Builds the `probe_hemi_full` encoder from its settings: L2 x hemisphere, rotated Gram. An
/// unknown or out-of-range setting is an error.
pub fn build_hemi_full(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let bands = output_bands(p)?;
    build(p, "probe_hemi_full", Op::Full { cone: false, bands })
}
/// Builds the `probe_cone_full` encoder from its settings: L2 x cone, rotated Gram. An unknown or
/// out-of-range setting is an error.
pub fn build_cone_full(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let bands = output_bands(p)?;
    build(p, "probe_cone_full", Op::Full { cone: true, bands })
}
/// Builds the `probe_hemi_q2l` encoder from its settings: quadratic-to-linear multiply. An unknown
/// or out-of-range setting is an error.
pub fn build_hemi_q2l(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, "probe_hemi_q2l", Op::Q2l)
}
/// The `iz` key of the HLSH operators: `pinned` (default) or `fitted`.
fn pin_iz(p: &mut Params) -> Result<bool> {
    match p.str_or("iz", "pinned")?.as_str() {
        "pinned" => Ok(true),
        "fitted" => Ok(false),
        s => bail!("iz '{s}': expected pinned (HLSH) or fitted (plain least squares, an ablation)"),
    }
}

/// Builds the `hlsh` encoder from its settings: HLSH: hemisphere multiply, I_z pinned. An unknown
/// or out-of-range setting is an error.
pub fn build_hlsh(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pin_iz = pin_iz(p)?;
    build(p, "hlsh", Op::Hlsh { cone: false, pin_iz })
}
/// Builds the `probe_hhd_lum` encoder from its settings: hemisphere multiply, luminance HHD. An
/// unknown or out-of-range setting is an error.
pub fn build_hhd_lum(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let weights = p.weights_or("weights", named_weights("rec709")?)?;
    build(p, "probe_hhd_lum", Op::HhdLum { weights })
}
/// Builds the `cone_multiply` encoder from its settings: HLSH cone multiply. An unknown or
/// out-of-range setting is an error.
pub fn build_cone_multiply(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pin_iz = pin_iz(p)?;
    build(p, "cone_multiply", Op::Hlsh { cone: true, pin_iz })
}
/// Builds the `ao_scale` encoder from its settings: L2 probe irradiance x cone AO. An unknown or
/// out-of-range setting is an error.
pub fn build_ao_scale(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, "ao_scale", Op::AoScale)
}
/// Builds the `bent_normal` encoder from its settings: L2 probe at the cone centre x AO. An unknown
/// or out-of-range setting is an error.
pub fn build_bent_normal(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, "bent_normal", Op::BentNormal)
}

#[cfg(test)]
mod tests;
