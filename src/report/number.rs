//! Numbers as the pictures and the report print them: `sig` (n significant digits, compact)
//! and `percent` (a fraction as a label).

/// `v` with `n` significant digits, compact.
pub fn sig(v: f64, n: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return "nonfinite".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{:.*e}", n.saturating_sub(1), v);
    }
    let decimals = (n as i32 - 1 - mag).max(0) as usize;
    format!("{v:.decimals$}")
}

/// A percentage for labels.
pub fn percent(v: f64) -> String {
    let p = v * 100.0;
    if p.abs() >= 10.0 || p == 0.0 {
        format!("{p:.0}%")
    } else if p.abs() >= 1.0 {
        format!("{p:.1}%")
    } else {
        format!("{}%", sig(p, 2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_and_percentages() {
        assert_eq!(sig(0.094552, 3), "0.0946");
        assert_eq!(percent(0.123), "12%");
    }
}
