//! The IO floor, below every other layer: the one atomic writer (`atomic`: temporary file,
//! fsync, rename, folder fsync), the output folder's lock and the cleanup of what killed
//! writers left (`folder`), outputs that would overwrite inputs (`distinct`), names that stay
//! in their folder (`name`), progress
//! reporting (`progress`: a small trait the library reports through and the binary draws) and
//! `--profile` spans (`profile`).
//!
//! The library above never prints: it reports progress through [`progress::Progress`] and
//! returns everything else as values. Only the binary (`src/main.rs`, `src/commands/`) writes
//! to the terminal.
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod atomic;
pub mod distinct;
pub mod folder;
pub mod name;
pub mod profile;
pub mod progress;
