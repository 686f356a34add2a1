//! Bench: `map_size`, what `probelab eval MAP --encoders sh2` does to a map of each size, in
//! process: decode the file, the row moments, the SH projection and the exact reference on the
//! default 256×128 grid of normals. The maps are made here, at bench time, from the committed
//! `pmndrs_bridge_256x128.exr` (`envmap::resample::resized`: averaged down to 32×16, nearest
//! texel up to the larger sizes) and written as half-float EXR to a temporary folder; nothing
//! large is committed. Figures, and the whole-process commands for 16k: benches/README.md.
use criterion::{criterion_group, criterion_main, Criterion};
use probelab::bench::{
    load_map, project, resized, write_exr_half, LatLong, Reference, RowMoments, DEFAULT_POLAR_NODES,
};
use std::hint::black_box;
use std::path::Path;

const SIZES: [(usize, usize); 7] =
    [(32, 16), (256, 128), (1000, 500), (1024, 512), (2048, 1024), (2000, 1000), (4096, 2048)];

fn eval_once(path: &Path) -> usize {
    let map = load_map(path).expect("the bench map loads");
    let rm = RowMoments::new(&map);
    let sh = project(&map);
    let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
    let values = r.irradiance_latlong(LatLong::new(256, 128));
    black_box(sh);
    black_box(values).len()
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps/pmndrs_bridge_256x128.exr");
    let map = load_map(&source).expect("the committed map loads");
    let mut group = c.benchmark_group("map_size");
    group.sample_size(10);
    for (w, h) in SIZES {
        let path = dir.path().join(format!("bridge_{w}x{h}.exr"));
        let resized = resized(&map, w, h).expect("a 2:1 size");
        write_exr_half(&path, &resized).expect("the bench map is written");
        drop(resized);
        group.bench_function(format!("{w}x{h} decode+moments+SH+reference 256x128"), |b| {
            b.iter(|| eval_once(black_box(&path)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
