//! Fuzz target: the Radiance header pre-read (`probelab::envmap::header::hdr`) on arbitrary
//! bytes, and the whole loader on the same bytes behind a `#?RADIANCE` signature.
//!
//! Any outcome is fine except a panic, an error that does not name the file, or an accepted
//! header that breaks the promises: an exposure finite and positive, a size within the limits;
//! a loaded map's texels finite and non-negative (divided by that exposure).
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::envmap::header::{hdr, MAX_HEIGHT, MAX_WIDTH};
use probelab::envmap::load::load;
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
    if let Ok(head) = hdr(&mut &data[..]) {
        assert!(head.exposure.is_finite() && head.exposure > 0.0, "{head:?}");
        if let Some((w, h)) = head.size {
            assert!(w <= MAX_WIDTH && h <= MAX_HEIGHT, "{head:?}");
        }
    }
    let path = PATH.get().unwrap();
    let bytes = [b"#?RADIANCE\n".as_slice(), data].concat();
    std::fs::write(path, bytes).expect("write the fuzz input");
    match load(path) {
        Ok(map) => {
            assert!(map.exposure.is_finite() && map.exposure > 0.0);
            assert_eq!(map.width(), 2 * map.height());
            assert!(map.texels().iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with(&path.display().to_string()), "{msg}");
        }
    }
});
