//! Fuzz target: probe files (CSV and raw f32) and shard state files on arbitrary bytes, through
//! the workflows the commands call (`probelab::ops::probes` on a file, whole and as a shard;
//! `probelab::ops::merge` of a state). The first byte picks what the rest is read
//! as. The library's internals are crate-private, so this goes through `ops`.
//!
//! Any outcome is fine except a panic, an error that does not name the file, or an accepted
//! input whose summary holds a NaN or an infinity.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::ops::merge::{merge, MergeOptions};
use probelab::ops::probes::{probes, ProbeInput, ProbesOptions};
use probelab::ops::{Env, Quiet, RunSettings, SearchPath};
use probelab::Error;
use std::path::PathBuf;
use std::sync::OnceLock;

static DIR: OnceLock<PathBuf> = OnceLock::new();

fn init() {
    let dir = std::env::temp_dir().join(format!("probelab-fuzz-probes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    DIR.set(dir).unwrap();
}

/// A summary's text holds no NaN or infinity.
fn finite(csv: Result<Vec<u8>, Error>) {
    let text = String::from_utf8(csv.expect("the summary of an accepted input")).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
}

fuzz_target!(init: init(), |data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else { return };
    let dir = DIR.get().unwrap();
    let env = Env {
        root: dir.clone(),
        search: SearchPath::new(Vec::new()),
        allow_long: false,
        notes: &Quiet,
        settings: RunSettings { timing: false, profile: None },
    };
    let named = |e: &Error, path: &PathBuf| {
        let msg = format!("{e:#}");
        assert!(msg.contains(&path.display().to_string()), "{msg}");
    };
    if kind % 4 < 2 {
        let path = dir.join(if kind % 4 == 0 { "p.csv" } else { "p.f32" });
        std::fs::write(&path, rest).unwrap();
        for shard in ["0/1".to_string(), format!("{}/3", (kind as usize / 4) % 3)] {
            let o = ProbesOptions {
                input: ProbeInput::File { path: path.clone(), format: None },
                encoders: "sh1,sh2".into(),
                shard,
                quadrature: "6x12".into(),
                chunk: 5,
                out: None,
                save: None,
            };
            match probes(&env, &o) {
                Ok(run) => finite(run.summary_csv()),
                Err(e) => named(&e, &path),
            }
        }
    } else {
        let path = dir.join("s.toml");
        std::fs::write(&path, rest).unwrap();
        match merge(&env, &MergeOptions { files: vec![path.clone()], out: None }) {
            Ok(m) => finite(m.summary_csv()),
            Err(e) => {
                let msg = format!("{e:#}");
                assert!(msg.contains(&path.display().to_string()) || msg.contains("shard"), "{msg}");
            }
        }
    }
});
