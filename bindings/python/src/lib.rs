//! `probelab._core`, the Python extension: a thin layer over the probelab crate that converts
//! Python values to the library's and back. Every number comes from the same functions as the
//! command line (`probelab::ops` for `eval` and `fit`, `probelab::api` for maps and the
//! reference); nothing here computes a score or a fit. The package `probelab`
//! (`python/probelab/__init__.py`) wraps these functions with numpy arrays, checks array
//! shapes and types, and documents the API.
//!
//! Every function that does real work releases the GIL (`Python::detach`) while it runs, so
//! Python threads and Dask workers run in parallel. `eval` runs its work on a thread of its own
//! and checks for signals meanwhile, so Ctrl-C stops it between chunks of work (`interruptible`).
//! Errors are `probelab.Error` (a
//! `ValueError`) carrying the command line's message, the `{:#}` form `probelab` prints after
//! `error: `.

use anyhow::Context;
use probelab::api::{unit_normal, DVec3, Map, Surface, Value};
use probelab::ops::eval::{self as evaluate, EvalMaps, EvalOptions};
use probelab::ops::fit::{self as fitting, encoder_ids, FitOptions};
use probelab::ops::{Cancel, Env, MapSource, Quiet, RunSettings, SearchPath, Texels};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pyo3::create_exception!(
    probelab,
    Error,
    PyValueError,
    "A probelab error: a map not found or refused, a bad option, a bad array. The message is the \
     command line's."
);

/// The library's error as a `probelab.Error`, with the whole chain as the command line prints it.
fn py_err(e: anyhow::Error) -> PyErr {
    Error::new_err(format!("{e:#}"))
}

/// Whether `eval` runs the timing pass (`set_timing`): the Python module's setting, as
/// `--no-timing` is the command line's; the library keeps none.
static TIMING: AtomicBool = AtomicBool::new(true);

/// What a workflow is given from Python: the root, its search path (`<root>/envmaps`, then
/// `PROBELAB_ENVMAPS`), no notes, no refusal of long work (a Python program decides that
/// itself), and the module's timing setting.
fn env(root: &str) -> Env<'static> {
    env_until(root, None)
}

/// [`env`], with the work checking `cancel` between chunks.
fn env_until<'a>(root: &str, cancel: Option<&'a Cancel>) -> Env<'a> {
    Env {
        root: root.into(),
        search: SearchPath::from_env(Path::new(root).join("envmaps")),
        allow_long: true,
        notes: &Quiet,
        settings: RunSettings { timing: TIMING.load(Ordering::Relaxed), profile: None, cancel },
    }
}

/// How often the calling thread looks for a signal while the work runs.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a thread of its own while the calling thread, without the GIL but for a
/// moment every [`SIGNAL_POLL`], checks for signals (`Python::check_signals`: on the main
/// thread, where Python handles them). When one raises (Ctrl-C: `KeyboardInterrupt`), `cancel`
/// is set, the work stops at its next chunk (the library checks it between chunks; it knows
/// nothing of Python), and the exception is raised once the work has stopped.
fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &Cancel,
    work: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    let done = AtomicBool::new(false);
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            let out = work();
            done.store(true, Ordering::Release);
            out
        });
        while !py.detach(|| wait(&done, SIGNAL_POLL)) {
            if let Err(signal) = py.check_signals() {
                cancel.cancel();
                py.detach(|| drop(handle.join()));
                return Err(signal);
            }
        }
        match handle.join() {
            Ok(out) => out.map_err(py_err),
            Err(_) => Err(Error::new_err("internal error: the work panicked")),
        }
    })
}

