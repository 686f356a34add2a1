//! The Python package (`bindings/python/`): its pytest suite, run with the interpreter named by
//! `PROBELAB_PYTHON` (one where `pip install ./bindings/python` was run, with pytest, numpy,
//! matplotlib and dask[distributed]), against this build's `probelab` binary. The suite checks
//! that the package's rows and coefficients equal the binary's to 1e-12 from a path and from an
//! array, that bad arrays raise clear errors, that the GIL is released, that the Dask recipe of
//! docs/scale-out.md on a two-worker LocalCluster gives the binary's rows, and that the notebook
//! example runs headless.
//!
//! pytest's output, its closing count line included, goes straight to this process's stdout
//! and stderr (not captured), so `.ci/run` can add pytest's counts to its summary.
//! Without `PROBELAB_PYTHON` (and outside CI) the test is ignored, with the reason.

use std::path::PathBuf;
use std::process::Command;

#[test]
#[cfg_attr(
    not(python_package),
    ignore = "needs the Python package: set PROBELAB_PYTHON to a Python where `pip install ./bindings/python` \
              and its test requirements are installed (docs/python.md); .ci/run does"
)]
fn pytest_suite_passes() {
    let python = std::env::var_os("PROBELAB_PYTHON").filter(|v| !v.is_empty()).expect(
        "CI is set but PROBELAB_PYTHON is not: .ci/run builds the package into a virtual environment and sets it",
    );
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let status = Command::new(&python)
        .args(["-m", "pytest", "-p", "no:cacheprovider", "bindings/python/tests"])
        .current_dir(&repo)
        .env("PROBELAB_BIN", env!("CARGO_BIN_EXE_probelab"))
        .env("MPLBACKEND", "Agg")
        .status()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", PathBuf::from(&python).display()));
    assert!(status.success(), "the Python package's pytest suite failed ({status}); its output is above");
}
