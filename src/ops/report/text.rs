//! What `report` says on stderr (and `reproduce` on stdout, with its summary): the report written,
//! the pictures drawn, the results viewer's files rewritten, the sheets kept for want of maps, and
//! each map found in another file.

use crate::report::Generated;

/// The lines (each ending in a newline).
pub fn lines(g: &Generated) -> String {
    let mut s = format!("wrote {} ({} picture(s) drawn)\n", g.report.display(), g.pictures);
    s += &format!("results viewer: {} file(s) of site/ rewritten (unchanged files are left alone)\n", g.site_rewritten);
    if !g.kept.is_empty() {
        s += &format!(
            "sheets not redrawn, the committed ones kept ({} map(s) not on the search path): {}\n",
            g.missing.len(),
            g.kept.join(", ")
        );
    }
    for m in &g.mismatches {
        s += &format!("warning: {m}\n");
    }
    s
}
