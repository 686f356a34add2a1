//! Validating an experiment file: every key checked in the file's order (so the first error is
//! the one reported), the encoders built through the registry.

use super::effect::parse_effect;
use super::file::{EncoderEntry, ExperimentFile};
use super::model::{DomainKind, Effect, Experiment, MAX_CASES};
use crate::encoders::{self, NamedEncoder};
use crate::reference::domain::{expand_orientations, Orientation};
use crate::reference::exact::DEFAULT_POLAR_NODES;
use crate::reference::metrics::Metric;
use anyhow::{bail, Context, Result};

impl Experiment {
    /// Validates a parsed file; `default_name` is the name when the file gives none. The
    /// checks run in the order of the file's keys, so the first error is the one reported.
    pub fn from_file(f: ExperimentFile, default_name: &str) -> Result<Self> {
        let name = check_name(f.name.unwrap_or_else(|| default_name.to_string()))?;
        check_maps(&f.maps)?;
        let built = build_encoders(f.encoders)?;
        let metrics = if f.metrics.is_empty() {
            vec![Metric::Exact]
        } else {
            f.metrics.iter().map(|m| Metric::parse(m).context("metrics")).collect::<Result<_>>()?
        };
        if let Some(i) = (1..metrics.len()).find(|&i| metrics[..i].contains(&metrics[i])) {
            bail!("metrics: '{}' appears twice", crate::math::echo::value(&f.metrics[i]));
        }
        let domain = match f.domain.as_deref().unwrap_or("sphere") {
            "sphere" => DomainKind::Sphere,
            "hemisphere" => DomainKind::Hemisphere,
            d => bail!("domain '{d}': expected sphere or hemisphere", d = crate::math::echo::value(d)),
        };
        check_surface_encoders(domain, &built)?;
        let mut orientations = Vec::new();
        for o in &f.orientations {
            orientations.extend(expand_orientations(o).context("orientations")?);
        }
        let mut effects = Vec::new();
        for e in f.effects {
            effects.push(parse_effect(e)?);
        }
        check_cases(orientations.len(), &effects)?;
        check_normals(domain, &orientations, &effects, &metrics)?;
        let resolution = f.resolution.map(|[w, h]| (w, h)).unwrap_or((256, 128));
        if resolution.0 != 2 * resolution.1 || resolution.1 < 2 || resolution.1 > 4096 {
            bail!("resolution {:?}: expected [2H, H] with 2 <= H <= 4096", resolution);
        }
        let polar_nodes = f.polar_nodes.unwrap_or(DEFAULT_POLAR_NODES);
        if !(1..=16).contains(&polar_nodes) {
            bail!("polar_nodes {polar_nodes}: expected 1..=16");
        }
        let names: Vec<String> = built.iter().map(|e| e.name.clone()).collect();
        let summary = f.summary.map(|s| crate::pipeline::summary::summary_baseline(s, &names)).transpose()?;
        if let Some(sheets) = &f.sheets {
            check_sheets(sheets, &f.maps)?;
        }
        Ok(Experiment {
            name,
            description: f.description,
            source: None,
            maps: f.maps,
            encoders: built,
            metrics,
            domain,
            orientations,
            effects,
            resolution,
            polar_nodes,
            ci: f.ci.unwrap_or(true),
            summary,
            sheets: f.sheets,
        })
    }
}

/// The longest experiment name, in characters. The name names a folder under `results/` and
/// files in the report (with a map's name beside it), and a file name holds at most 255 bytes
/// on common file systems; a 300-character name once ran the whole experiment, then failed at
/// the write.
pub const MAX_NAME_CHARS: usize = 100;

/// The experiment's name, if it can name a folder under `results/`.
fn check_name(name: String) -> Result<String> {
    if name.chars().count() > MAX_NAME_CHARS {
        bail!(
            "name '{}' is {} characters long: at most {MAX_NAME_CHARS} (it names a folder and files under results/)",
            crate::math::echo::value(&name),
            name.chars().count()
        );
    }
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        bail!(
            "name '{name}': use letters, digits, '_' or '-' (it names a folder under results/)",
            name = crate::math::echo::value(&name.to_string())
        );
    }
    Ok(name)
}

