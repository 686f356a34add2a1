//! `probelab maps`: the map search path, the maps it finds and the known maps it lacks
//! ([`list`]); `probelab maps import`, the 256x128 maps of map files made as the shared ones
//! were ([`import`]).

pub mod import;
pub mod list;
