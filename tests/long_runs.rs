//! Long runs: work estimated above the bound (`pipeline::estimate::BOUND_S`, 30 minutes) is
//! refused before any map is loaded, with the estimate and what drives it, unless
//! `--allow-long` is given; everything committed (each experiment, each sweep, `reproduce` as a
//! whole) stays under the bound, so nothing needs the flag. docs/robustness.md, "Long runs".

mod common;

use common::harness::Scratch;
use std::io::{BufRead, BufReader};
use std::process::Stdio;
use std::time::{Duration, Instant};

/// The repository's generated maps, six small ones.
const MAPS: &str =
    "maps = ['gen_constant', 'gen_hemisphere', 'gen_sun_sky', 'gen_two_lights', 'gen_cone', 'gen_sky_sun']\n\
                    encoders = ['sh0', 'sh1', 'sh2']\ndomain = 'hemisphere'\neffects = ['hemisphere']\n";

/// A scratch repository with the generated maps and one experiment file `long.toml`.
fn scratch_with(experiment: &str) -> Scratch {
    let s = Scratch::new();
    for m in ["gen_constant", "gen_hemisphere", "gen_sun_sky", "gen_two_lights", "gen_cone", "gen_sky_sun"] {
        s.copy_from_repo(&format!("envmaps/{m}.exr"));
    }
    s.write("long.toml", format!("{MAPS}{experiment}"));
    s
}

/// `run` refuses at once (well within a few seconds, on a loaded machine), exit 2, naming the
/// experiment file, the estimate and what drives it, writing nothing.
fn refused(experiment: &str, driver: &str) -> Scratch {
    let s = scratch_with(experiment);
    let file = s.path().join("long.toml");
    let t = Instant::now();
    let out = s.probelab().args(["run", "--out"]).arg(s.path().join("results")).arg(&file).output().unwrap();
    let took = t.elapsed();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(took < Duration::from_secs(5), "the refusal took {took:?}");
    assert!(err.contains(&format!("{}: estimated ", file.display())), "{err}");
    assert!(err.contains(driver) && err.contains("--allow-long"), "{err}");
    assert!(!s.path().join("results").join("long").exists(), "nothing is written");
    s
}

/// With `--allow-long` the same run goes ahead: it announces its estimate (and would run for
/// hours, so it is stopped there; an interrupted run leaves nothing behind).
fn accepted_with_allow_long(s: &Scratch) {
    let mut child = s
        .probelab()
        .args(["--allow-long", "run", "--out"])
        .arg(s.path().join("results"))
        .arg(s.path().join("long.toml"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines.next().and_then(|l| l.ok()).unwrap_or_default();
    let still_running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(first.contains("long.toml: estimated ") && !first.contains("error"), "{first}");
    assert!(still_running, "{first}");
}

#[test]
fn the_largest_output_grid_is_refused_without_allow_long() {
    let s = refused("orientations = ['axes6']\nresolution = [8192, 4096]\n", "8192×2048 output normals");
    accepted_with_allow_long(&s);
}

#[test]
fn thousands_of_orientations_are_refused_without_allow_long() {
    let s = refused("orientations = ['fibonacci4096']\nresolution = [512, 256]\n", "4096 orientation(s)");
    accepted_with_allow_long(&s);
}

/// A sweep is estimated before it starts too: every value's reference, timed over and over.
#[test]
fn a_long_sweep_is_refused_without_allow_long() {
    let s = scratch_with("orientations = ['fibonacci4096']\nknob = 'polar_nodes'\nvalues = [1, 2, 4, 8, 16]\n");
    let sweep = s.path().join("long.toml");
    let out = s.probelab().args(["sweep", "--out"]).arg(s.path().join("results")).arg(&sweep).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("long.toml: estimated ") && err.contains("5 value(s) of polar_nodes"), "{err}");
    assert!(!s.path().join("results").join("sweeps").exists(), "nothing is written");
}

/// `check` and `bless` re-run experiments too: an experiment edited to run for hours is
/// refused by either before it runs, exit 2, naming the file; no baseline is written.
#[test]
fn check_and_bless_refuse_a_long_experiment_too() {
    let s = scratch_with("");
    let file =
        s.write("experiments/long.toml", format!("{MAPS}orientations = ['fibonacci4096']\nresolution = [512, 256]\n"));
    for cmd in ["check", "bless"] {
        let t = Instant::now();
        let out = s.probelab().args([cmd, "--out"]).arg(s.path().join("results")).arg(&file).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{cmd}: {err}");
        assert!(t.elapsed() < Duration::from_secs(5), "{cmd}: the refusal took {:?}", t.elapsed());
        assert!(
            err.contains(&format!("{}: estimated ", file.display())) && err.contains("--allow-long"),
            "{cmd}: {err}"
        );
        assert!(!s.path().join("results").join("long").exists(), "{cmd}: nothing is written");
    }
}
