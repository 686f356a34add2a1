//! The site's pages, script and style sheet, compiled into the binary from `assets/` and written
//! by the report beside the data (the vendored chart library sits committed in
//! `results/site/vendor/` with its licence; the report never writes it).

/// Every compiled-in file: its path under the site folder and its text.
pub(super) const ASSETS: [(&str, &str); 9] = [
    ("index.html", include_str!("assets/index.html")),
    ("claims.html", include_str!("assets/claims.html")),
    ("landscape.html", include_str!("assets/landscape.html")),
    ("site.css", include_str!("assets/site.css")),
    ("common.js", include_str!("assets/common.js")),
    ("explorer.js", include_str!("assets/explorer.js")),
    ("views.js", include_str!("assets/views.js")),
    ("claims.js", include_str!("assets/claims.js")),
    ("landscape.js", include_str!("assets/landscape.js")),
];
