//! Fuzz target: the map loader (`envmap::load::load`, reached as `probelab::bench::load_map`
//! with the `bench` feature: the library's internals are crate-private) on arbitrary bytes.
//!
//! The bytes are written to a per-process file and loaded. Any outcome is fine except: a panic
//! that escapes `load` (libFuzzer reports it as a crash), an error message that does not start
//! with the file path, or a map that breaks the loader's promises (2:1, within the size
//! limits, every texel finite, non-negative and at most 1e24; its SH projection finite).
//!
//! Panics inside the OpenEXR/HDR decoders are caught by the loader and returned as
//! `LoadError::DecoderPanic` (told by its debug form); they are silenced here and counted (printed at exit) unless
//! `PROBELAB_FUZZ_STRICT=1`, which keeps libFuzzer's abort-on-any-panic hook to hunt them.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::bench::{load_map as load, project};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

static PATH: OnceLock<PathBuf> = OnceLock::new();
static DECODER_PANICS: AtomicUsize = AtomicUsize::new(0);
/// The loader's size limits (`envmap::header::MAX_WIDTH`, `MAX_HEIGHT`) and texel bound.
const MAX_WIDTH: usize = 16384;
const MAX_HEIGHT: usize = 8192;
const MAX_TEXEL: f32 = 1e24;

fn init() {
    if std::env::var_os("PROBELAB_FUZZ_STRICT").is_none() {
        // Caught decoder panics are expected; an escaping panic still aborts in libfuzzer-sys.
        std::panic::set_hook(Box::new(|_| {}));
    }
    let dir = std::env::temp_dir();
    PATH.set(dir.join(format!("probelab-fuzz-{}.exr", std::process::id()))).unwrap();
}

fuzz_target!(init: init(), |data: &[u8]| {
    let path = PATH.get().unwrap();
    std::fs::write(path, data).expect("write the fuzz input");
    match load(path) {
        Ok(map) => {
            assert_eq!(map.width(), 2 * map.height());
            assert!(map.width() <= MAX_WIDTH && map.height() <= MAX_HEIGHT);
            assert!(map.texels().iter().flatten().all(|v| v.is_finite() && (0.0..=MAX_TEXEL).contains(v)));
            if map.width() <= 64 {
                assert!(project(&map).is_finite());
            }
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with(&path.display().to_string()), "{msg}");
            if format!("{e:?}").starts_with("DecoderPanic") {
                let n = DECODER_PANICS.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_power_of_two() {
                    eprintln!("caught decoder panic #{n}: {msg}");
                }
            }
        }
    }
});
