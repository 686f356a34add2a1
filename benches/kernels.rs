//! Benches of the kernels behind every table and probe set: each registered encoder's fit and
//! evaluation (iterating the registry, so encoders join automatically), and the probe-set
//! kernels (synthesis, SH rotation, per-probe error, statistics). Figures: benches/README.md.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use probelab::bench::{
    build, fibonacci_sphere, generated, probe_rmse, project, project_visible, uniform_rotation, Cap, EnvMap, FitInput,
    Fitted, MapLight, Params, Reference, Rgb, RowMoments, Sh9, ShRotation, SphereRule, Stored, Summary, Synth,
    DEFAULT_POLAR_NODES, REGISTRY,
};
use std::hint::black_box;

/// The inputs every encoder is fitted from: the generated sky-and-sun scene seen by a probe
/// (sphere) and by a floor (normal +Y, hemisphere effect, with the exact irradiance at N).
struct Inputs {
    probe: Sh9,
    visible: Sh9,
    exact_at_normal: Rgb,
}

fn inputs(map: &EnvMap, rm: &RowMoments) -> Inputs {
    let caps = vec![Cap::hemisphere(DVec3::Y)];
    Inputs {
        probe: project(map),
        visible: project_visible(rm, &caps, DEFAULT_POLAR_NODES),
        exact_at_normal: Reference::new(rm, caps, DEFAULT_POLAR_NODES).irradiance(DVec3::Y),
    }
}

fn encoders(c: &mut Criterion) {
    let scene = generated().into_iter().find(|s| s.id == "gen_sky_sun").expect("scene");
    let map = scene.map(256);
    let rm = RowMoments::new(&map);
    let inp = inputs(&map, &rm);
    // The map's light, as the runner passes it (its caches fill on the first fit, as in a run:
    // the SH through band 4, the samples and the E/π grids are inputs, not part of the fit).
    let sphere_light = MapLight::new(&map, &rm, vec![], DEFAULT_POLAR_NODES);
    let floor_light = MapLight::new(&map, &rm, vec![Cap::hemisphere(DVec3::Y)], DEFAULT_POLAR_NODES);
    let sphere = FitInput { radiance: Some(&sphere_light), ..FitInput::sphere(&inp.probe) };
    let floor = FitInput {
        probe_sh: &inp.probe,
        visible_sh: &inp.visible,
        surface_normal: Some(DVec3::Y),
        cone: None,
        exact_at_normal: Some(inp.exact_at_normal),
        surface_albedo: None,
        radiance: Some(&floor_light),
    };
    let normals = fibonacci_sphere(1024);
    let mut g = c.benchmark_group("encoder");
    for k in REGISTRY {
        let e = (k.build)(&mut Params::default()).expect("default settings build");
        // An encoder defined only about a surface normal (the H-basis) is fitted and evaluated
        // on the floor alone: on the sphere it would time its fallback.
        let surface_only = e.needs_surface_normal();
        for (label, input) in [("sphere", &sphere), ("floor", &floor)] {
            if surface_only && label == "sphere" {
                continue;
            }
            g.throughput(Throughput::Elements(1));
            g.bench_with_input(BenchmarkId::new(format!("fit/{label}"), k.id), input, |b, i| {
                b.iter(|| black_box(e.fit(black_box(i))))
            });
        }
        let fit = e.fit(if surface_only { &floor } else { &sphere });
        g.throughput(Throughput::Elements(normals.len() as u64));
        // Over the whole sphere, also for the H-basis (its polynomials below the horizon cost
        // the same).
        g.bench_function(BenchmarkId::new("eval x1024 normals", k.id), |b| {
            b.iter(|| {
                let mut acc = Rgb::ZERO;
                for &n in &normals {
                    acc += fit.irradiance(black_box(n));
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

/// A fit that hides its SH3 form, to time the quadrature path of probe errors.
struct NoHook(Box<dyn Fitted>);
impl Fitted for NoHook {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.0.irradiance(n)
    }
    fn stored(&self) -> Stored {
        self.0.stored()
    }
}

fn probes(c: &mut Criterion) {
    let palette: Vec<(String, Sh9)> = generated().into_iter().map(|s| (s.id.clone(), s.sh())).collect();
    let synth = Synth::new(1, palette);
    let mut g = c.benchmark_group("probes");
    g.throughput(Throughput::Elements(1));
    let mut i = 0u64;
    g.bench_function("synthesise one probe", |b| {
        b.iter(|| {
            i += 1;
            black_box(synth.probe(i))
        })
    });
    let p = synth.probe(42);
    let q = uniform_rotation(0.1, 0.5, 0.9);
    g.bench_function("SH rotation: build (3x3 + 5x5)", |b| b.iter(|| black_box(ShRotation::from_quat(black_box(q)))));
    let rot = ShRotation::from_quat(q);
    g.bench_function("SH rotation: apply to RGB SH3", |b| b.iter(|| black_box(rot.apply(black_box(&p)))));
    let reference = p.convolve_cosine();
    let rule = SphereRule::standard();
    let sh1 = build("sh1", None, toml::Table::new()).expect("sh1");
    let fit = sh1.encoder.fit(&FitInput::sphere(&p));
    g.bench_function("probe error: closed form (sh1)", |b| {
        b.iter(|| black_box(probe_rmse(fit.as_ref(), black_box(&reference), &rule)))
    });
    let geo = build("geomerics", None, toml::Table::new()).expect("geomerics");
    let gfit = geo.encoder.fit(&FitInput::sphere(&p));
    g.bench_function("probe error: closed form (geomerics, Funk-Hecke)", |b| {
        b.iter(|| black_box(probe_rmse(gfit.as_ref(), black_box(&reference), &rule)))
    });
    let ghidden = NoHook(geo.encoder.fit(&FitInput::sphere(&p)));
    g.bench_function("probe error: 72-normal quadrature (geomerics hidden)", |b| {
        b.iter(|| black_box(probe_rmse(&ghidden, black_box(&reference), &rule)))
    });
    let hidden = NoHook(sh1.encoder.fit(&FitInput::sphere(&p)));
    g.bench_function("probe error: 72-normal quadrature (sh1 hidden)", |b| {
        b.iter(|| black_box(probe_rmse(&hidden, black_box(&reference), &rule)))
    });
    let mut s = Summary::default();
    let mut x = 0.37f64;
    g.bench_function("statistics: add one value", |b| {
        b.iter(|| {
            x = (x * 1.618_033_988_749_895).fract() + 1e-3;
            s.add(black_box(x))
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(1));
    targets = encoders, probes
}
criterion_main!(benches);
