//! Where a workflow's map comes from ([`MapSource`]): a name or file path found on the search
//! path, or texels handed over in memory ([`Texels`], the Python package's arrays). Opening one
//! is `api::Map::load_on` or `api::Map::from_texels`, so both front ends read maps alike.

use crate::api::Map;
use crate::envmap::search::SearchPath;
use anyhow::Result;

/// A lat-long map handed over in memory: RGB texels, row-major, row 0 at the zenith.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    /// The map's name in the rows and documents.
    pub name: String,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width × height` RGB texels.
    pub texels: Vec<[f32; 3]>,
}

impl Texels {
    /// The map, its texels checked (`api::Map::from_texels`).
    pub fn open(&self) -> Result<Map> {
        Map::from_texels(&self.name, self.width, self.height, self.texels.clone())
    }
}

/// Where one map comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum MapSource {
    /// A name (on the search path) or a file path.
    Named(String),
    /// Texels in memory.
    Texels(Texels),
}

impl MapSource {
    /// The map as asked for: the name or path, or the texels' name.
    pub fn given(&self) -> &str {
        match self {
            MapSource::Named(name) => name,
            MapSource::Texels(t) => &t.name,
        }
    }

    /// The map: found on `search` and loaded, or built from the texels and checked.
    pub fn open(&self, search: &SearchPath) -> Result<Map> {
        match self {
            MapSource::Named(name) => Map::load_on(search, name),
            MapSource::Texels(t) => t.open(),
        }
    }
}
