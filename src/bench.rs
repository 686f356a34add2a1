//! The internal kernels the benches time (`benches/`), re-exported only when the `bench` feature
//! is on (`cargo bench --features bench`). The benches measure the reference, the projection,
//! each encoder's fit and evaluation, the probe-set kernels and the ZH3 axis solve at the level
//! where their cost lives, below the public surface; the fuzz targets (`fuzz/`) reach the map
//! loader and the claims parser the same way. A default build has none of this, and
//! nothing else may use it (`tests/architecture.rs`: only `benches/` names it). No stability
//! promise: these names follow the code.

pub use crate::claims::declaration::parse::parse as parse_claims;
pub use crate::claims::declaration::{ClaimDecl, Paper};
pub use crate::encoders::encoder::{FitInput, Fitted, Params};
pub use crate::encoders::stored::Stored;
pub use crate::encoders::zh3::model::{solved, Solved};
pub use crate::encoders::zh3::solve::{Formulation, SolveStats, SolverSettings, Zonal};
pub use crate::encoders::zh3::AxisRule;
pub use crate::encoders::{build, REGISTRY};
pub use crate::envmap::load::{load as load_map, write_exr_half};
pub use crate::envmap::moments::RowMoments;
pub use crate::envmap::resample::resized;
pub use crate::envmap::search::SearchPath;
pub use crate::envmap::{EnvMap, LatLong};
pub use crate::math::cap::Cap;
pub use crate::math::colour::Rgb;
pub use crate::math::sh::{constant, Sh9};
pub use crate::math::sh_rotation::{uniform_rotation, ShRotation};
pub use crate::math::stats::Summary;
pub use crate::pipeline::cases::cone_centre;
pub use crate::pipeline::probeset::score::{probe_rmse, SphereRule};
pub use crate::pipeline::probeset::synth::{scene_palette, Synth};
pub use crate::reference::domain::{fibonacci_sphere, Domain};
pub use crate::reference::exact::{Reference, DEFAULT_POLAR_NODES};
pub use crate::reference::lighting::Light;
pub use crate::reference::projection::{project, project_visible};
pub use crate::reference::radiance::MapLight;
pub use crate::reference::scenes::generated;
