//! One look per encoder, everywhere: the colour and marker every chart, sweep, strip and the
//! HTML viewer give an encoder id, and nothing else.
//!
//! The hue is the encoder's family ([`Family`], which each encoder declares: AHD and HHD are
//! families of their own, so they differ in hue). Within a family, the members are numbered in
//! registry order ([`crate::encoders::REGISTRY`]), and member `i` takes lightness level `i % 3`
//! and marker `i % 8`: the pairs are distinct for the first [`SLOTS`] = 24 members, so no two
//! registered ids of one family look alike (tested). Every colour has a WCAG 2 contrast ratio of
//! at least [`CONTRAST_FLOOR`] = 3:1 against white (the WCAG floor for graphics), tested.
//!
//! An id the registry does not have is an experiment's variant, named after its kind with a
//! suffix (`sh2_of_visible`, `hhd_search_hemi+bounce`): its family is that of the registered id
//! sharing the most leading words (split at `_` and `+`), and its slot one of the family's
//! slots no registered member takes, chosen by a hash of the whole name, so it looks the same
//! in every chart. An id that shares no word with a registered one is of [`Family::Other`]
//! (grey).

use crate::encoders::encoder::Family;
use crate::encoders::{family_of, REGISTRY};

/// A marker shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Marker {
    Circle,
    Square,
    TriangleUp,
    TriangleDown,
    Diamond,
    Cross,
    Plus,
    Star,
}

impl Marker {
    /// Every marker, in the order members take them.
    pub(crate) const ALL: [Marker; 8] = [
        Marker::Circle,
        Marker::Square,
        Marker::TriangleUp,
        Marker::TriangleDown,
        Marker::Diamond,
        Marker::Cross,
        Marker::Plus,
        Marker::Star,
    ];

    /// The marker's name ("circle", "square", "triangle-up", …), as the HTML viewer reads it.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Marker::Circle => "circle",
            Marker::Square => "square",
            Marker::TriangleUp => "triangle-up",
            Marker::TriangleDown => "triangle-down",
            Marker::Diamond => "diamond",
            Marker::Cross => "cross",
            Marker::Plus => "plus",
            Marker::Star => "star",
        }
    }
}

/// How an encoder is drawn: its family, colour and marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct EncoderStyle {
    /// The family (the hue).
    pub family: Family,
    /// The colour, sRGB.
    pub rgb: [u8; 3],
    /// The marker.
    pub marker: Marker,
}

impl EncoderStyle {
    /// The colour as `#rrggbb`.
    pub(crate) fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.rgb[0], self.rgb[1], self.rgb[2])
    }
}

/// The distinct (lightness, marker) pairs of one family: lcm(3, 8).
pub(crate) const SLOTS: usize = 24;

/// The least WCAG 2 contrast ratio of every colour against white.
pub(crate) const CONTRAST_FLOOR: f64 = 3.0;

/// Per family (in [`Family::ALL`] order), the hue at three lightness levels: HSL colours of
/// the stated hue and saturation whose relative luminance is 0.06, 0.13 and 0.235 (contrast
/// against white 9.6, 5.9 and 3.7).
const LEVELS: [[[u8; 3]; 3]; 11] = [
    // SH: hue 215°, saturation 0.75 (blue).
    [[19, 67, 135], [28, 98, 196], [64, 133, 228]],
    // ZH3: hue 28°, saturation 0.95 (orange).
    [[111, 53, 3], [161, 77, 4], [211, 102, 5]],
    // Geomerics L1: hue 125°, saturation 0.60 (green).
    [[20, 80, 25], [29, 116, 36], [38, 153, 48]],
    // Probe occlusion: hue 165°, saturation 0.80 (teal).
    [[9, 79, 62], [13, 114, 89], [17, 150, 117]],
    // AHD: hue 275°, saturation 0.55 (purple).
    [[98, 40, 139], [141, 60, 198], [168, 106, 212]],
    // HHD: hue 352°, saturation 0.75 (red).
    [[137, 20, 35], [197, 28, 51], [230, 80, 100]],
    // Ambient cube: hue 22°, saturation 0.45 (brown).
    [[98, 60, 37], [143, 87, 54], [186, 116, 74]],
    // Ambient dice: hue 320°, saturation 0.65 (magenta).
    [[125, 27, 93], [181, 38, 134], [218, 79, 172]],
    // Spherical Gaussians: hue 58°, saturation 0.80 (olive).
    [[74, 71, 8], [107, 103, 12], [141, 136, 16]],
    // H-basis: hue 192°, saturation 0.85 (cyan).
    [[7, 75, 92], [11, 110, 135], [14, 144, 177]],
    // Other: grey.
    [[69, 69, 69], [100, 100, 100], [133, 133, 133]],
];

