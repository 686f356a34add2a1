//! No reference computed twice: `reproduce` over two maps and two experiments whose cases
//! overlap computes each distinct (map, caps, normals) reference once, as its `--profile`
//! counts, and what it hands back from the cache is what a process computing it afresh
//! writes, byte for byte (tables and sheets).

mod common;

use common::harness::{repo, Run, Scratch};
use std::process::Output;

/// The calls of `--profile` phase `phase` on standard error (0 when the phase is absent).
fn calls(stderr: &str, phase: &str) -> u64 {
    stderr
        .lines()
        .filter_map(|l| l.trim().strip_prefix(phase))
        .filter_map(|rest| {
            let fields: Vec<&str> = rest.split_whitespace().collect();
            // A row of the phase itself reads "SECONDS SHARE% CALLS" after its name.
            (fields.len() == 3 && fields[1].ends_with('%')).then(|| fields[2].parse().ok()).flatten()
        })
        .next()
        .unwrap_or(0)
}

fn ok(o: Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{}{err}", String::from_utf8_lossy(&o.stdout));
    err
}

#[test]
fn reproduce_computes_each_distinct_reference_once() {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    for (name, src) in [("a", "gen_sun_sky"), ("b", "gen_two_lights")] {
        let bytes = std::fs::read(repo().join("envmaps").join(format!("{src}.exr"))).unwrap();
        root.write(&format!("envmaps/{name}.exr"), bytes);
    }
    // x: the six axes, each under two albedos of the self-bounce (the bounce is added to one
    // capped reference). y: `up` (= +y) and the same six axes, at the same resolution.
    root.write(
        "experiments/x.toml",
        "maps = ['a', 'b']\nencoders = ['sh1', { kind = 'with_self_bounce', inner = 'sh2', name = 'sb' }]\n\
         domain = 'hemisphere'\norientations = ['axes6']\nresolution = [16, 8]\n\
         effects = ['hemisphere', { kind = 'self_bounce', albedo = [0.2, 0.5] }]\n",
    );
    root.write(
        "experiments/y.toml",
        "maps = ['a', 'b']\nencoders = ['sh2']\ndomain = 'hemisphere'\norientations = ['up', 'axes6']\n\
         resolution = [16, 8]\neffects = ['hemisphere']\n",
    );
    let err = ok(root.probelab().args(["--profile", "--no-timing", "reproduce"]).run());
    // Asked for: x 2 maps x 12 cases, y 2 x 7; distinct: 2 maps x 6 hemispheres (one grid each).
    assert_eq!(calls(&err, "reference"), 12, "{err}");
    // The sheets: each experiment's case nearest +y on each map, one disc looking down +y
    // (x's first albedo, y's `up`): the same caps and normals, so 2 distinct of 4.
    assert_eq!(calls(&err, "report: reference (sheets)"), 2, "{err}");
    assert_eq!(calls(&err, "reference reused (cache)"), 24 + 14 - 12 + 4 - 2, "{err}");

    // What was handed back is what is computed afresh: y alone (computing all its own) writes
    // the same table, and a report in a new process draws the same sheets.
    let tables = root.snapshot("results");
    let alone = root.path().join("alone");
    ok(root.probelab().args(["--no-timing", "run", "y", "--out"]).arg(&alone).run());
    let alone = std::fs::read(alone.join("y/table.csv")).unwrap();
    assert!(alone == tables[&std::path::PathBuf::from("y/table.csv")], "y's table differs when run alone");
    ok(root.probelab().args(["report"]).run());
    let again = root.snapshot("results");
    let sheets: Vec<_> = tables.keys().filter(|p| p.to_string_lossy().contains("sheet_")).collect();
    assert_eq!(sheets.len(), 4, "{:?}", tables.keys().collect::<Vec<_>>());
    for p in sheets {
        assert!(again[p] == tables[p], "{} differs when drawn afresh", p.display());
    }
}
