//! Reading lat-long environment maps from OpenEXR and Radiance RGBE (`.hdr`) files, and
//! writing small maps as OpenEXR.
//!
//! [`load`] identifies the format from the first bytes of the file (the extension is not
//! trusted), reads and checks the header before any pixel is decoded (size limits, aspect,
//! channels, sample types, single part, no deep data), then decodes the pixels, refusing an
//! OpenEXR file whose chunks do not store every pixel exactly once (a duplicated, missing or
//! misplaced chunk is never read as default-filled pixels), and checks every texel through
//! [`EnvMap::new`](crate::envmap::EnvMap::new). Every failure is a [`LoadError`] whose message
//! starts with the file path and says what is wrong; a decoder panic on malformed data is
//! caught and reported as an error too (the library installs no panic hook:
//! [`in_guarded_decoder`] lets a front end's hook keep the caught panic quiet).
//!
//! [`write_exr`] writes a single-part scanline f32 RGB EXR with ZIP compression, and
//! [`write_exr_half`] the same with half channels (the format of the shared maps), each
//! atomically (temporary file in the same directory, then rename).
//!
//! The files: `read.rs` (the entry points), `format.rs` (telling the formats apart), `exr.rs`,
//! `hdr.rs` (the decoders), `exr_blocks.rs`
//! (an OpenEXR layer's chunks decompressed on the run's threads), `colour.rs` (exposure, colour correction, primaries), `size.rs`, `coverage.rs` (what is checked), `watch.rs`
//! (truncation), `guard.rs` (decoder panics), `error.rs`, `hash.rs` (the file's sha256),
//! `write.rs`.

mod colour;
mod coverage;
mod error;
mod exr;
mod exr_blocks;
mod format;
mod guard;
mod hash;
mod hdr;
mod read;
mod size;
mod watch;
mod write;

pub use error::LoadError;
pub use guard::in_guarded_decoder;
pub use hash::{sha256_hex, sha256_hex_of};
pub use read::{dimensions, load};
pub use write::{write_exr, write_exr_half};
