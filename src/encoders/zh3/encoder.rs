//! A configured ZH3 encoder (one of the ids of [`crate::encoders::zh3`]'s table): its fit, with
//! the solver's diagnostics, its stored form and its bytes when quantised.

use crate::encoders::encoder::{fit_each_unboxed, sq_errors_unboxed, Encoder, Family, FitInput, Fitted};
use crate::encoders::quantise;
use crate::encoders::stored::{sh_name, Role, Stored, Unit, Value};
use crate::encoders::zh3::model::{closed_form_sq_error, hallucinate, solved, stored, AxisRule, Zh3};
use crate::encoders::zh3::serialise::{decode_zh3, encode_zh3};
use crate::encoders::zh3::solve::{Curve, Formulation, SolveStats, SolverSettings, Zonal};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::Result;
use glam::DVec3;

/// What a ZH3 encoder does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Method {
    /// k hallucinated from the projected L1 by this curve.
    Hallucinate(Curve),
    /// k stored, the axes from the projected L1.
    Stored,
    /// The L1 solved, k stored or hallucinated.
    Solved(Zonal),
}

/// A configured ZH3 encoder (one of the ids in the table above).
pub struct Zh3Encoder {
    /// The registered id.
    pub(super) id: &'static str,
    /// How k (and the L1) are found.
    pub(super) method: Method,
    /// Where the zonal axes come from.
    pub(super) rule: AxisRule,
    /// The solve's channel weights.
    pub(super) err_w: Rgb,
    /// The solver's settings.
    pub(super) settings: SolverSettings,
    /// Whether the fit goes through its stored bytes.
    pub(super) quantise: bool,
}

/// The fitted ZH3, expanded to irradiance SH3. Its diagnostics are built when asked for, from
/// the encoder's settings and the solve's statistics it keeps, so a fit allocates nothing.
pub struct Zh3Fit {
    /// The fitted ZH3.
    pub zh3: Zh3,
    sh: Sh9,
    /// What the diagnostics echo: the encoder's method, axis rule, channel weights and settings.
    method: Method,
    rule: AxisRule,
    err_w: Rgb,
    settings: SolverSettings,
    /// The solve's statistics (solved variants).
    stats: Option<SolveStats>,
    /// The length of the stored bytes the fit went through (quantised variants).
    bytes: Option<usize>,
}

/// How a stored ZH3 reconstructs (FORMULAS §2–5).
const ZH3_BASIS: &str = "per channel E/pi(n) = L0_0*Y_0(n) + sum_m L1_m*Y_1m(n) + k*sum_m Y_2m(a)*Y_2m(n) \
     (= k*(5/8pi)*(3(a.n)^2 - 1)); E/pi coefficients (the radiance SH times 1, 2/3, 1/4: docs/conventions.md section 3), Y the real orthonormal SH of \
     section 2, a = zonal_axis (section 5: the channel's, or one shared, L1 direction (-L1_1, -L1_-1, L1_0) \
     normalised); no axis (L1 = 0) means k = 0";

/// How a hallucinated ZH3 finds its k (FORMULAS §5).
const ZH3_HALLUCINATED: &str = "; k is not stored but hallucinated: k = (1/4)*sqrt(4pi/5)*L0_0*g(r) with the \
     radiance ratio r = 1.5*|L1.a|/L0_0 (L1 = (-L1_1, -L1_-1, L1_0) of the channel) and g the encoder's curve \
     (the paper's g(r) = 0.08r + 0.6r^2 by default), k = 0 where L0_0 <= 0";

