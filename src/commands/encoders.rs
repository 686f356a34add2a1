//! `probelab encoders`: lists every registered encoder id with its one-line summary.

use anyhow::Result;
use probelab::io::output;

pub fn run() -> Result<i32> {
    let text: String = probelab::encoders::REGISTRY.iter().map(|k| format!("{:28} {}\n", k.id, k.summary)).collect();
    output::write(text.as_bytes())?;
    Ok(0)
}
