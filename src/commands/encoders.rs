//! `probelab encoders`: lists every registered encoder id with its one-line summary
//! (`ops::encoders`).

use super::output;
use anyhow::Result;

pub fn run() -> Result<i32> {
    output::write(probelab::ops::encoders::encoders().to_text().as_bytes())?;
    Ok(0)
}