impl Fitted for Zh3Fit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.sh.eval(n)
    }
    /// L0 and L1 as E/π SH (12 scalars), then k when it is stored (15); the zonal axis, the
    /// ratio r and a hallucinated k are derived (FORMULAS §5).
    fn stored(&self) -> Stored {
        let k_stored = curve_of(self.method).is_none();
        let basis = if k_stored { ZH3_BASIS.to_string() } else { format!("{ZH3_BASIS}{ZH3_HALLUCINATED}") };
        let mut s = Stored::new(basis);
        for i in 0..4 {
            s.rgb(sh_name(i), Unit::Irradiance, self.sh[i]);
        }
        let k_role = if k_stored { Role::Stored } else { Role::Derived };
        s.push(k_role, "k", Unit::Irradiance, Value::Rgb(self.zh3.k));
        if matches!(self.rule, AxisRule::Shared(_)) {
            if let Some(a) = self.zh3.axes[0] {
                s.push(Role::Derived, "zonal_axis", Unit::Direction, Value::Vector(a));
            }
        } else {
            for (c, name) in ["zonal_axis_r", "zonal_axis_g", "zonal_axis_b"].into_iter().enumerate() {
                if let Some(a) = self.zh3.axes[c] {
                    s.push(Role::Derived, name, Unit::Direction, Value::Vector(a));
                }
            }
        }
        s.push(Role::Derived, "ratio", Unit::Unitless, Value::Rgb(self.zh3.ratios()));
        s
    }
    /// The axis weights (shared axis), the solve's weights, statistics and settings (solved),
    /// the curve's coefficients (polynomial curve) and the stored length (quantised), in that
    /// order.
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        let mut diag: Vec<(&'static str, f64)> = Vec::new();
        if let AxisRule::Shared(w) = self.rule {
            diag.extend([("axis_wr", w.x), ("axis_wg", w.y), ("axis_wb", w.z)]);
        }
        if let (Method::Solved(zonal), Some(st)) = (self.method, &self.stats) {
            if matches!(self.rule, AxisRule::Shared(_)) {
                diag.extend([("err_wr", self.err_w.x), ("err_wg", self.err_w.y), ("err_wb", self.err_w.z)]);
            }
            let set = &self.settings;
            diag.extend([
                ("runs", st.runs as f64),
                ("iters", st.iters as f64),
                ("cost_evals", st.cost_evals as f64),
                ("grad_evals", st.grad_evals as f64),
                ("evals", st.evals as f64),
                ("failures", st.failures as f64),
                ("objective", st.objective),
                ("objective_l1_axis", st.objective_l1_axis),
                ("best_start", st.best_start as f64),
                ("max_iters", set.max_iters as f64),
                ("tol_grad", set.tol_grad),
                ("tol_cost", set.tol_cost),
                ("memory", set.memory as f64),
                ("starts", set.starts as f64),
            ]);
            if zonal == Zonal::Stored {
                diag.push(("reduced", (set.formulation == Formulation::Axis) as u8 as f64));
                diag.push(("screen", set.screen as f64));
            }
        }
        if let Some(Curve::Poly([c1, c2, c3])) = curve_of(self.method) {
            diag.extend([("c1", c1), ("c2", c2), ("c3", c3)]);
        }
        if let Some(n) = self.bytes {
            diag.push(("bytes", n as f64));
        }
        diag
    }
    /// Every variant (hallucinated, stored, solved, quantised) is evaluated as its SH3
    /// expansion (FORMULAS §5), so it is exactly that SH3.
    fn sh3(&self) -> Option<Sh9> {
        Some(self.sh)
    }
}

impl Zh3Encoder {
    /// Fits from a radiance SH: the encoding, and what its diagnostics report.
    pub fn fit_zh3(&self, radiance: &Sh9) -> Zh3Fit {
        let irr = radiance.convolve_cosine();
        let (zh3, stats) = match self.method {
            Method::Hallucinate(curve) => (hallucinate(&irr, self.rule, curve), None),
            Method::Stored => (stored(&irr, self.rule), None),
            Method::Solved(zonal) => {
                let s = solved(&irr, self.rule, self.err_w, zonal, &self.settings);
                (s.zh3, Some(s.stats))
            }
        };
        let (zh3, bytes) = if self.quantise {
            // The stored bytes, decoded: what a shader would read.
            let bytes = self.encode(&zh3);
            (self.decode(&bytes).expect("encode_zh3 writes 13 or 16 bytes"), Some(bytes.len()))
        } else {
            (zh3, None)
        };
        Zh3Fit {
            zh3,
            sh: zh3.to_sh(),
            method: self.method,
            rule: self.rule,
            err_w: self.err_w,
            settings: self.settings,
            stats,
            bytes,
        }
    }
}