/// Waits up to `limit` for `done`; whether it is set.
fn wait(done: &AtomicBool, limit: Duration) -> bool {
    let start = Instant::now();
    while !done.load(Ordering::Acquire) {
        if start.elapsed() >= limit {
            return false;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    true
}

/// The map of `map`: a `str` (a name or path) or a tuple `(name, width, height, bytes)` of
/// little-endian float32 RGB texels, row-major from the zenith (what `probelab` makes of an
/// (H, W, 3) array).
fn source(map: &Bound<'_, PyAny>) -> PyResult<MapSource> {
    if let Ok(name) = map.extract::<String>() {
        return Ok(MapSource::Named(name));
    }
    let (name, width, height, bytes): (String, usize, usize, Bound<'_, PyBytes>) = map.extract()?;
    let bytes = bytes.as_bytes();
    if bytes.len() != width * height * 12 {
        return Err(Error::new_err(format!(
            "map '{name}': {} bytes of texels for {width}x{height} (expected {})",
            bytes.len(),
            width * height * 12
        )));
    }
    let texels = bytes
        .chunks_exact(12)
        .map(|t| std::array::from_fn(|c| f32::from_le_bytes(t[4 * c..4 * c + 4].try_into().unwrap())))
        .collect();
    Ok(MapSource::Texels(Texels { name, width, height, texels }))
}

/// `(name, width, height, texels)`: the map `name` (a name on the search path or a file
/// path) with its texels as little-endian float32 RGB, row-major, row 0 at the zenith.
#[pyfunction]
fn load_map<'py>(
    py: Python<'py>,
    name: String,
    root: String,
) -> PyResult<(String, usize, usize, Bound<'py, PyByteArray>)> {
    let env = env(&root);
    let map = py.detach(|| Map::load_on(&env.search, &name)).map_err(py_err)?;
    let (w, h) = map.size();
    let texels = PyByteArray::new_with(py, w * h * 12, |buf| {
        for (dst, t) in buf.chunks_exact_mut(12).zip(map.texels()) {
            for c in 0..3 {
                dst[4 * c..4 * c + 4].copy_from_slice(&t[c].to_le_bytes());
            }
        }
        Ok(())
    })?;
    Ok((map.name().to_string(), w, h, texels))
}

/// `probelab eval`'s output on one map, as text: its JSON document (`format` "json",
/// docs/json.md) or its CSV table (`format` "csv", byte for byte what `probelab eval` prints).
/// Ctrl-C stops it ([`interruptible`]).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn eval(
    py: Python<'_>,
    map: &Bound<'_, PyAny>,
    root: String,
    encoders: String,
    domain: String,
    metric: String,
    resolution: String,
    polar_nodes: usize,
    format: String,
) -> PyResult<String> {
    let maps = match source(map)? {
        MapSource::Named(name) => EvalMaps::Named(vec![name]),
        MapSource::Texels(texels) => EvalMaps::Texels(texels),
    };
    let options = EvalOptions { maps, encoders, domain, metric, resolution, polar_nodes };
    let cancel = Cancel::default();
    let env = env_until(&root, Some(&cancel));
    interruptible(py, &cancel, || {
        let evaluated = evaluate::eval(&env, &options)?;
        match format.as_str() {
            "csv" => Ok(String::from_utf8(evaluated.to_csv()?)?),
            "json" => evaluated.to_json(),
            other => anyhow::bail!("format '{other}': expected csv or json"),
        }
    })
}

/// The flattened stored coefficients of one fit: per component, its name (`L1_0.g`, `d.x`,
/// `ratio`), its unit and its value.
type Coefficients = (Vec<String>, Vec<String>, Vec<f64>);

/// `probelab fit`'s JSON document on one map, and each fit's stored coefficients flattened
/// (the entries of role `stored`, their components in order: as many as the encoder stores).
#[pyfunction]
fn fit(
    py: Python<'_>,
    map: &Bound<'_, PyAny>,
    root: String,
    encoders: String,
    normal: Option<(f64, f64, f64)>,
) -> PyResult<(String, Vec<Coefficients>)> {
    let options = FitOptions { map: source(map)?, encoders, surface: surface(normal) };
    py.detach(|| {
        let fitted = fitting::fit(&env(&root), &options)?;
        let coefficients = fitted.fits.iter().map(|(_, stored)| flatten(stored)).collect();
        Ok((fitted.to_json()?, coefficients))
    })
    .map_err(py_err)
}

/// The stored entries' components with their names and units.
fn flatten(stored: &probelab::api::Stored) -> Coefficients {
    let mut out: Coefficients = Default::default();
    for e in stored.entries.iter().filter(|e| e.role == probelab::api::Role::Stored) {
        let suffixes: &[&str] = match e.value {
            Value::Scalar(_) => &[""],
            Value::Rgb(_) => &[".r", ".g", ".b"],
            Value::Vector(_) => &[".x", ".y", ".z"],
        };
        for (s, v) in suffixes.iter().zip(e.value.components()) {
            out.0.push(format!("{}{s}", e.name));
            out.1.push(e.unit.label().to_string());
            out.2.push(v);
        }
    }
    out
}

/// The exact E/π at each normal of `normals` (little-endian float64 triples; each finite and
/// non-zero, normalised here), on the sphere or about the surface normal `normal`, as
/// little-endian float64 RGB triples.
#[pyfunction]
fn reference<'py>(
    py: Python<'py>,
    map: &Bound<'_, PyAny>,
    root: String,
    normals: &[u8],
    normal: Option<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyByteArray>> {
    let source = source(map)?;
    let normals = unit_normals(normals)?;
    let surface = surface(normal);
    let values = py
        .detach(|| -> anyhow::Result<Vec<DVec3>> {
            let map = source.open(&env(&root).search)?;
            Ok(map.lighting(surface)?.reference(&normals))
        })
        .map_err(py_err)?;
    rgb_bytes(py, &values)
}

/// The E/π of encoder `id` (defaults), fitted to the map on the sphere or about the surface
/// normal `normal`, at each normal of `normals` (as for [`reference`]), as float64 RGB triples.
#[pyfunction]
fn irradiance<'py>(
    py: Python<'py>,
    map: &Bound<'_, PyAny>,
    root: String,
    id: String,
    normals: &[u8],
    normal: Option<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyByteArray>> {
    let source = source(map)?;
    let normals = unit_normals(normals)?;
    let surface = surface(normal);
    let values = py
        .detach(|| -> anyhow::Result<Vec<DVec3>> {
            let ids = encoder_ids(&id, surface)?;
            let map = source.open(&env(&root).search)?;
            let light = map.lighting(surface)?;
            let fit = light.fit(&ids[0], "")?;
            Ok(normals.iter().map(|&n| fit.irradiance(n)).collect())
        })
        .map_err(py_err)?;
    rgb_bytes(py, &values)
}

/// RGB triples as a bytearray of little-endian float64.
fn rgb_bytes<'py>(py: Python<'py>, values: &[DVec3]) -> PyResult<Bound<'py, PyByteArray>> {
    PyByteArray::new_with(py, values.len() * 24, |buf| {
        for (dst, v) in buf.chunks_exact_mut(8).zip(values.iter().flat_map(|v| v.to_array())) {
            dst.copy_from_slice(&v.to_le_bytes());
        }
        Ok(())
    })
}

