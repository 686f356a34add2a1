//! Check (not a timing): the default ZH3 axis solve against the previous one, per probe.
//!
//! The previous solve always ran L-BFGS twice (from the best screened axis line, then from the
//! best line at least 45° from where that ended); the default skips the second run where it
//! provably cannot win (`skip_futile`). For each probe this prints nothing unless the default's
//! error (the square root of the solve's objective, E/π over the sphere, bands 1–2, equal
//! channel weights as `zh3_solved_shared`) rises by more than 1e-9 relative; then the probe is
//! listed. Probes: the five paper probes (from PROBELAB_ENVMAPS; skipped with a note when
//! absent) and N synthetic probes (default 100,000; `-- N` to change) from the probe
//! synthesiser (seed 1, the generated scenes' palette: palette SH under random rotations and
//! exposures, coloured ambient, directional, sphere and cone lights, all non-negative radiance).
//!
//! `cargo bench --features bench --bench zh3_equivalence [-- N]`
use probelab::bench::{project, scene_palette, solved, AxisRule, Rgb, SearchPath, Sh9, SolverSettings, Synth, Zonal};

const PROBES: [&str; 5] = ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

/// (new, old) objective and L-BFGS runs of one probe's shared solve.
fn both(irr: &Sh9) -> ((f64, u32), (f64, u32)) {
    let eq = Rgb::splat(1.0 / 3.0);
    let one = |s: &SolverSettings| {
        let st = solved(irr, AxisRule::Shared(eq), eq, Zonal::Stored, s).stats;
        (st.objective, st.runs)
    };
    let previous = SolverSettings { skip_futile: false, ..SolverSettings::default() };
    (one(&SolverSettings::default()), one(&previous))
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
    let (mut rises, mut worst, mut lower) = (0u64, f64::NEG_INFINITY, 0u64);
    let (mut runs_new, mut runs_old) = (0u64, 0u64);
    for (name, irr) in &inputs {
        let ((f_new, r_new), (f_old, r_old)) = both(irr);
        let (e_new, e_old) = (f_new.sqrt(), f_old.sqrt());
        let rel = (e_new - e_old) / e_old.max(f64::MIN_POSITIVE);
        worst = worst.max(rel);
        if rel > 1e-9 {
            rises += 1;
            println!("{name}: error {e_new:e} against {e_old:e} before ({rel:+e} relative)");
        }
        lower += u64::from(rel < -1e-9);
        runs_new += u64::from(r_new);
        runs_old += u64::from(r_old);
    }
    let k = inputs.len() as f64;
    println!(
        "{} probes: {rises} with an error more than 1e-9 above the previous solve's, {lower} more than 1e-9 below; \
         largest relative change {worst:+e}; L-BFGS runs per probe {:.3} (previously {:.3})",
        inputs.len(),
        runs_new as f64 / k,
        runs_old as f64 / k
    );
}