/// The style of slot `slot` of `family`.
fn slot_style(family: Family, slot: usize) -> EncoderStyle {
    let levels = &LEVELS[family.index().min(LEVELS.len() - 1)];
    let slot = slot % SLOTS;
    EncoderStyle { family, rgb: levels[slot % levels.len()], marker: Marker::ALL[slot % Marker::ALL.len()] }
}

/// Every registered encoder id with its family, in registry order.
fn registered() -> Vec<(&'static str, Family)> {
    REGISTRY.iter().map(|k| (k.id, family_of(k.id).unwrap_or(Family::Other))).collect()
}

/// Every registered encoder id with its style, in registry order.
pub(crate) fn all_registered() -> Vec<(String, EncoderStyle)> {
    let reg = registered();
    let mut taken = [0usize; Family::ALL.len()];
    reg.into_iter()
        .map(|(id, f)| {
            let slot = taken[f.index()];
            taken[f.index()] += 1;
            (id.to_string(), slot_style(f, slot))
        })
        .collect()
}

/// The style of any id in any table: a registered id's own, or an experiment variant's (see
/// the module doc).
pub(crate) fn style_of(encoder_id: &str) -> EncoderStyle {
    if let Some((_, s)) = all_registered().into_iter().find(|(id, _)| id == encoder_id) {
        return s;
    }
    let reg = registered();
    let family = kind_family(encoder_id, &reg);
    let members = reg.iter().filter(|(_, f)| *f == family).count().min(SLOTS - 1);
    let free = SLOTS - members;
    slot_style(family, members + (fnv1a(encoder_id) % free as u64) as usize)
}

