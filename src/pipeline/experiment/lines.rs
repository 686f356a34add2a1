//! Where an error is in an experiment's text: the line of a value or key, a byte offset's line
//! and column, and the line quoted for the message.

/// The line of an error in the source text. The message's quoted words ('…') are tried from
/// the last (the most specific: "encoder 'sh1': unknown key(s) 'bogus'" points at `bogus`) to
/// the first, each looked up as a string literal ("w" or 'w') or as a key (`w =`). Failing
/// that, a message starting with a key ("maps: …", "resolution (…)") points at its line.
pub fn find_line(text: &str, e: &anyhow::Error) -> Option<usize> {
    let msg = format!("{e:#}");
    let quoted: Vec<&str> = msg.split('\'').skip(1).step_by(2).filter(|q| !q.is_empty()).collect();
    if let Some(l) = quoted.iter().rev().find_map(|q| find_value_or_key(text, q)) {
        return Some(l);
    }
    let key: String = msg.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
    if key.is_empty() {
        return None;
    }
    find_key(text, &key)
}

/// The first line holding `w` as a string literal, else as a key.
fn find_value_or_key(text: &str, w: &str) -> Option<usize> {
    // A value cut for the message (`math::echo`): its start, without the closing quote.
    if let Some(start) = w.strip_suffix('…') {
        let opened = [format!("\"{start}"), format!("'{start}")];
        return text.lines().position(|l| opened.iter().any(|q| l.contains(q.as_str()))).map(|i| i + 1);
    }
    let literal = [format!("\"{w}\""), format!("'{w}'")];
    text.lines()
        .position(|l| literal.iter().any(|q| l.contains(q.as_str())))
        .map(|i| i + 1)
        .or_else(|| find_key(text, w))
}

/// The first line of every string literal ("…" or '…', without escapes) in `text`.
pub(super) fn string_literal_lines(text: &str) -> std::collections::HashMap<&str, usize> {
    let mut out = std::collections::HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(start) = rest.find(['"', '\'']) {
            let quote = rest[start..].chars().next().unwrap_or('"');
            let after = &rest[start + 1..];
            let Some(len) = after.find(quote) else { break };
            out.entry(&after[..len]).or_insert(i + 1);
            rest = &after[len + 1..];
        }
    }
    out
}

/// The first line where `key` is assigned (`key =`, at the start of a line or inside an
/// inline table after `{` or `,`).
pub(super) fn find_key(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            l.match_indices(key).any(|(i, _)| {
                let before = l[..i].trim_end();
                let after = l[i + key.len()..].trim_start();
                (before.is_empty() || before.ends_with('{') || before.ends_with(',')) && after.starts_with('=')
            })
        })
        .map(|i| i + 1)
}

/// 1-based line and column of byte offset `at`.
pub(super) fn line_col(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// The source line `line` (1-based), quoted for an error message.
pub(super) fn quote_line(text: &str, line: usize) -> String {
    match text.lines().nth(line.wrapping_sub(1)) {
        Some(l) if !l.trim().is_empty() => format!("\n  {line} | {}", crate::math::echo::line(l.trim_end())),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_handles_multibyte_text() {
        assert_eq!(line_col("a\nbé c", 5), (2, 3));
        assert_eq!(line_col("é", 1), (1, 1));
        assert_eq!(line_col("", 10), (1, 1));
    }
}
