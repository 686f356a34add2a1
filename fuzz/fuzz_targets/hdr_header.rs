//! Fuzz target: the Radiance header pre-read (`envmap::header::hdr`: size limits, line ends,
//! `EXPOSURE=`, `COLORCORR=`, `PRIMARIES=`, `PIXASPECT=`) and the whole loader behind it, on
//! arbitrary bytes after a `#?RADIANCE` signature, through `probelab::bench::load_map` (the
//! `bench` feature; the library's internals are crate-private).
//!
//! Any outcome is fine except a panic, an error that does not name the file, or an accepted map
//! that breaks the promises: an exposure finite and positive, a size within the limits, texels
//! finite, non-negative and at most 1e24 (after exposure, colour correction and primaries).
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::bench::load_map as load;
use std::path::PathBuf;
use std::sync::OnceLock;

static PATH: OnceLock<PathBuf> = OnceLock::new();

fn init() {
    if std::env::var_os("PROBELAB_FUZZ_STRICT").is_none() {
        // Decoder panics are caught by the loader; an escaping panic still aborts.
        std::panic::set_hook(Box::new(|_| {}));
    }
    let dir = std::env::temp_dir();
    PATH.set(dir.join(format!("probelab-fuzz-hdr-{}.hdr", std::process::id()))).unwrap();
}

fuzz_target!(init: init(), |data: &[u8]| {
    let path = PATH.get().unwrap();
    let bytes = [b"#?RADIANCE\n".as_slice(), data].concat();
    std::fs::write(path, bytes).expect("write the fuzz input");
    match load(path) {
        Ok(map) => {
            assert!(map.exposure.is_finite() && map.exposure > 0.0);
            assert_eq!(map.width(), 2 * map.height());
            assert!(map.width() <= 16384 && map.height() <= 8192);
            assert!(map.texels().iter().flatten().all(|v| v.is_finite() && (0.0..=1e24).contains(v)));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with(&path.display().to_string()), "{msg}");
        }
    }
});
