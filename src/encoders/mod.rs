//! The encoders: the one `Encoder` trait (`encoder`), one file (or folder) per family, and the
//! registry (`registry`: one line per encoder kind, re-exported here). Adding an encoder means
//! adding its file and one entry in the registry; nothing else in the program names an encoder.
//! Outside the crate this module is the trait, the registry and the types they name; the
//! families' files are internal.

pub(crate) mod ambient_cube;
pub(crate) mod ambient_dice;
pub(crate) mod encoder;
pub(crate) mod geomerics;
pub(crate) mod hbasis;
pub(crate) mod lightmap;
pub(crate) mod probe_occlusion;
pub(crate) mod quantise;
mod registry;
pub(crate) mod self_bounce;
pub(crate) mod sg;
pub(crate) mod sh;
pub(crate) mod sh_high;
pub(crate) mod stored;
pub(crate) mod zh3;

pub use registry::{
    build, build_list, family_of, known_ids, EncoderKind, NamedEncoder, BASELINE, DEFAULT_IDS, REGISTRY,
};

// The surface for people who add an encoding: the trait, what a fit reads and returns, and the
// types those name.
pub use crate::math::colour::Rgb;
pub use crate::math::sh::Sh9;
pub use crate::reference::radiance::RadianceSource;
pub use encoder::{Encoder, Family, FitInput, Fitted, Light, Params};
pub use stored::{Entry, Role, Stored, Unit, Value};
