//! The library facade: the few types an engine's bake or a script needs, with a stability
//! promise the internal modules do not make. Load a lat-long map ([`Map`]); choose where the
//! light is seen from ([`Surface`]: a probe on the whole sphere, or a surface with normal N
//! seeing the hemisphere about it); compute the exact reference E/π at given normals
//! ([`Lighting::reference`]); fit any registered encoder by id with its settings
//! ([`Lighting::fit`]); evaluate the fit ([`Fit::irradiance`]); get its stored coefficients
//! ([`Fit::stored`], a [`Stored`]); score it against the reference ([`Lighting::score`]).
//!
//! Units and directions are those of `docs/conventions.md` §1: irradiance is E/π (a constant
//! environment of radiance 1 gives 1), directions are world-space unit vectors with +Y up.
//! Everything goes through the same code as the `probelab` command line: the fit input of a
//! surface is the one `probelab eval --domain hemisphere:…` builds (the map's light under the
//! hemisphere about N, and the exact E/π at N), and [`Lighting::score`] is its scoring step.

use crate::encoders::encoder::{surface_normal_refusal, Encoder, Fitted};
use crate::envmap::search::SearchPath;
use crate::envmap::EnvMap;
use crate::pipeline::experiment::Experiment as PipelineExperiment;
use crate::pipeline::runner::{score_fit, Case, CaseData, MapData};
use crate::reference::exact::DEFAULT_POLAR_NODES;
use crate::reference::metrics::Metric;
use anyhow::{bail, Context, Result};
use std::path::Path;

pub use crate::encoders::stored::{Entry, Role, Stored, Unit, Value};
pub use crate::math::colour::Rgb;
pub use crate::pipeline::table::Row;
pub use crate::reference::metrics::Scores;
pub use glam::DVec3;

/// The output grid (W, H) of normals that `probelab eval` and experiments score on unless told
/// otherwise (`--resolution`, the experiment key `resolution`): pass it to [`Lighting::score`]
/// to get the command line's numbers.
pub const DEFAULT_RESOLUTION: (usize, usize) = (256, 128);

/// A lat-long HDR map (OpenEXR or Radiance `.hdr`), read as piecewise-constant radiance over
/// its texel cells (`docs/conventions.md` §1).
pub struct Map {
    map: EnvMap,
}

impl Map {
    /// Loads a map by name or path: a path that exists is read as it is; a name is looked up
    /// as `<name>.exr` or `<name>.hdr` in `<root>/envmaps`, then in each folder of the
    /// `PROBELAB_ENVMAPS` variable (the command line's search path). Errors name the file and
    /// what is wrong, or every folder searched.
    pub fn load(name: &str, root: impl AsRef<Path>) -> Result<Map> {
        let search = SearchPath::from_env(root.as_ref().join("envmaps"));
        let map = search.load(name).with_context(|| format!("loading map '{name}'"))?;
        Ok(Map { map })
    }

    /// Loads a map by name or path on a given search path ([`crate::ops::SearchPath`], e.g. the
    /// command line's: `<root>/envmaps`, then `PROBELAB_ENVMAPS`).
    pub fn load_on(search: &SearchPath, name: &str) -> Result<Map> {
        Ok(Map { map: search.load(name)? })
    }

    /// A map from its texels in memory: `width` × `height` linear RGB radiances, row-major,
    /// row 0 at the zenith and the centre column looking along −Z (`docs/conventions.md` §1,
    /// the layout of a loaded file; [`Map::texels`]), named `name` in tables. A size that is
    /// not 2:1, a texel count that does not match it, and a NaN, infinite or negative value are
    /// errors naming `name`, what is wrong and the first bad texel.
    pub fn from_texels(name: &str, width: usize, height: usize, texels: Vec<[f32; 3]>) -> Result<Map> {
        let map = EnvMap::new(name, width, height, texels).with_context(|| format!("map '{name}'"))?;
        Ok(Map { map })
    }

