//! Decoder panics as errors: a decoder step runs under [`guarded`], which catches a panic and
//! returns it as [`LoadError::DecoderPanic`]. The library installs no panic hook; a front end
//! that keeps caught panics off its stderr asks [`in_guarded_decoder`] in its own hook (the
//! binary does, `main.rs`).

use super::error::LoadError;
use std::any::Any;
use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

thread_local! {
    /// Set while this thread runs a [`guarded`] decoder step.
    static IN_GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// Whether the calling thread is inside a decoder step of the loader, whose panic is caught and
/// returned as [`LoadError::DecoderPanic`]. For a front end's panic hook: the default hook
/// prints every panic, caught or not, so a hook that stays quiet while this is true (and defers
/// to the previous hook otherwise) keeps a malformed file's decoder panic off stderr, where
/// the error already says what happened. The decoders run on the calling thread.
pub fn in_guarded_decoder() -> bool {
    IN_GUARDED.with(Cell::get)
}

/// Runs a decoder step, turning a panic into [`LoadError::DecoderPanic`]. Whether the panic is
/// also printed is the process's panic hook's business ([`in_guarded_decoder`]).
pub(super) fn guarded<T>(
    path: &Path,
    format: &'static str,
    f: impl FnOnce() -> Result<T, LoadError>,
) -> Result<T, LoadError> {
    let was = IN_GUARDED.with(|g| g.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    IN_GUARDED.with(|g| g.set(was));
    result.unwrap_or_else(|payload| {
        Err(LoadError::DecoderPanic { path: path.to_path_buf(), format, message: panic_message(payload.as_ref()) })
    })
}

/// The text of a panic payload, if it has one.
fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "no message".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guarded_turns_a_panic_into_an_error() {
        let path = Path::new("maps/x.exr");
        let r: Result<(), LoadError> = guarded(path, "OpenEXR", || panic!("index out of bounds"));
        let msg = r.unwrap_err().to_string();
        assert_eq!(msg, "maps/x.exr: OpenEXR decoder failed on malformed data (it panicked: index out of bounds)");
        let r = guarded(path, "OpenEXR", || Ok(7));
        assert_eq!(r.unwrap(), 7);
    }
}
