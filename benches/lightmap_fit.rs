//! Per-texel fit time of every registered encoder from a lightmap bake (L2 SH of the visible
//! radiance + exact I_z), as a minimum over many batches of the thread's CPU time: on the
//! shared, loaded machine criterion's means measure the load, while the minimum of a short
//! batch's CPU time approaches the unloaded cost. Iterates `encoders::REGISTRY` (names none).
//!
//! Input: the generated `gen_sky_sun` scene (256x128) seen by 32 texels whose normals are a
//! spherical Fibonacci set, each with the hemisphere effect about its normal (visible SH by the
//! exact masked projection, I_z by the exact reference).
//!
//! `cargo bench --features bench --bench lightmap_fit` prints `min-of-N` lines: ns per texel per core.

use glam::DVec3;
use probelab::bench::{
    fibonacci_sphere, generated, project, project_visible, Cap, FitInput, Params, Reference, Rgb, RowMoments, Sh9,
    DEFAULT_POLAR_NODES, REGISTRY,
};
use std::hint::black_box;

fn thread_cpu_ns() -> u64 {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes the timespec it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let scene = generated().into_iter().find(|s| s.id == "gen_sky_sun").expect("scene");
    let map = scene.map(256);
    let rm = RowMoments::new(&map);
    let probe = project(&map);
    let normals = fibonacci_sphere(32);
    let bakes: Vec<(DVec3, Sh9, Rgb)> = normals
        .iter()
        .map(|&n| {
            let caps = vec![Cap::hemisphere(n)];
            let vis = project_visible(&rm, &caps, DEFAULT_POLAR_NODES);
            let iz = Reference::new(&rm, caps, DEFAULT_POLAR_NODES).irradiance(n);
            (n, vis, iz)
        })
        .collect();
    let inputs: Vec<FitInput> = bakes
        .iter()
        .map(|(n, vis, iz)| FitInput {
            probe_sh: &probe,
            visible_sh: vis,
            surface_normal: Some(*n),
            cone: None,
            exact_at_normal: Some(*iz),
            surface_albedo: None,
            radiance: None,
        })
        .collect();
    let batches = 300;
    println!("min-of-{batches} batches of {} texels, thread CPU time, ns per texel fit", inputs.len());
    for k in REGISTRY {
        if filter.as_deref().is_some_and(|f| !k.id.contains(f)) {
            continue;
        }
        let e = (k.build)(&mut Params::default()).expect("default settings build");
        let mut best = u64::MAX;
        let start = std::time::Instant::now();
        for _ in 0..batches {
            let t0 = thread_cpu_ns();
            for i in &inputs {
                black_box(e.fit(black_box(i)));
            }
            best = best.min(thread_cpu_ns() - t0);
            if start.elapsed().as_secs_f64() > 2.0 {
                break;
            }
        }
        println!("min-of-{batches} {:<28} {:>10.1} ns/texel", k.id, best as f64 / inputs.len() as f64);
    }
}