    /// Writes the map to `path` as an OpenEXR file that [`Map::load`] reads back bit-exactly:
    /// f32 R, G, B channels, ZIP compression, written beside `path` and then moved over it, so a
    /// reader never sees a partial file. Errors name the file and what failed.
    pub fn write_exr(&self, path: impl AsRef<Path>) -> Result<()> {
        Ok(crate::envmap::load::write_exr(path.as_ref(), &self.map)?)
    }

    /// Writes the map as a half-float ZIP OpenEXR, the format of most published HDRIs (values
    /// round to the nearest half), atomically like [`Map::write_exr`].
    pub fn write_exr_half(&self, path: impl AsRef<Path>) -> Result<()> {
        Ok(crate::envmap::load::write_exr_half(path.as_ref(), &self.map)?)
    }

    /// The map at another 2:1 size: averaged down, solid-angle weighted, to a smaller grid (as
    /// the shared maps were made), or the nearest texel up to a larger one.
    pub fn resized(&self, width: usize, height: usize) -> Result<Map> {
        let map = crate::envmap::resample::resized(&self.map, width, height).map_err(anyhow::Error::msg)?;
        Ok(Map { map })
    }

    /// The texels: linear RGB radiance, row-major, row 0 at the zenith, the centre column
    /// looking along −Z (`docs/conventions.md` §1); [`Map::size`] gives (W, H).
    pub fn texels(&self) -> &[[f32; 3]] {
        self.map.texels()
    }

    /// The map as the internal layers hold it (for `ops`).
    pub(crate) fn env_map(&self) -> &EnvMap {
        &self.map
    }

    /// The map's name (its file stem).
    pub fn name(&self) -> &str {
        &self.map.name
    }

    /// Width and height in texels (2:1).
    pub fn size(&self) -> (usize, usize) {
        (self.map.width(), self.map.height())
    }

    /// The light as seen from `surface`: the whole map for [`Surface::Sphere`], the
    /// hemisphere about N for [`Surface::Normal`]. N is checked and normalised by
    /// [`unit_normal`].
    pub fn lighting(&self, surface: Surface) -> Result<Lighting<'_>> {
        let case = match surface {
            Surface::Sphere => Case::sphere(),
            Surface::Normal(n) => {
                let n = unit_normal(n).context("surface normal")?;
                Case::hemisphere(n, format!("hemisphere:({}, {}, {})", n.x, n.y, n.z))
            }
        };
        Ok(Lighting { data: MapData::new(&self.map), case, name: self.map.name.clone() })
    }
}

/// The shortest length a normal may have before it is normalised: below it, its direction is
/// mostly rounding.
pub const MIN_NORMAL_LENGTH: f64 = 1e-6;

/// `n` normalised: every component finite and |n| ≥ [`MIN_NORMAL_LENGTH`], else an error that
/// shows `n` and says what a normal must be. The one check of every normal a user gives
/// (`fit --normal`, [`Surface::Normal`], the Python package).
pub fn unit_normal(n: DVec3) -> Result<DVec3> {
    let shown = |v: f64| crate::math::echo::value(&v.to_string());
    // Scaled by its largest component first, so that neither a huge nor a tiny normal
    // overflows or underflows on the way to its length.
    let largest = n.abs().max_element();
    let scaled = if largest > 0.0 { n / largest } else { n };
    let length = largest * scaled.length();
    if !n.is_finite() || length.is_nan() || length < MIN_NORMAL_LENGTH {
        bail!(
            "({}, {}, {}): a normal must be three finite numbers of length at least {MIN_NORMAL_LENGTH:e} (its \
             length is {}); e.g. 0,1,0",
            shown(n.x),
            shown(n.y),
            shown(n.z),
            shown(length)
        );
    }
    Ok(scaled.normalize())
}

/// Where the light is seen from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// A probe in free space: the whole map's light, normals over the whole sphere.
    Sphere,
    /// A surface with this normal N: only the light above its horizon (the hemisphere about
    /// N) reaches it, and the encoders that need N (AHD/HHD, the H-basis, the occlusion
    /// operators) are fitted about it.
    Normal(DVec3),
}

