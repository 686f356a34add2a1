//! The results viewer (`results/site/`, written by `probelab report`) in a real browser: the
//! pytest file `tests/viewer/test_site.py`, run with the interpreter named by `PROBELAB_PYTHON`
//! (one with the Python package, pytest and Playwright installed; `.ci/run` installs them and
//! Debian's `chromium`), against this build's binary. It checks that every page loads from
//! `file://` with no console error or failed request; that the page's evaluation equals the
//! library's irradiance (the Python package's `irradiance`) for one encoder of every family and
//! page form, to 1e-4 of the largest E/π, and its RMSE `probelab eval`'s on the same grid, metric
//! and domain to 1e-3 relative; the pixel checks on a constant map; that every choice changes
//! the picture and the numbers; that each page fits 1280×800 with text of 12 px or more; the
//! claims and the landscape; and the site's size (under 10 MB).
//!
//! pytest's output, its closing count line included, goes straight to this process's stdout
//! (not captured), so `.ci/run` adds pytest's counts to its summary. Without `PROBELAB_PYTHON`,
//! Playwright in it, or Chromium (the build script's `viewer_browser`), and outside CI, the test
//! is ignored with the reason, never passed; in CI (CI=true) it runs, and a missing browser fails
//! it (the pytest file fails rather than skips there).

use std::path::PathBuf;
use std::process::Command;

#[test]
#[cfg_attr(
    not(viewer_browser),
    ignore = "needs PROBELAB_PYTHON: a Python with `pip install ./bindings/python pytest playwright`, and \
              Debian's chromium at /usr/bin/chromium or PROBELAB_CHROMIUM (docs/report.md, \"The results \
              viewer\"); .ci/run installs both. After installing them, `touch build.rs`"
)]
fn the_viewer_passes_its_browser_tests() {
    let python = std::env::var_os("PROBELAB_PYTHON").filter(|v| !v.is_empty()).expect(
        "CI is set but PROBELAB_PYTHON is not: .ci/run builds the package into a virtual environment and sets it",
    );
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let status = Command::new(&python)
        .args(["-m", "pytest", "-p", "no:cacheprovider", "-s", "tests/viewer"])
        .current_dir(&repo)
        .env("PROBELAB_BIN", env!("CARGO_BIN_EXE_probelab"))
        .status()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", PathBuf::from(&python).display()));
    assert!(status.success(), "the viewer's browser tests failed ({status}); their output is above");
}
