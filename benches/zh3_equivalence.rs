//! Check (not a timing): the default ZH3 axis solve against the previous one, per probe.
//!
//! The previous solve ran L-BFGS from the best screened axis line (`axis_solver = "lbfgs"`),
//! stopping on its tolerances; the default runs Newton's method there to the objective's
//! rounding (L-BFGS where Newton does not end at a local minimum). For each probe this prints
//! nothing unless the default's error (the square root of the solve's objective, E/π over the
//! sphere, bands 1–2, equal channel weights as `zh3_solved_shared`) rises by more than 1e-9
//! relative; then the probe is listed. It also gives the largest pointwise change, the largest
//! difference of the two solves' SH3 coefficients relative to the probe's largest coefficient.
//! Probes: the five paper probes (from PROBELAB_ENVMAPS; skipped with a note when absent) and N
//! synthetic probes (default 100,000; `-- N` to change) from the probe synthesiser (seed 1, the
//! generated scenes' palette: palette SH under random rotations and exposures, coloured ambient,
//! directional, sphere and cone lights, all non-negative radiance).
//!
//! `cargo bench --features bench --bench zh3_equivalence [-- N]`
use probelab::bench::{
    project, scene_palette, solved, AxisRule, AxisSolver, Rgb, SearchPath, Sh9, Solved, SolverSettings, Synth, Zonal,
};

const PROBES: [&str; 5] = ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

/// The (new, old) shared solves of one probe.
fn both(irr: &Sh9) -> (Solved, Solved) {
    let eq = Rgb::splat(1.0 / 3.0);
    let one = |s: &SolverSettings| solved(irr, AxisRule::Shared(eq), eq, Zonal::Stored, s);
    let previous = SolverSettings { axis_solver: AxisSolver::Lbfgs, ..SolverSettings::default() };
    (one(&SolverSettings::default()), one(&previous))
}

/// The largest coefficient difference of two SH3, relative to the largest coefficient of `old`.
fn pointwise(new: &Sh9, old: &Sh9) -> f64 {
    let (mut d, mut m) = (0.0f64, 0.0f64);
    for i in 0..9 {
        d = d.max((new[i] - old[i]).abs().max_element());
        m = m.max(old[i].abs().max_element());
    }
    d / m.max(f64::MIN_POSITIVE)
}

fn main() {
    let n: u64 = std::env::args().skip(1).find_map(|a| a.parse().ok()).unwrap_or(100_000);
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let search = SearchPath::from_env(root.join("envmaps"));
    let mut inputs: Vec<(String, Sh9)> = Vec::new();
    for p in PROBES {
        match search.load(p) {
            Ok(map) => inputs.push((p.to_string(), project(&map).convolve_cosine())),
            Err(_) => eprintln!("zh3_equivalence: {p} not found (set PROBELAB_ENVMAPS); skipped"),
        }
    }
    let synth = Synth::new(1, scene_palette());
    inputs.extend((0..n).map(|i| (format!("synth seed 1 #{i}"), synth.probe(i).convolve_cosine())));
    let (mut rises, mut worst, mut lower, mut moved) = (0u64, f64::NEG_INFINITY, 0u64, (0.0f64, String::new()));
    let (mut runs_new, mut runs_old, mut newton, mut rejected, mut in_rounding) = (0u64, 0u64, 0u64, 0u64, 0u64);
    for (name, irr) in &inputs {
        let (new, old) = both(irr);
        let (e_new, e_old) = (new.stats.objective.sqrt(), old.stats.objective.sqrt());
        let rel = (e_new - e_old) / e_old.max(f64::MIN_POSITIVE);
        // The objective's resolution: the previous solve's own stop on its change, 1e-14 of the
        // largest L0² (`tol_cost`); a rise below it is rounding, counted apart.
        let floor = 1e-14 * (0..3).map(|c| irr[0][c] * irr[0][c]).fold(0.0, f64::max);
        let rounding = new.stats.objective - old.stats.objective <= floor;
        if rel > 1e-9 && rounding {
            in_rounding += 1;
        } else {
            worst = worst.max(rel);
            if rel > 1e-9 {
                rises += 1;
                println!("{name}: error {e_new:e} against {e_old:e} before ({rel:+e} relative)");
            }
        }
        lower += u64::from(rel < -1e-9);
        let p = pointwise(&new.zh3.to_sh(), &old.zh3.to_sh());
        if p > moved.0 {
            moved = (p, name.clone());
        }
        runs_new += u64::from(new.stats.runs);
        runs_old += u64::from(old.stats.runs);
        newton += u64::from(new.stats.newton_iters);
        rejected += u64::from(new.stats.newton_rejected);
    }
    let k = inputs.len() as f64;
    println!(
        "{} probes: {rises} with an error more than 1e-9 above the previous solve's, {lower} more than 1e-9 below, \
         {in_rounding} more than 1e-9 above within the objective's resolution (1e-14 of the largest L0²); \
         largest relative change {worst:+e}; largest pointwise change {:.2e} ({}); L-BFGS runs per probe {:.4} \
         (previously {:.3}); Newton iterations per probe {:.3}, {rejected} Newton ends not kept",
        inputs.len(),
        moved.0,
        moved.1,
        runs_new as f64 / k,
        runs_old as f64 / k,
        newton as f64 / k,
    );
}
