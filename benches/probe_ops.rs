//! Bench: the cost per shaded normal of each probe occlusion operator, the currency
//! in which the hemispherical-lighting talk argues for HLSH. Each operator is measured twice,
//! through the one `Encoder`/`Fitted` trait: the fit (once per surface normal N, amortised
//! over the normals that share it) and the evaluation at one shaded normal n′. A per-pixel
//! operator pays both per pixel.
//!
//! Also: what a declared effect costs the runner per case (visible SH and the exact reference
//! at 1024 hemisphere normals), against an experiment that declares none.
//!
//! Measured in CPU time, not wall time: this machine's two cores are shared by several
//! engineers, and wall time would count the neighbours. The operator benches use the bench
//! thread's CPU clock; the effect benches (the masked projection runs on rayon) the process's.
//! Criterion's "thrpt" line then reads directly in ns per element (per fit or per normal).
use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;
use probelab::bench::{
    build, cone_centre, fibonacci_sphere, generated, project_visible, Cap, EnvMap, FitInput, Reference, RowMoments,
    DEFAULT_POLAR_NODES,
};
use std::hint::black_box;

const OPS: &[&str] = &[
    "probe_unoccluded",
    "probe_hemi_full",
    "probe_hemi_q2l",
    "hlsh",
    "probe_hhd_lum",
    "cone_multiply",
    "probe_cone_full",
    "ao_scale",
    "bent_normal",
];

/// CPU time of a POSIX clock (`CLOCK_THREAD_CPUTIME_ID` or `CLOCK_PROCESS_CPUTIME_ID`), in ns.
struct CpuTime(libc::clockid_t);

impl CpuTime {
    fn now(&self) -> u64 {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: clock_gettime writes one timespec through a valid pointer.
        let rc = unsafe { libc::clock_gettime(self.0, &mut t) };
        assert_eq!(rc, 0, "clock_gettime failed");
        t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
    }
}

impl Measurement for CpuTime {
    type Intermediate = u64;
    type Value = u64;
    fn start(&self) -> u64 {
        self.now()
    }
    fn end(&self, i: u64) -> u64 {
        self.now().saturating_sub(i)
    }
    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }
    fn zero(&self) -> u64 {
        0
    }
    fn to_f64(&self, v: &u64) -> f64 {
        *v as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &NsFormatter
    }
}

/// Values in CPU ns; throughput as CPU ns per element.
struct NsFormatter;

impl ValueFormatter for NsFormatter {
    fn scale_values(&self, _typical: f64, _values: &mut [f64]) -> &'static str {
        "ns (CPU)"
    }
    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let n = match *t {
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => n,
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) | Throughput::Bits(n) => n,
        };
        for v in values {
            *v /= n.max(1) as f64;
        }
        "ns (CPU)/elem"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

/// Deterministic unit vectors (spherical Fibonacci).
fn directions(n: usize) -> Vec<DVec3> {
    fibonacci_sphere(n)
}

fn ops(c: &mut Criterion<CpuTime>) {
    // A realistic probe: the generated sun-and-sky scene's closed-form L2 SH.
    let scene = generated().into_iter().find(|s| s.id == "gen_sun_sky").expect("scene");
    let sh = scene.sh();
    let normals: Vec<DVec3> = directions(64);
    let cones: Vec<(DVec3, f64)> = normals.iter().map(|&n| (cone_centre(n, 30.0), 0.5)).collect();
    let shade_n = DVec3::new(0.3, 0.8, -0.52).normalize();
    let shaded: Vec<DVec3> = directions(2048).into_iter().filter(|d| d.dot(shade_n) > 0.0).take(1024).collect();
    let mut g = c.benchmark_group("probe_ops");
    for &id in OPS {
        let enc = build(id, None, toml::Table::new()).expect("encoder").encoder;
        let inputs: Vec<FitInput> = normals
            .iter()
            .zip(&cones)
            .map(|(&n, &cone)| FitInput {
                probe_sh: &sh,
                visible_sh: &sh,
                surface_normal: Some(n),
                cone: Some(cone),
                exact_at_normal: None,
                surface_albedo: None,
                radiance: None,
            })
            .collect();
        g.throughput(Throughput::Elements(inputs.len() as u64));
        g.bench_function(format!("{id}/fit per N"), |b| {
            b.iter(|| {
                for i in &inputs {
                    black_box(enc.fit(black_box(i)));
                }
            })
        });
        let fitted = enc.fit(&FitInput {
            probe_sh: &sh,
            visible_sh: &sh,
            surface_normal: Some(shade_n),
            cone: Some((cone_centre(shade_n, 30.0), 0.5)),
            exact_at_normal: None,
            surface_albedo: None,
            radiance: None,
        });
        g.throughput(Throughput::Elements(shaded.len() as u64));
        g.bench_function(format!("{id}/eval per normal"), |b| {
            b.iter(|| {
                let mut acc = DVec3::ZERO;
                for &n in &shaded {
                    acc += fitted.irradiance(black_box(n));
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

/// What a declared effect costs per case on a 256x128 map, against none.
fn effects(c: &mut Criterion<CpuTime>) {
    let map = EnvMap::from_fn("bench", 256, 128, |i, j| {
        let v = ((i * 7919 + j * 104729) % 1000) as f32 / 100.0;
        [v, 0.5 * v + 0.1, (i % 13) as f32]
    })
    .expect("map");
    let rm = RowMoments::new(&map);
    let n = DVec3::new(0.3, 0.8, -0.52).normalize();
    let normals: Vec<DVec3> = directions(2048).into_iter().filter(|d| d.dot(n) > 0.0).take(1024).collect();
    let variants: [(&str, Vec<Cap>); 3] = [
        ("none", vec![]),
        ("hemisphere", vec![Cap::hemisphere(n)]),
        ("cone(cos=0.5,tilt=30deg)", vec![Cap::new(cone_centre(n, 30.0), 0.5)]),
    ];
    let mut g = c.benchmark_group("effect_cost");
    g.sample_size(10);
    for (label, masks) in &variants {
        g.throughput(Throughput::Elements(1));
        g.bench_function(format!("visible SH/{label}"), |b| {
            // No effect: the runner hands encoders the probe SH (no projection at all).
            b.iter(|| if masks.is_empty() { None } else { Some(black_box(project_visible(&rm, masks, 2))) })
        });
        let r = Reference::new(&rm, masks.clone(), DEFAULT_POLAR_NODES);
        g.throughput(Throughput::Elements(normals.len() as u64));
        g.bench_function(format!("reference per normal/{label}"), |b| {
            b.iter(|| normals.iter().map(|&m| r.irradiance(m)).sum::<DVec3>())
        });
    }
    g.finish();
}

fn config(clock: libc::clockid_t) -> Criterion<CpuTime> {
    Criterion::default()
        .with_measurement(CpuTime(clock))
        .sample_size(20)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2))
}

criterion_group! {
    name = operator_benches;
    config = config(libc::CLOCK_THREAD_CPUTIME_ID);
    targets = ops
}
criterion_group! {
    name = effect_benches;
    config = config(libc::CLOCK_PROCESS_CPUTIME_ID);
    targets = effects
}
criterion_main!(operator_benches, effect_benches);
