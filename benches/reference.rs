//! Bench: the exact reference for a 256×128 map at 256×128 output normals (target ≤ 0.1 s on
//! the 2-core machine), the general capped path (a cone-AO case, 4096 hemisphere
//! normals), and the SH projection of a 1024×512 map (target ≤ 5 ms).
use criterion::{criterion_group, criterion_main, Criterion};
use probelab::bench::{cone_centre, project, Cap, Domain, EnvMap, LatLong, Reference, RowMoments, DEFAULT_POLAR_NODES};
use std::hint::black_box;

fn synthetic(w: usize) -> EnvMap {
    EnvMap::from_fn("bench", w, w / 2, |i, j| {
        let v = ((i * 7919 + j * 104729) % 1000) as f32 / 100.0;
        [v, 0.5 * v + 0.1, (i % 13) as f32]
    })
    .expect("valid synthetic map")
}

fn bench(c: &mut Criterion) {
    let map = synthetic(256);
    c.bench_function("reference 256x128 map -> 256x128 normals (incl. moments)", |b| {
        b.iter(|| {
            let rm = RowMoments::new(black_box(&map));
            let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
            black_box(r.irradiance_latlong(LatLong::new(256, 128)))
        })
    });
    // The general (capped) path: a cone-AO case, cone of cos 0.5 about N tilted 30° from +Y,
    // at the hemisphere normals of a 128x64 grid (128x32 = 4096 normals), as `cone_ao` runs it.
    let rm = RowMoments::new(&map);
    let n = glam::DVec3::Y;
    let cone = Cap::new(cone_centre(n, 30.0), 0.5);
    let grid = Domain::Hemisphere { normal: n }.output_grid((128, 64));
    let capped = Reference::new(&rm, vec![cone], DEFAULT_POLAR_NODES);
    c.bench_function("reference 256x128 map, cone cap -> 4096 hemisphere normals", |b| {
        b.iter(|| black_box(capped.irradiance_many(black_box(&grid.normals))))
    });
    let big = synthetic(1024);
    c.bench_function("projection 1024x512 map -> SH L2", |b| b.iter(|| black_box(project(black_box(&big)))));
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