/// The curve that gives k when none is stored (hallucinated variants), or None (stored k).
fn curve_of(method: Method) -> Option<Curve> {
    match method {
        Method::Hallucinate(c) | Method::Solved(Zonal::Hallucinated(c)) => Some(c),
        Method::Stored | Method::Solved(Zonal::Stored) => None,
    }
}

impl Zh3Encoder {
    /// The curve that gives k when none is stored (hallucinated variants), or None (stored k).
    fn curve(&self) -> Option<Curve> {
        curve_of(self.method)
    }

    /// The bytes this encoder stores for a ZH3 when quantised ([`encode_zh3`]): 16 with a
    /// stored zonal coefficient, 13 when it hallucinates one.
    pub fn encode(&self, z: &Zh3) -> Vec<u8> {
        encode_zh3(z, self.curve().is_none())
    }

    /// Decodes this encoder's bytes ([`decode_zh3`] with its axis rule and curve).
    pub fn decode(&self, bytes: &[u8]) -> Result<Zh3> {
        decode_zh3(bytes, self.rule, self.curve().unwrap_or(Curve::PAPER))
    }
}

impl Encoder for Zh3Encoder {
    fn id(&self) -> &str {
        self.id
    }
    fn family(&self) -> Family {
        Family::Zh3
    }
    /// Quantised (`ratio8`, FORMULAS §11), it loses precision by design, as the quantised SH do.
    fn degrades_input(&self) -> bool {
        self.quantise
    }
    fn stored_scalars(&self) -> usize {
        match self.method {
            Method::Stored | Method::Solved(Zonal::Stored) => 15,
            _ => 12,
        }
    }
    /// Quantised: the length [`encode_zh3`] writes (16 bytes with a stored zonal coefficient,
    /// 13 when hallucinated; FORMULAS §11). Otherwise half floats.
    fn stored_bytes(&self) -> usize {
        match (self.quantise, self.curve()) {
            (true, None) => quantise::BYTES_ZH3,
            (true, Some(_)) => quantise::BYTES_L1,
            (false, _) => crate::encoders::encoder::HALF_BYTES * self.stored_scalars(),
        }
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        Box::new(self.fit_zh3(input.visible_sh))
    }
    fn fit_sphere_each(&self, probes: &[Sh9], visit: &mut dyn FnMut(usize, &dyn Fitted)) {
        fit_each_unboxed(probes, visit, |p| self.fit_zh3(p));
    }
    /// The closed-form variants (hallucinated or stored k, not quantised) score straight from
    /// the irradiance ([`closed_form_sq_error`]), the others through their fits.
    fn sphere_sq_errors(&self, probes: &[Sh9], irradiance: &[Sh9], out: &mut [f64]) -> bool {
        if self.quantise || matches!(self.method, Method::Solved(_)) {
            return sq_errors_unboxed(probes, irradiance, out, |p| self.fit_zh3(p));
        }
        let zonal = match self.method {
            Method::Hallucinate(curve) => Zonal::Hallucinated(curve),
            _ => Zonal::Stored,
        };
        for (irr, o) in irradiance.iter().zip(out) {
            *o = closed_form_sq_error(irr, self.rule, zonal);
        }
        true
    }
    /// The solved variants run L-BFGS: `probelab check` gives them the iterative tolerance.
    fn is_iterative(&self) -> bool {
        matches!(self.method, Method::Solved(_))
    }
}