/// Prints `sphere` or `hemisphere about N = (x, y, z)`.
impl std::fmt::Display for Surface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Surface::Sphere => f.write_str("sphere"),
            Surface::Normal(n) => write!(f, "hemisphere about N = ({}, {}, {})", n.x, n.y, n.z),
        }
    }
}

/// A map's light as seen from one [`Surface`]: what every fit and the reference are computed
/// from (the map's SH and row moments, computed once).
pub struct Lighting<'m> {
    data: MapData<'m>,
    case: Case,
    name: String,
}

impl<'m> Lighting<'m> {
    /// What this light is, for a reader: the map and the domain, e.g. `map blender_city_256x128,
    /// sphere (the whole map, no surface)` or `…, hemisphere about N = (0, 1, 0)`.
    pub fn describe(&self) -> String {
        match self.case.normal {
            None => format!("map {}, sphere (the whole map, no surface)", self.name),
            Some(n) => format!(
                "map {}, hemisphere about N = ({}, {}, {}) (the light above the surface's horizon)",
                self.name, n.x, n.y, n.z
            ),
        }
    }

    /// The surface normal N, if any.
    pub fn normal(&self) -> Option<DVec3> {
        self.case.normal
    }

    fn case_data(&self) -> CaseData<'_> {
        CaseData::new(&self.data, &self.case, DEFAULT_POLAR_NODES)
    }

    /// The exact E/π at each unit normal: the map integrated cell by cell against the
    /// clamped cosine, under the hemisphere about N for a surface (`docs/conventions.md`,
    /// "The exact reference").
    pub fn reference(&self, normals: &[DVec3]) -> Vec<Rgb> {
        self.case_data().reference_many(normals)
    }

    /// Fits the encoder `id` (one of [`encoder_ids`]) with `settings`, TOML text of its keys
    /// (`""` for the defaults; e.g. `axis_weights = "rec709"`). Errors: an unknown id (listing
    /// the valid ones), a bad or unknown key, and an encoder that needs a surface normal fitted
    /// on [`Surface::Sphere`].
    pub fn fit(&self, id: &str, settings: &str) -> Result<Fit> {
        let table: toml::Table =
            toml::from_str(settings).with_context(|| format!("settings of encoder '{id}': not TOML"))?;
        let named = crate::encoders::build(id, None, table)?;
        if self.case.normal.is_none() && named.encoder.needs_surface_normal() {
            bail!("{}; fit it on Surface::Normal(N)", surface_normal_refusal(id));
        }
        let fitted = named.encoder.fit(&self.case_data().fit_input());
        Ok(Fit { id: named.name, encoder: named.encoder, fitted })
    }

    /// The solid-angle-weighted error of `fit` against the exact reference over the domain
    /// (the sphere, or the hemisphere about N) on a lat-long grid of `resolution` (W, H):
    /// the `exact` metric of the result tables (`docs/tables.md`). W and H must be even and
    /// from 4 to 4096.
    pub fn score(&self, fit: &Fit, resolution: (usize, usize)) -> Result<Score> {
        let (w, h) = resolution;
        if !(4..=4096).contains(&w) || !(4..=4096).contains(&h) || w % 2 != 0 || h % 2 != 0 {
            bail!("resolution {w}x{h}: expected even W and H from 4 to 4096");
        }
        let cd = self.case_data();
        let grid = self.case.domain.output_grid(resolution);
        let reference = cd.reference_on(&grid);
        let s = score_fit(fit.encoder.as_ref(), fit.fitted.as_ref(), &grid, &reference, Metric::Exact);
        Ok(Score { rmse: s.rmse, rel_rmse: s.rel_rmse, rmse_rgb: Rgb::from_array(s.rmse_rgb), neg_frac: s.neg_frac })
    }
}

/// The error of a fit against the exact reference ([`Lighting::score`]), in E/π.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    /// √(mean of the three channels' weighted mean squared errors).
    pub rmse: f64,
    /// `rmse` over the RMS of the reference.
    pub rel_rmse: f64,
    /// The RMSE of each channel.
    pub rmse_rgb: Rgb,
    /// The weighted fraction of normals where any channel of the fit is negative.
    pub neg_frac: f64,
}