/// The family of the registered id that shares the most leading words with `name` (the first
/// such in registry order), or [`Family::Other`] when none shares one.
fn kind_family(name: &str, reg: &[(&'static str, Family)]) -> Family {
    let words = |s: &str| s.split(['_', '+']).map(str::to_string).collect::<Vec<_>>();
    let mine = words(name);
    let mut best = (0, Family::Other);
    for (id, f) in reg {
        let shared = mine.iter().zip(words(id)).take_while(|(a, b)| *a == b).count();
        if shared > best.0 {
            best = (shared, *f);
        }
    }
    best.1
}

/// FNV-1a, 64-bit: a hash that is the same on every machine and in every release.
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// WCAG 2 relative luminance of an sRGB colour.
    fn relative_luminance(rgb: [u8; 3]) -> f64 {
        let lin = |c: u8| {
            let c = f64::from(c) / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        0.2126 * lin(rgb[0]) + 0.7152 * lin(rgb[1]) + 0.0722 * lin(rgb[2])
    }

    /// WCAG 2 contrast ratio against white (luminance 1).
    fn contrast_on_white(rgb: [u8; 3]) -> f64 {
        1.05 / (relative_luminance(rgb) + 0.05)
    }

    #[test]
    fn wcag_contrast_matches_known_values() {
        // Black on white is 21:1; white on white 1:1; #767676 is the well-known 4.54:1 grey.
        assert!((contrast_on_white([0, 0, 0]) - 21.0).abs() < 1e-9);
        assert!((contrast_on_white([255, 255, 255]) - 1.0).abs() < 1e-9);
        assert!((contrast_on_white([0x76, 0x76, 0x76]) - 4.54).abs() < 0.01);
    }

    /// Every registered encoder is drawn: its family's hue, no two ids of one family alike, and
    /// every colour at least 3:1 against white.
    #[test]
    fn every_registered_encoder_has_its_own_visible_style() {
        let all = all_registered();
        assert_eq!(all.len(), REGISTRY.len());
        let mut seen = HashSet::new();
        for (id, s) in &all {
            assert_eq!(Some(s.family), family_of(id), "{id}");
            assert!(seen.insert((s.family, s.rgb, s.marker)), "{id} shares its style within {:?}", s.family);
            let c = contrast_on_white(s.rgb);
            assert!(c >= CONTRAST_FLOOR, "{id}: {} has contrast {c:.2} < {CONTRAST_FLOOR} on white", s.hex());
            assert_eq!(style_of(id), *s, "{id}");
        }
    }

    #[test]
    fn every_colour_of_every_family_meets_the_floor_and_families_differ_in_hue() {
        for (f, levels) in Family::ALL.iter().zip(LEVELS) {
            for rgb in levels {
                assert!(contrast_on_white(rgb) >= CONTRAST_FLOOR, "{f:?} {rgb:?}");
            }
        }
        let mids: HashSet<[u8; 3]> = LEVELS.iter().map(|l| l[1]).collect();
        assert_eq!(mids.len(), LEVELS.len());
        assert_eq!(LEVELS.len(), Family::ALL.len());
        let ahd = slot_style(Family::Ahd, 0).rgb;
        assert!((0..SLOTS).all(|i| slot_style(Family::Hhd, i).rgb != ahd));
    }

    #[test]
    fn slots_are_distinct_within_a_family() {
        let pairs: HashSet<([u8; 3], Marker)> =
            (0..SLOTS).map(|i| slot_style(Family::Sh, i)).map(|s| (s.rgb, s.marker)).collect();
        assert_eq!(pairs.len(), SLOTS);
        assert_eq!(Marker::ALL.iter().map(|m| m.name()).collect::<HashSet<_>>().len(), 8);
        assert_eq!(slot_style(Family::Zh3, 0).hex(), "#6f3503");
    }

    /// A variant takes its kind's family, a slot no registered member of it takes, and the
    /// same style on every call; a name sharing no word with a registered id is grey.
    #[test]
    fn variants_take_their_kinds_family_and_a_free_slot() {
        let all = all_registered();
        for (variant, kind) in [
            (format!("{}_of_visible", REGISTRY[1].id), REGISTRY[1].id),
            (format!("{}+bounce", REGISTRY[2].id), REGISTRY[2].id),
        ] {
            let s = style_of(&variant);
            assert_eq!(Some(s.family), family_of(kind));
            assert!(all.iter().all(|(_, r)| *r != s), "{variant} looks like a registered encoder");
            assert_eq!(style_of(&variant), s);
        }
        assert_eq!(style_of("no such words").family, Family::Other);
    }

    /// Every experiment's encoders: each takes the family its experiment declares, and no two
    /// of one experiment look alike (a variant's hashed slot could meet another's).
    #[test]
    fn every_experiments_encoders_look_apart_and_keep_their_family() {
        use crate::pipeline::experiment::{list_experiments, Experiment};
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        for path in list_experiments(&dir).unwrap() {
            let Ok(e) = Experiment::load(&path) else { continue };
            let mut seen = HashSet::new();
            for n in &e.encoders {
                let s = style_of(&n.name);
                assert_eq!(s.family, n.encoder.family(), "{}: {}", path.display(), n.name);
                assert!(seen.insert(s), "{}: {} shares its style", path.display(), n.name);
            }
        }
    }
}
