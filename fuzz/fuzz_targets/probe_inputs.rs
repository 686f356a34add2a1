//! Fuzz target: probe files (CSV and raw f32, `probelab::pipeline::probeset::format`) and shard
//! state files (`SetStats::load`, then `merge` with itself and with a valid state), on arbitrary
//! bytes. The first byte picks what the rest is read as.
//!
//! Any outcome is fine except a panic, an error that does not name the file, or an accepted
//! input that breaks the promises: every probe finite, every statistic of a loaded or merged
//! state finite, a merged state's probe count the checked sum of its shards'.
#![no_main]

use libfuzzer_sys::fuzz_target;
use probelab::pipeline::probeset::format::{read_all, Format, ProbeReader};
use probelab::pipeline::probeset::score::SetStats;
use probelab::pipeline::probeset::shard::Shard;
use std::path::PathBuf;
use std::sync::OnceLock;

static DIR: OnceLock<PathBuf> = OnceLock::new();

fn init() {
    let dir = std::env::temp_dir().join(format!("probelab-fuzz-probes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    DIR.set(dir).unwrap();
}

fn check_state(s: &SetStats) {
    for e in &s.encoders {
        for sum in [&e.rmse, &e.rel_rmse] {
            assert!(sum.mean().is_none_or(f64::is_finite));
            assert!(sum.count == 0 || (sum.min.is_finite() && sum.max.is_finite() && sum.min <= sum.max));
            for q in [0.0, 0.5, 0.95, 1.0] {
                assert!(sum.quantile(q).is_none_or(f64::is_finite));
            }
        }
    }
    let csv = s.summary_csv().expect("summary of a loaded state");
    let text = String::from_utf8(csv).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
}

fuzz_target!(init: init(), |data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else { return };
    let dir = DIR.get().unwrap();
    match kind % 4 {
        0 | 1 => {
            let (name, format) = if kind % 4 == 0 { ("p.csv", Format::Csv) } else { ("p.f32", Format::F32) };
            let path = dir.join(name);
            std::fs::write(&path, rest).unwrap();
            match read_all(&path, None) {
                Ok(probes) => assert!(probes.iter().all(|p| p.is_finite())),
                Err(e) => assert!(format!("{e:#}").starts_with(&path.display().to_string()), "{e:#}"),
            }
            // A shard of it: the same outcome class, never a panic.
            let shard = Shard { index: (kind as usize / 4) % 3, count: 3 };
            if let Ok(mut r) = ProbeReader::open(&path, format, shard) {
                while let Ok(Some(c)) = r.next_chunk(5) {
                    assert!(c.iter().all(|p| p.is_finite()));
                }
            }
        }
        _ => {
            let path = dir.join("s.toml");
            std::fs::write(&path, rest).unwrap();
            match SetStats::load(&path) {
                Ok(s) => {
                    check_state(&s);
                    let mut twice = s.clone();
                    if twice.merge(&s).is_ok() {
                        check_state(&twice);
                        assert_eq!(Some(twice.probes), s.probes.checked_mul(2));
                    }
                }
                Err(e) => assert!(format!("{e:#}").starts_with(&path.display().to_string()), "{e:#}"),
            }
        }
    }
});
