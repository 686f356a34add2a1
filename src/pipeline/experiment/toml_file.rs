//! Reading a TOML file of the project (an experiment, sweep, claims or report-plan file):
//! nesting refused past a limit before the parser sees it, syntax and type errors as
//! `FILE:LINE:COL` with the line quoted.

use super::lines::{line_col, quote_line};
use anyhow::{bail, Result};
use std::path::Path;

/// The deepest nesting a TOML file may have: tables (headers and dotted keys), arrays and
/// inline tables together. Deeper files are refused with their line before the parser sees them
/// (whose own limit would end in "recursion limit", or a deep stack).
pub const MAX_TOML_DEPTH: usize = 32;

/// Parses the TOML `text` of the file at `path` (an experiment, sweep, claims or report-plan
/// file): refused with `FILE:LINE:` when it nests deeper than [`MAX_TOML_DEPTH`]; a syntax or
/// type error reads `FILE:LINE:COL: message` and quotes the line (cut to 120 characters).
pub fn parse_toml<T: serde::de::DeserializeOwned>(text: &str, path: &Path) -> Result<T> {
    if let Some(line) = too_deep(text) {
        bail!(
            "{}:{line}: nested deeper than {MAX_TOML_DEPTH} levels (tables, dotted keys, arrays and inline tables \
             together); refusing to read it{}",
            path.display(),
            quote_line(text, line)
        );
    }
    toml::from_str(text).map_err(|e| {
        let at = e.span().map(|s| line_col(text, s.start));
        let msg = crate::math::echo::quoted_values(e.message().trim_end());
        match at {
            Some((line, col)) => anyhow::anyhow!("{}:{line}:{col}: {msg}{}", path.display(), quote_line(text, line)),
            None => anyhow::anyhow!("{}: {msg}", path.display()),
        }
    })
}

/// The first line where `text` nests deeper than [`MAX_TOML_DEPTH`], counting the current
/// table's header segments, open arrays and inline tables, and a key's dotted segments. Strings
/// and comments are skipped; a scan, never a parse, so it cannot itself recurse.
fn too_deep(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let (mut line, mut i) = (1usize, 0usize);
    let mut open: Vec<u8> = Vec::new(); // the open brackets: b'[' (array or header) or b'{'
    let (mut table, mut dots, mut in_key, mut header) = (0usize, 0usize, true, false);
    while i < b.len() {
        let c = b[i];
        match c {
            b'\n' => {
                line += 1;
                if open.is_empty() {
                    (dots, in_key) = (0, true);
                }
            }
            b'#' => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'"' | b'\'' => {
                i = skip_string(b, i, &mut line);
                continue;
            }
            b'[' if open.is_empty() && in_key => (header, dots, table) = (true, 0, 0),
            b'[' | b'{' => (dots, in_key) = (0, c == b'{'),
            b'.' if in_key || header => dots += 1,
            b'=' => in_key = false,
            b',' => in_key = open.last() == Some(&b'{'),
            _ => {}
        }
        if c == b'[' || c == b'{' {
            open.push(c);
        } else if c == b']' || c == b'}' {
            open.pop();
            if header && open.is_empty() && b.get(i + 1) != Some(&b']') {
                (header, table, in_key) = (false, dots + 1, true);
            }
        }
        let key = if in_key || header { dots + 1 } else { 0 };
        if table + open.len() + key > MAX_TOML_DEPTH {
            return Some(line);
        }
        i += 1;
    }
    None
}

/// The index just past the string that starts at `b[i]` (basic or literal, one line or
/// multi-line), counting the lines it spans into `line`.
fn skip_string(b: &[u8], i: usize, line: &mut usize) -> usize {
    let q = b[i];
    let multi = b[i..].starts_with(&[q, q, q]);
    let mut j = if multi { i + 3 } else { i + 1 };
    while j < b.len() {
        match b[j] {
            b'\\' if q == b'"' => j += 1,
            b'\n' if !multi => return j,
            b'\n' => *line += 1,
            c if c == q && (!multi || b[j..].starts_with(&[q, q, q])) => return j + if multi { 3 } else { 1 },
            _ => {}
        }
        j += 1;
    }
    j
}
