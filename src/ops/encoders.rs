//! `probelab encoders`: every registered encoder's id with its one-line summary, in the order
//! tables list them (`encoders::REGISTRY`), and the listing as the command prints it.

use crate::encoders::REGISTRY;

/// One registered encoder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EncoderEntry {
    /// The id `--encoders` and experiment files name it by.
    pub id: &'static str,
    /// What it is, in one line.
    pub summary: &'static str,
}

/// The registered encoders, in registry order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncoderListing {
    /// Each encoder.
    pub encoders: Vec<EncoderEntry>,
}

/// `probelab encoders`.
pub fn encoders() -> EncoderListing {
    EncoderListing { encoders: REGISTRY.iter().map(|k| EncoderEntry { id: k.id, summary: k.summary }).collect() }
}

impl EncoderListing {
    /// The listing as printed: one line per encoder, its id padded to 28 characters.
    pub fn to_text(&self) -> String {
        self.encoders.iter().map(|e| format!("{:28} {}\n", e.id, e.summary)).collect()
    }
}
