//! Maps and constructed scenes, kept apart. A constructed scene (`constructed_*`, the claims
//! measurements' own; `gen_*`, the generated scenes of `reference::scenes`) is made to show
//! one effect, so it is never pooled with photographs: the set `all` holds every map of a
//! table that is not a constructed scene, and the set `scenes` holds only the constructed
//! scenes. A declared map set (`paper`) may not name a scene.

/// The built-in set of every map of a table that is not a constructed scene.
pub const ALL: &str = "all";

/// The built-in set of the constructed scenes of a table.
pub const SCENES: &str = "scenes";

/// The name prefixes of constructed scenes.
const CONSTRUCTED: [&str; 2] = ["constructed_", "gen_"];

/// Whether a map name is a constructed scene rather than a photograph.
pub fn is_constructed(map: &str) -> bool {
    CONSTRUCTED.iter().any(|p| map.starts_with(p))
}

/// The maps a set judges.
#[derive(Clone, Copy)]
pub(crate) enum Population<'a> {
    /// `all`: every map that is not a constructed scene.
    Maps,
    /// `scenes`: the constructed scenes only.
    Scenes,
    /// A declared set: exactly these maps.
    Named(&'a [String]),
}

impl<'a> Population<'a> {
    /// The population of set `set`, whose declared maps (for a named set) are `named`.
    pub(crate) fn of(set: &str, named: Option<&'a [String]>) -> Population<'a> {
        match set {
            ALL => Population::Maps,
            SCENES => Population::Scenes,
            _ => Population::Named(named.unwrap_or(&[])),
        }
    }

    /// Whether `map` belongs to the set.
    pub(crate) fn holds(&self, map: &str) -> bool {
        match self {
            Population::Maps => !is_constructed(map),
            Population::Scenes => is_constructed(map),
            Population::Named(m) => m.iter().any(|x| x == map),
        }
    }

    /// The declared maps of a named set (None for the built-in sets).
    pub(crate) fn named(&self) -> Option<&'a [String]> {
        match self {
            Population::Named(m) => Some(m),
            _ => None,
        }
    }
}

/// What one member of set `set` is called: `constructed scene` in `scenes`, `map` otherwise.
pub fn noun(set: &str) -> &'static str {
    if set == SCENES {
        "constructed scene"
    } else {
        "map"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scene/map split: `all` never holds a constructed scene, `scenes` only them.
    #[test]
    fn constructed_scenes_are_never_maps() {
        for scene in ["constructed_two_colours", "gen_tilted_light"] {
            assert!(is_constructed(scene));
            assert!(!Population::Maps.holds(scene));
            assert!(Population::Scenes.holds(scene));
        }
        for map in ["ennis_256x128", "wells_probulator", "pmndrs_night_256x128", "generator_room"] {
            assert!(!is_constructed(map));
            assert!(Population::Maps.holds(map));
            assert!(!Population::Scenes.holds(map));
        }
        let paper = ["ennis_256x128".to_string()];
        assert!(Population::of("paper", Some(&paper)).holds("ennis_256x128"));
        assert!(!Population::of("paper", Some(&paper)).holds("grace_256x128"));
        assert_eq!(noun(SCENES), "constructed scene");
        assert_eq!(noun(ALL), "map");
    }
}
