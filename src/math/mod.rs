//! The math layer: pure functions and small value types with no knowledge of maps, encoders
//! or files. SH basis and band scales (`sh`; through band 4: `sh4`), the peer tool's Halton
//! sphere samples (`halton`), SH rotation (`sh_rotation`), Gram matrices over
//! hemispheres and cones (`gram`), Gauss–Legendre quadrature (`quadrature`), spherical caps
//! and their arcs on a parallel (`cap`), linear RGB and Rec.709 luminance (`colour`), other primaries converted to Rec.709
//! (`primaries`), the direction convention (`convention`), exact
//! mergeable statistics (`stats`), the one rule for echoing a user's value or line in an
//! error (`echo`), and the nearest known name to a typo (`nearest`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod cap;
pub mod colour;
pub mod convention;
pub mod echo;
pub mod gram;
pub mod halton;
pub mod nearest;
pub mod primaries;
pub mod quadrature;
pub mod sh;
pub mod sh4;
pub mod sh_rotation;
pub mod stats;
#[cfg(test)]
pub(crate) mod test_rng;
