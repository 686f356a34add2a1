//! Echoing what a user wrote in an error message: a value cut to [`MAX_VALUE_CHARS`]
//! characters and a quoted line to [`MAX_LINE_CHARS`], ending in "…" where cut, so that a
//! 300-digit number or a megabyte-long line is never printed whole. Every error that repeats a
//! value or a line from a file or the command line goes through [`value`] or [`line`] (maps,
//! experiment, sweep and claims files, `--domain`, sweep axes, encoder names).

/// Most characters of a value echoed in an error (the "…" included).
pub const MAX_VALUE_CHARS: usize = 40;
/// Most characters of a quoted line echoed in an error (the "…" included).
pub const MAX_LINE_CHARS: usize = 120;

/// `text` cut to `max` characters, the last of them "…" when it was longer.
pub fn cut(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        return text.to_string();
    }
    let mut s: String = text.chars().take(max.saturating_sub(1)).collect();
    s.push('…');
    s
}

/// A value as an error echoes it: at most [`MAX_VALUE_CHARS`] characters.
pub fn value(text: &str) -> String {
    cut(text, MAX_VALUE_CHARS)
}

/// A quoted line as an error echoes it: at most [`MAX_LINE_CHARS`] characters.
pub fn line(text: &str) -> String {
    cut(text, MAX_LINE_CHARS)
}

/// `message` with every span between double quotes or backquotes cut like a [`value`]: for a
/// parser's message (TOML, serde) that quotes what it read.
pub fn quoted_values(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(1024));
    let mut rest = message;
    while let Some(open) = rest.find(['"', '`']) {
        let q = rest[open..].chars().next().unwrap_or('"');
        let inner = &rest[open + 1..];
        let Some(close) = inner.find(q) else { break };
        out.push_str(&rest[..=open]);
        out.push_str(&value(&inner[..close]));
        out.push(q);
        rest = &inner[close + 1..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_values_and_lines_are_cut_with_an_ellipsis() {
        assert_eq!(value("sh1"), "sh1");
        let digits = "9".repeat(300);
        let v = value(&digits);
        assert_eq!(v.chars().count(), 40);
        assert_eq!(v, format!("{}…", "9".repeat(39)));
        assert_eq!(value(&"x".repeat(40)), "x".repeat(40));
        let l = line(&"é".repeat(500));
        assert_eq!(l.chars().count(), 120);
        assert!(l.ends_with("é…"));
    }

    #[test]
    fn quoted_spans_of_a_message_are_cut_and_the_rest_kept() {
        let long = "7".repeat(300);
        let m = quoted_values(&format!("invalid type: string \"{long}\", expected `u32`, got `{long}`"));
        let cut = format!("{}…", "7".repeat(39));
        assert_eq!(m, format!("invalid type: string \"{cut}\", expected `u32`, got `{cut}`"));
        assert_eq!(quoted_values("an \"unclosed quote"), "an \"unclosed quote");
    }
}
