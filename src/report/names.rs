//! The names of the pages and files the report writes and links: a result folder's page,
//! PROVENANCE.md, the claims engine's CLAIMS.csv, a link from REPORT.md into a folder, and file
//! names made safe.

/// A result folder's page, `results/<name>/README.md`.
pub const PAGE: &str = "README.md";

/// How the run was made in full (tables' provenance, settings, maps with sha256).
pub const PROVENANCE_PAGE: &str = "PROVENANCE.md";

/// The claims engine's table, relative to the results folder.
pub const CLAIMS_CSV: &str = "CLAIMS.csv";

/// A file name made of `[A-Za-z0-9._-]`.
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') { c } else { '_' }).collect()
}

/// Link text from REPORT.md (in `out`) to `name/file`.
pub(super) fn rel(name: &str, file: &str) -> String {
    format!("{name}/{file}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_are_safe() {
        assert_eq!(file_safe("a b/c.png"), "a_b_c.png");
    }
}