/// Refuses an empty map list and a map listed twice.
fn check_maps(maps: &[String]) -> Result<()> {
    if maps.is_empty() {
        bail!("maps: list at least one map");
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(m) = maps.iter().find(|m| !seen.insert(m.as_str())) {
        bail!("maps: '{m}' appears twice", m = crate::math::echo::value(&m.to_string()));
    }
    Ok(())
}

/// Builds the `encoders` entries through the registry, in order; refuses an empty list and two
/// encoders of one name.
fn build_encoders(entries: Vec<EncoderEntry>) -> Result<Vec<NamedEncoder>> {
    if entries.is_empty() {
        bail!("encoders: list at least one encoder (valid: {})", encoders::known_ids());
    }
    let built = entries.into_iter().map(build_encoder).collect::<Result<Vec<_>>>()?;
    for (i, e) in built.iter().enumerate() {
        if built[..i].iter().any(|o| o.name == e.name) {
            bail!("encoders: '{}' appears twice; give variants distinct names with name = \"…\"", e.name);
        }
    }
    Ok(built)
}

/// One `encoders` entry: a kind with its default settings, or a table of `kind`, an optional
/// `name` and the encoder's settings.
fn build_encoder(e: EncoderEntry) -> Result<NamedEncoder> {
    match e {
        EncoderEntry::Kind(k) => encoders::build(&k, None, toml::Table::new()),
        EncoderEntry::Table(mut t) => {
            let kind = match t.remove("kind") {
                Some(toml::Value::String(k)) => k,
                _ => bail!("encoders: a table entry needs kind = \"<encoder>\" (valid: {})", encoders::known_ids()),
            };
            let name = match t.remove("name") {
                Some(toml::Value::String(n)) => Some(n),
                None => None,
                Some(v) => bail!("encoders: name must be a string, got {v}"),
            };
            encoders::build(&kind, name.as_deref(), t)
        }
    }
}

/// Refuses a `self_bounce` effect without the hemisphere effect or listed twice, and more than
/// [`MAX_CASES`] cases (the `n_orientations` normals, at least one, times every effect's
/// parameter combinations).
fn check_cases(n_orientations: usize, effects: &[Effect]) -> Result<()> {
    let variants = effects.iter().try_fold(n_orientations.max(1), |n: usize, e| match e {
        Effect::Hemisphere => Some(n),
        Effect::Cone { cos_alpha, tilt_deg } => n.checked_mul(cos_alpha.len())?.checked_mul(tilt_deg.len()),
        Effect::SelfBounce { albedo } => n.checked_mul(albedo.len()),
    });
    if effects.iter().any(|e| matches!(e, Effect::SelfBounce { .. })) {
        if !effects.contains(&Effect::Hemisphere) {
            bail!(
                "effects: 'self_bounce' needs the hemisphere effect (the bounce is the light of the surface \
                 below the horizon); add \"hemisphere\" to effects"
            );
        }
        if effects.iter().filter(|e| matches!(e, Effect::SelfBounce { .. })).count() > 1 {
            bail!("effects: 'self_bounce' appears twice; list every albedo in one entry");
        }
    }
    match variants {
        Some(n) if n <= MAX_CASES => Ok(()),
        _ => bail!(
            "orientations: the orientations and effect parameters make more than {MAX_CASES} cases (one per \
             normal and parameter combination); split the experiment"
        ),
    }
}

/// Surface normals are given exactly when something uses them (a hemisphere domain or an
/// effect); the `probulator` metric, which scores the whole sphere, only on the sphere domain.
fn check_normals(
    domain: DomainKind,
    orientations: &[Orientation],
    effects: &[Effect],
    metrics: &[Metric],
) -> Result<()> {
    let needs_normal = domain == DomainKind::Hemisphere || !effects.is_empty();
    if needs_normal && orientations.is_empty() {
        bail!("orientations: a hemisphere domain or an effect needs surface normals (e.g. orientations = [\"up\"])");
    }
    if !needs_normal && !orientations.is_empty() {
        bail!("orientations: only a hemisphere domain or an effect uses surface normals; remove them or set domain = \"hemisphere\"");
    }
    if domain == DomainKind::Hemisphere && metrics.contains(&Metric::Probulator) {
        bail!("metrics: 'probulator' scores the whole sphere at 256x128; it cannot be used with a hemisphere domain");
    }
    Ok(())
}

/// Refuses a `sheets` entry that is not one of the experiment's maps, or listed twice.
fn check_sheets(sheets: &[String], maps: &[String]) -> Result<()> {
    if let Some(m) = sheets.iter().find(|m| !maps.contains(m)) {
        bail!("sheets: '{m}' is not one of the experiment's maps", m = crate::math::echo::value(&m.to_string()));
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(m) = sheets.iter().find(|m| !seen.insert(m.as_str())) {
        bail!("sheets: '{m}' appears twice", m = crate::math::echo::value(&m.to_string()));
    }
    Ok(())
}

/// Refuses an encoder defined only on the hemisphere about a surface normal
/// ([`crate::encoders::encoder::Encoder::needs_surface_normal`]) unless the domain
/// is `hemisphere`: on the sphere there is no N, and it must not be scored where it is not
/// defined. The error names the encoder (and, through [`Experiment::parse`], the file and line).
pub fn check_surface_encoders(domain: DomainKind, encoders: &[NamedEncoder]) -> Result<()> {
    if domain == DomainKind::Hemisphere {
        return Ok(());
    }
    if let Some(e) = encoders.iter().find(|e| e.encoder.needs_surface_normal()) {
        bail!(
            "encoders: {}; this experiment's domain is the sphere: use domain = \"hemisphere\" with orientations \
             (and the hemisphere effect), or remove it",
            crate::encoders::encoder::surface_normal_refusal(&e.name)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Experiment> {
        Experiment::from_file(toml::from_str(s)?, "t")
    }

    #[test]
    fn minimal_file_gets_defaults() {
        let e = parse("maps = ['a']\nencoders = ['sh1', 'sh2']").unwrap();
        assert_eq!(e.name, "t");
        assert_eq!(e.metrics, vec![Metric::Exact]);
        assert_eq!(e.resolution, (256, 128));
        assert_eq!(e.encoders.len(), 2);
    }

    #[test]
    fn errors_are_specific() {
        let e = |s: &str| format!("{:#}", parse(s).err().unwrap());
        assert!(e("maps=['a']\nencoders=['shx']").contains("valid encoders"));
        assert!(e("maps=['a']\nencoders=['sh1']\nbogus=1").contains("bogus"));
        assert!(e("maps=['a']\nencoders=['sh1']\neffects=['fog']").contains("unknown effect 'fog'"));
        assert!(e("maps=['a']\nencoders=['sh1']\ndomain='hemisphere'").contains("orientations"));
        assert!(e("maps=['a']\nencoders=['sh1','sh1']").contains("twice"));
        assert!(e("maps=['a']\nencoders=['sh1']\nmetrics=['exact','exact']").contains("metrics: 'exact' appears twice"));
        let long = format!("name='{}'\nmaps=['a']\nencoders=['sh1']", "n".repeat(101));
        assert!(e(&long).contains("is 101 characters long: at most 100"), "{}", e(&long));
        let ok = format!("name='{}'\nmaps=['a']\nencoders=['sh1']", "n".repeat(100));
        assert!(parse(&ok).is_ok());
        assert!(e("maps=['a']\nencoders=['sh1']\nmetrics=['l1']").contains("unknown metric"));
    }

    /// The H-basis needs N: refused on the sphere (and on a sphere with effects about N), with
    /// the encoder's name and what to do; accepted on the hemisphere domain.
    #[test]
    fn surface_encoders_need_the_hemisphere_domain() {
        let e = |s: &str| format!("{:#}", parse(s).err().expect("must fail"));
        let msg = e("maps = ['a']\nencoders = [{ kind = 'hbasis6', name = 'h6' }]\n");
        assert!(msg.contains("'h6' needs a surface normal N: it is defined only on the hemisphere"), "{msg}");
        assert!(msg.contains("domain = \"hemisphere\""), "{msg}");
        let msg = e("maps = ['a']\nencoders = ['hbasis4']\norientations = ['up']\neffects = ['hemisphere']\n");
        assert!(msg.contains("'hbasis4'"), "{msg}");
        let ok = parse("maps = ['a']\nencoders = ['hbasis4']\ndomain = 'hemisphere'\norientations = ['up']\n");
        assert!(ok.is_ok());
    }
}
