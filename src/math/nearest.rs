//! "Did you mean": the nearest of some known names to a name that was not found, by the
//! normalised Damerau–Levenshtein similarity of the `strsim` crate. Used for map names, encoder
//! ids and experiment names, so a typo is answered with the name meant. Names are compared
//! without regard to case (`SH2` is one edit from nothing but `sh2`), since every name probelab
//! knows is matched exactly and a difference of case alone is the commonest slip.

/// The least similarity (0 to 1) a name must have to be suggested.
const MIN_SIMILARITY: f64 = 0.7;

/// The known name most similar to `name` (the first of equals, in the order given), when it
/// is similar enough to be a typo of it: a similarity of at least 0.7 between the lower-cased
/// names, or `name` a prefix of it (an unfinished name). `None` when nothing is close, or when
/// `name` is itself known.
pub fn nearest<'a, I, S>(name: &str, known: I) -> Option<String>
where
    I: IntoIterator<Item = &'a S>,
    S: AsRef<str> + 'a + ?Sized,
{
    let mut best: Option<(f64, &str)> = None;
    let lower = name.to_lowercase();
    for k in known {
        let k = k.as_ref();
        if k == name {
            return None;
        }
        let mut score = strsim::normalized_damerau_levenshtein(&lower, &k.to_lowercase());
        if name.len() >= 3 && k.to_lowercase().starts_with(&lower) {
            score = score.max(MIN_SIMILARITY);
        }
        if score >= MIN_SIMILARITY && best.is_none_or(|(b, _)| score > b) {
            best = Some((score, k));
        }
    }
    best.map(|(_, k)| k.to_string())
}

/// `" (did you mean 'x'?)"` for the nearest known name, or an empty string.
pub fn did_you_mean<'a, I, S>(name: &str, known: I) -> String
where
    I: IntoIterator<Item = &'a S>,
    S: AsRef<str> + 'a + ?Sized,
{
    nearest(name, known).map(|k| format!(" (did you mean '{k}'?)")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_typo_gets_the_nearest_name_and_a_stranger_gets_none() {
        let maps = ["gen_sun_sky", "gen_sky_sun", "gen_cone", "ennis_256x128"];
        // One letter dropped: gen_sky_sun is one edit away, gen_sun_sky four.
        assert_eq!(nearest("gen_sky_su", &maps).as_deref(), Some("gen_sky_sun"));
        // Two letters swapped is one edit (Damerau).
        assert_eq!(nearest("gen_cnoe", &maps).as_deref(), Some("gen_cone"));
        // An unfinished name is a prefix.
        assert_eq!(nearest("ennis", &maps).as_deref(), Some("ennis_256x128"));
        assert_eq!(nearest("landscape", &maps), None);
        // A known name needs no suggestion.
        assert_eq!(nearest("gen_cone", &maps), None);
        let ids = ["sh0", "sh1", "sh2", "zh3_hallucinated"];
        assert_eq!(nearest("sh22", &ids).as_deref(), Some("sh2"));
        assert_eq!(did_you_mean("sh22", &ids), " (did you mean 'sh2'?)");
        assert_eq!(did_you_mean("xyz", &ids), "");
        // A difference of case alone is the nearest of all.
        assert_eq!(nearest("SH2", &ids).as_deref(), Some("sh2"));
        assert_eq!(nearest("Gen_Cone", &maps).as_deref(), Some("gen_cone"));
        assert_eq!(nearest("ENNIS", &maps).as_deref(), Some("ennis_256x128"));
    }
}
