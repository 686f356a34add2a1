//! Names that become file names stay in their folder. A table, experiment, claims file or map
//! name is joined under a folder (`results/claims/measures/<name>.csv`, `<dir>/<name>.exr`),
//! so it must be a plain identifier: ASCII letters, digits, `_`, `.` and `-`, not starting with
//! a dot (no `..`, no hidden or temporary file) and with no separator. `measure:../../x` in a
//! claims file once read a table outside `results/claims/measures/`.

/// Why `name` is not a plain identifier, or `None` when it is.
pub fn fault(name: &str) -> Option<String> {
    if name.is_empty() {
        return Some("is empty".into());
    }
    if name.starts_with('.') {
        return Some("starts with a dot".into());
    }
    if let Some(c) = name.chars().find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'))) {
        let what = if matches!(c, '/' | '\\') { "a path separator".to_string() } else { format!("{c:?}") };
        return Some(format!("holds {what}"));
    }
    None
}

/// Whether `name` is a plain identifier (see the module doc).
pub fn is_plain(name: &str) -> bool {
    fault(name).is_none()
}

/// `Ok` for a plain identifier, else the message `'NAME' is not a plain name (…)` for the
/// caller to place (file, line, key).
pub fn check(name: &str) -> Result<(), String> {
    match fault(name) {
        None => Ok(()),
        Some(why) => Err(format!(
            "'{name}' is not a plain name ({why}): use letters, digits, '_', '.' or '-', not starting with a dot"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_plain_identifiers_pass() {
        for ok in ["zh3", "grace-new_256x128", "probe.v2", "a", "A1-b_c.d"] {
            assert!(is_plain(ok), "{ok}");
        }
        for bad in ["", ".", "..", "../x", "../../x", "a/b", "a\\b", ".hidden", "a b", "/abs", "é", "a:b", "x\n"] {
            assert!(!is_plain(bad), "{bad:?}");
            assert!(check(bad).unwrap_err().contains("not a plain name"), "{bad:?}");
        }
        assert!(check("a/b").unwrap_err().contains("a path separator"));
    }
}
