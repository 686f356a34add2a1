//! Fuzz target: the experiment file parser (`pipeline::experiment::Experiment::parse`, reached
//! through the public `probelab::Experiment::from_toml`) on arbitrary text. Any outcome is
//! fine except a panic or an error that does not start with the file's name.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::Experiment;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Experiment::from_toml("fuzz", text) {
        Ok(exp) => assert!(!exp.name().is_empty()),
        Err(e) => {
            let msg = format!("{e:#}");
            assert!(msg.starts_with("fuzz"), "{msg}");
        }
    }
});
