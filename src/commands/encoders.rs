//! `probelab encoders`: lists every registered encoder id with its one-line summary.

use super::output;
use anyhow::Result;

pub fn run() -> Result<i32> {
    let text: String = probelab::encoders::REGISTRY.iter().map(|k| format!("{:28} {}\n", k.id, k.summary)).collect();
    output::write(text.as_bytes())?;
    Ok(0)
}
