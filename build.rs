//! Build script: tells the tests what this machine has, so that a test which cannot run here
//! is reported by cargo as *ignored*, with its reason, instead of passing without checking
//! anything. It sets four cfgs (declared below, so rustc does not warn about them); they reach
//! every target of the package, the integration tests in `tests/` included:
//!
//! - `shared_maps`: `PROBELAB_ENVMAPS` is set (non-empty), or `CI` is `true`/`1`. Tests that
//!   read the shared maps (the paper probes ennis, grace, pisa, uffizi, wells and the other maps
//!   of that folder) carry
//!   `#[cfg_attr(not(shared_maps), ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md")]`.
//!   Setting the variable (or running in CI) declares the maps present: the tests then run, and
//!   a missing map fails them, loudly, rather than skipping. A build whose variable names no
//!   folder holding the paper probes also prints a warning.
//! - `gnu_parallel`: GNU parallel is on `PATH` (the sharding recipe of docs/scale.md needs it).
//! - `mode_000_readable`: this user can open a file of mode 000 (root can), so the tests that a
//!   permission-denied error is reported cannot run.
//! - `python_package`: `PROBELAB_PYTHON` is set (non-empty), or `CI` is `true`/`1`. The test
//!   that runs the Python package's pytest suite (`tests/python_package.rs`) needs an
//!   interpreter with the package installed (`pip install ./bindings/python`); without one it
//!   is ignored with that reason, and in CI a missing one fails it.
//! - `viewer_browser`: `CI` is `true`/`1`, or `PROBELAB_PYTHON` names an interpreter that imports
//!   Playwright and a Chromium is at `PROBELAB_CHROMIUM` (default `/usr/bin/chromium`). The
//!   results viewer's browser tests (`tests/viewer.rs`) need both; without them they are ignored
//!   with that reason, and in CI a missing one fails them.

use std::env;
use std::path::PathBuf;
use std::process::Command;

/// The maps of the papers' tables (`experiments/sh_baseline.toml`, `zh3_table.toml`, `claims
/// zh3`); `tests/common/shared_maps.rs` lists the same five.
const PAPER_PROBES: [&str; 5] =
    ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

fn main() {
    for cfg in ["shared_maps", "gnu_parallel", "mode_000_readable", "python_package", "viewer_browser"] {
        println!("cargo::rustc-check-cfg=cfg({cfg})");
    }
    println!("cargo::rerun-if-changed=build.rs");
    shared_maps();
    gnu_parallel();
    mode_000_readable();
    python_package();
    viewer_browser();
}

fn viewer_browser() {
    println!("cargo::rerun-if-env-changed=PROBELAB_CHROMIUM");
    let ci = env::var("CI").is_ok_and(|v| v == "true" || v == "1");
    let chromium = env::var_os("PROBELAB_CHROMIUM")
        .filter(|v| !v.is_empty())
        .map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    if chromium.is_file() {
        println!("cargo::rerun-if-changed={}", chromium.display());
    }
    let python = env::var_os("PROBELAB_PYTHON").filter(|v| !v.is_empty());
    let playwright = python.is_some_and(|p| {
        let probe = Command::new(p).args(["-c", "import playwright.sync_api"]).output();
        probe.is_ok_and(|o| o.status.success())
    });
    if ci || (playwright && chromium.is_file()) {
        println!("cargo::rustc-cfg=viewer_browser");
    }
}

fn python_package() {
    println!("cargo::rerun-if-env-changed=PROBELAB_PYTHON");
    let ci = env::var("CI").is_ok_and(|v| v == "true" || v == "1");
    if ci || env::var_os("PROBELAB_PYTHON").is_some_and(|v| !v.is_empty()) {
        println!("cargo::rustc-cfg=python_package");
    }
}

fn shared_maps() {
    println!("cargo::rerun-if-env-changed=PROBELAB_ENVMAPS");
    println!("cargo::rerun-if-env-changed=CI");
    let ci = env::var("CI").is_ok_and(|v| v == "true" || v == "1");
    let folders: Vec<PathBuf> = match env::var_os("PROBELAB_ENVMAPS") {
        Some(v) => env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()).collect(),
        None => Vec::new(),
    };
    if folders.is_empty() && !ci {
        return;
    }
    println!("cargo::rustc-cfg=shared_maps");
    for f in folders.iter().filter(|f| f.is_dir()) {
        // A map added to or removed from the folder updates the warning below.
        println!("cargo::rerun-if-changed={}", f.display());
    }
    let found =
        |name: &str| folders.iter().any(|f| ["exr", "hdr"].iter().any(|e| f.join(format!("{name}.{e}")).is_file()));
    let missing: Vec<&str> = PAPER_PROBES.into_iter().filter(|m| !found(m)).collect();
    if folders.is_empty() {
        println!("cargo::warning=CI is set but PROBELAB_ENVMAPS is not: the tests that need the shared maps will fail");
    } else if !missing.is_empty() {
        let list: Vec<String> = folders.iter().map(|f| f.display().to_string()).collect();
        println!(
            "cargo::warning=PROBELAB_ENVMAPS ({}) does not hold {}: the tests that need them will fail",
            list.join(", "),
            missing.join(", ")
        );
    }
}

fn gnu_parallel() {
    // A change of PATH, or of the executable found, reruns this script. Installing the tool
    // into a folder already on PATH does not (watching those folders would rebuild the package
    // whenever anything there changes): then `touch build.rs`, as the test's ignore reason says.
    println!("cargo::rerun-if-env-changed=PATH");
    let path = env::var_os("PATH").unwrap_or_default();
    let found = env::split_paths(&path).map(|d| d.join("parallel")).find(|p| p.is_absolute() && p.is_file());
    if let Some(p) = &found {
        println!("cargo::rerun-if-changed={}", p.display());
        let version = Command::new(p).arg("--version").output();
        if version.is_ok_and(|o| o.status.success() && o.stdout.starts_with(b"GNU parallel")) {
            println!("cargo::rustc-cfg=gnu_parallel");
        }
    }
}

#[cfg(unix)]
fn mode_000_readable() {
    use std::os::unix::fs::PermissionsExt;
    let probe = PathBuf::from(env::var_os("OUT_DIR").unwrap()).join("mode_000_probe");
    let _ = std::fs::remove_file(&probe);
    std::fs::write(&probe, b"").unwrap();
    std::fs::set_permissions(&probe, std::fs::Permissions::from_mode(0o000)).unwrap();
    let readable = std::fs::File::open(&probe).is_ok();
    std::fs::set_permissions(&probe, std::fs::Permissions::from_mode(0o600)).unwrap();
    std::fs::remove_file(&probe).unwrap();
    if readable {
        println!("cargo::rustc-cfg=mode_000_readable");
    }
}

#[cfg(not(unix))]
fn mode_000_readable() {}
