//! The encoders: the one `Encoder` trait (`encoder`), one file (or folder) per family, and the
//! registry (`registry`: one line per encoder kind, re-exported here). Adding an encoder means
//! adding its file and one entry in the registry; nothing else in the program names an encoder.

pub mod ambient_cube;
pub mod ambient_dice;
pub mod encoder;
pub mod geomerics;
pub mod hbasis;
pub mod lightmap;
pub mod probe_occlusion;
pub mod quantise;
mod registry;
pub mod self_bounce;
pub mod sg;
pub mod sh;
pub mod sh_high;
pub mod stored;
pub mod zh3;

pub use registry::{
    build, build_list, family_of, known_ids, EncoderKind, NamedEncoder, BASELINE, DEFAULT_IDS, REGISTRY,
};