/// The sphere, or the surface with normal `normal`.
fn surface(normal: Option<(f64, f64, f64)>) -> Surface {
    match normal {
        None => Surface::Sphere,
        Some((x, y, z)) => Surface::Normal(DVec3::new(x, y, z)),
    }
}

/// The normals of `bytes` (float64 triples), each normalised; a zero or non-finite one is an
/// error naming its row.
fn unit_normals(bytes: &[u8]) -> PyResult<Vec<DVec3>> {
    if !bytes.len().is_multiple_of(24) {
        return Err(Error::new_err(format!("normals: {} bytes is not a whole number of float64 triples", bytes.len())));
    }
    bytes
        .chunks_exact(24)
        .enumerate()
        .map(|(i, t)| {
            let c: [f64; 3] = std::array::from_fn(|k| f64::from_le_bytes(t[8 * k..8 * k + 8].try_into().unwrap()));
            unit_normal(DVec3::from_array(c)).with_context(|| format!("normals: row {i}")).map_err(py_err)
        })
        .collect()
}

/// Every registered encoder as `(id, summary)`, in the order `probelab encoders` lists them.
#[pyfunction]
fn encoders() -> Vec<(&'static str, &'static str)> {
    probelab::ops::encoders::encoders().encoders.iter().map(|e| (e.id, e.summary)).collect()
}

/// Whether `eval` measures `fit_ns` and `eval_ns` (the command line's `--no-timing` is
/// `set_timing(False)`); for this Python process.
#[pyfunction]
fn set_timing(on: bool) {
    TIMING.store(on, Ordering::Relaxed);
}

/// The module `probelab._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<Error>())?;
    m.add("COLUMNS", evaluate::COLUMNS.to_vec())?;
    m.add("NUMERIC_COLUMNS", evaluate::NUMERIC_COLUMNS.to_vec())?;
    m.add("TIMING_COLUMNS", evaluate::TIMING_COLUMNS.to_vec())?;
    m.add("DEFAULT_POLAR_NODES", evaluate::DEFAULT_POLAR_NODES)?;
    m.add_function(wrap_pyfunction!(load_map, m)?)?;
    m.add_function(wrap_pyfunction!(eval, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(reference, m)?)?;
    m.add_function(wrap_pyfunction!(irradiance, m)?)?;
    m.add_function(wrap_pyfunction!(encoders, m)?)?;
    m.add_function(wrap_pyfunction!(set_timing, m)?)?;
    Ok(())
}