/// Prints `rmse=… rel_rmse=… neg_frac=…` (E/π; `rel_rmse` and `neg_frac` are unitless).
impl std::fmt::Display for Score {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "rmse={} rel_rmse={} neg_frac={}", self.rmse, self.rel_rmse, self.neg_frac)
    }
}

/// A fitted encoding.
pub struct Fit {
    id: String,
    encoder: Box<dyn Encoder>,
    fitted: Box<dyn Fitted>,
}

impl Fit {
    /// The encoder's id.
    pub fn id(&self) -> &str {
        &self.id
    }

    /// E/π at unit normal `n`.
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        self.fitted.irradiance(n)
    }

    /// The stored coefficients: named values with units and the reconstruction they feed
    /// ([`Stored`]). Its stored scalars number [`Fit::stored_scalars`].
    pub fn stored(&self) -> Stored {
        self.fitted.stored()
    }

    /// Scalars the encoding stores per probe or texel (RGB counts 3).
    pub fn stored_scalars(&self) -> usize {
        self.encoder.stored_scalars()
    }

    /// Whether the encoder is defined only about a surface normal N.
    pub fn needs_surface_normal(&self) -> bool {
        self.encoder.needs_surface_normal()
    }

    /// Solver statistics and similar per-fit figures (the tables' `diagnostics` column).
    pub fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        self.fitted.diagnostics()
    }
}

/// An experiment (`docs/experiments.md`): maps, encoders with their settings, metrics, the
/// domain, orientations, effects and the output resolution; what `probelab run FILE` runs,
/// here run without writing anything.
pub struct Experiment {
    exp: PipelineExperiment,
}

impl Experiment {
    /// An experiment from the text of an experiment file. `name` is its name (the default of
    /// the file's `name` key) and names it in errors, which give the line of the fault as for a
    /// file (`NAME:LINE: …`).
    pub fn from_toml(name: &str, text: &str) -> Result<Experiment> {
        let mut exp = PipelineExperiment::parse(text, Path::new(name))?;
        exp.source = None;
        Ok(Experiment { exp })
    }

    /// An experiment file (`experiments/NAME.toml`); errors name the file and the line.
    pub fn load(path: impl AsRef<Path>) -> Result<Experiment> {
        Ok(Experiment { exp: PipelineExperiment::load(path.as_ref())? })
    }

    /// Its name.
    pub fn name(&self) -> &str {
        &self.exp.name
    }

    /// Runs it on its maps, found as [`Map::load`] finds them (`<root>/envmaps`, then
    /// `PROBELAB_ENVMAPS`), and returns the rows of its table (`docs/tables.md`: one per map,
    /// case, encoder and metric). A map that is not found is an error naming it and the
    /// folders searched.
    pub fn run(&self, root: impl AsRef<Path>) -> Result<Vec<Row>> {
        let search = SearchPath::from_env(root.as_ref().join("envmaps"));
        let report = crate::pipeline::runner::run(
            &self.exp,
            &search,
            &Default::default(),
            &crate::pipeline::reuse::ReferenceCache::new(None),
        )?;
        if !report.missing.is_empty() {
            bail!(
                "experiment {}: map(s) not found: {}",
                self.exp.name,
                search.missing_maps(&report.missing, &report.missing_why)
            );
        }
        Ok(report.rows)
    }
}

/// The id of every registered encoder, in the order tables list them (`probelab encoders`).
pub fn encoder_ids() -> Vec<&'static str> {
    crate::encoders::REGISTRY.iter().map(|k| k.id).collect()
}

/// Whether the encoder `id` needs a surface normal ([`Surface::Normal`]) to be fitted; an
/// unknown id is an error listing the valid ones.
pub fn needs_surface_normal(id: &str) -> Result<bool> {
    Ok(crate::encoders::build(id, None, toml::Table::new())?.encoder.needs_surface_normal())
}
