//! Fuzz target: a paper's claims declaration (`probelab::bench::parse_claims`, the crate's own parser behind the `bench` feature) on
//! arbitrary text. Any outcome is fine except a panic (a deep nesting included: it is refused
//! with its line before the TOML parser sees it) or an error that does not start with the file
//! name; an accepted declaration has a title and claims with distinct ids.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::bench::parse_claims as parse;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse("fuzz", text, Path::new("fuzz.toml")) {
        Ok(paper) => {
            assert_eq!(paper.key, "fuzz");
            let mut ids: Vec<&str> = paper.claims.iter().map(|c| c.id.as_str()).collect();
            ids.sort_unstable();
            let n = ids.len();
            ids.dedup();
            assert_eq!(ids.len(), n, "a claim id twice");
        }
        Err(e) => {
            let msg = format!("{e:#}");
            assert!(msg.starts_with("fuzz.toml"), "{msg}");
        }
    }
});
