//! Fuzz target: the experiment file parser (`probelab::pipeline::experiment::Experiment::parse`) on
//! arbitrary text. Any outcome is fine except a panic or an error that does not start with
//! the file name; an accepted experiment must satisfy the validated invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::pipeline::experiment::Experiment;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Experiment::parse(text, Path::new("fuzz.toml")) {
        Ok(exp) => {
            assert!(!exp.maps.is_empty() && !exp.encoders.is_empty());
            assert_eq!(exp.resolution.0, 2 * exp.resolution.1);
            assert!((1..=16).contains(&exp.polar_nodes));
            // Building the cases must not panic either.
            let _ = probelab::pipeline::runner::cases(&exp);
        }
        Err(e) => {
            let msg = format!("{e:#}");
            assert!(msg.starts_with("fuzz.toml"), "{msg}");
        }
    }
});
