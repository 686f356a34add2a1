//! Gauss–Legendre quadrature and the splitting of lat-long rows into smooth polar pieces.

/// Gauss–Legendre nodes and weights on [−1, 1] for `n` points (n ≥ 1), by Newton iteration on
/// the Legendre polynomial (Numerical Recipes `gauleg`).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    assert!(n >= 1, "gauss_legendre needs at least one node");
    let mut out = vec![(0.0, 0.0); n];
    let m = n.div_ceil(2);
    for i in 0..m {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut pp = 0.0;
        for _ in 0..100 {
            let (mut p1, mut p2) = (1.0, 0.0);
            for j in 0..n {
                let p3 = p2;
                p2 = p1;
                p1 = ((2 * j + 1) as f64 * z * p2 - j as f64 * p3) / (j + 1) as f64;
            }
            pp = n as f64 * (z * p1 - p2) / (z * z - 1.0);
            let z1 = z;
            z = z1 - p1 / pp;
            if (z - z1).abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - z * z) * pp * pp);
        out[i] = (-z, w);
        out[n - 1 - i] = (z, w);
    }
    out
}

/// The tallest polar piece a rule is applied to: π/128, a row of a 256×128 map. The polar
/// integrands are smooth between breakpoints, so the rule's error falls with the piece's height;
/// capping the height makes a coarse map's reference as accurate as a 256×128 map's (a constant
/// map within 3e-7 at 2 nodes, at every map size) instead of degrading with the row height
/// (a 2×1 map's single row gave 9% with 2 nodes). Rows of maps 128 or more rows tall are never
/// cut, so their references are unchanged bit for bit.
pub const MAX_POLAR_PIECE: f64 = std::f64::consts::PI / 128.0;

/// Equal pieces a polar interval of height `h` is cut into so that none is taller than
/// [`MAX_POLAR_PIECE`] (1 for a 256×128 row: the relative slack absorbs the row edges' rounding).
pub fn polar_pieces(h: f64) -> usize {
    let n = (h / MAX_POLAR_PIECE * (1.0 - 1e-9)).ceil();
    if n.is_finite() && n > 1.0 {
        n as usize
    } else {
        1
    }
}

/// Polar quadrature of one row [φ0, φ1]: the row is split at the given breakpoints (where an
/// integrand has a kink), each piece is cut into [`polar_pieces`] equal parts no taller than
/// [`MAX_POLAR_PIECE`], and each part gets the Gauss–Legendre rule `rule` (nodes on [−1, 1]).
/// Calls `f(φ, w)` for every node, with `w` the node's weight in dφ (no sin φ Jacobian).
#[inline]
pub fn for_each_polar_node(
    phi0: f64,
    phi1: f64,
    breakpoints: &[f64],
    rule: &[(f64, f64)],
    mut f: impl FnMut(f64, f64),
) {
    let mut cuts = [0.0f64; 10];
    let mut n = 0;
    cuts[n] = phi0;
    n += 1;
    let mut inner = [0.0f64; 8];
    let mut ni = 0;
    for &b in breakpoints {
        if b > phi0 && b < phi1 && ni < inner.len() {
            inner[ni] = b;
            ni += 1;
        }
    }
    inner[..ni].sort_by(|a, b| a.total_cmp(b));
    for &b in &inner[..ni] {
        cuts[n] = b;
        n += 1;
    }
    cuts[n] = phi1;
    n += 1;
    for p in cuts[..n].windows(2) {
        let (a, b) = (p[0], p[1]);
        if b <= a {
            continue;
        }
        let parts = polar_pieces(b - a);
        if parts == 1 {
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for &(x, w) in rule {
                f(mid + half * x, half * w);
            }
            continue;
        }
        let step = (b - a) / parts as f64;
        for k in 0..parts {
            let lo = a + step * k as f64;
            let hi = if k + 1 == parts { b } else { a + step * (k + 1) as f64 };
            let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            for &(x, w) in rule {
                f(mid + half * x, half * w);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for n in 1..=8 {
            let rule = gauss_legendre(n);
            let wsum: f64 = rule.iter().map(|r| r.1).sum();
            assert!((wsum - 2.0).abs() < 1e-14);
            // ∫_{-1}^{1} x^k = 2/(k+1) for even k, exact up to degree 2n-1.
            for k in 0..(2 * n) {
                let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                let want = if k % 2 == 0 { 2.0 / (k as f64 + 1.0) } else { 0.0 };
                assert!((got - want).abs() < 1e-13, "n={n} k={k}: {got} vs {want}");
            }
        }
    }

    /// A row of a 256×128 map (any row, as the grid computes its edges) is one piece; a taller
    /// row is cut into pieces no taller than π/128, and the cut rule integrates sin φ over
    /// [0, π] (a 2×1 map's row) to 2 within 1e-8 where the uncut 2-node rule misses by 6%.
    #[test]
    fn tall_rows_are_cut_into_short_pieces() {
        use std::f64::consts::PI;
        for h in [128usize, 256, 4096, 8192] {
            // The row edges as `envmap::LatLong::phi_edge` computes them.
            let g: Vec<f64> = (0..=h).map(|j| PI * j as f64 / h as f64).collect();
            assert!(g.windows(2).all(|p| polar_pieces(p[1] - p[0]) == 1), "height {h}");
        }
        assert_eq!(polar_pieces(PI), 128);
        assert_eq!(polar_pieces(PI / 64.0), 2);
        assert_eq!(polar_pieces(PI / 127.0), 2);
        let rule = gauss_legendre(2);
        let integrate = |cut: bool| {
            let mut s = 0.0;
            if cut {
                for_each_polar_node(0.0, PI, &[], &rule, |x, w| s += w * x.sin());
            } else {
                for &(x, w) in &rule {
                    s += 0.5 * PI * w * (0.5 * PI * (1.0 + x)).sin();
                }
            }
            s
        };
        assert!((integrate(true) - 2.0).abs() < 1e-8, "{}", integrate(true));
        assert!((integrate(false) - 2.0).abs() > 0.05, "{}", integrate(false));
    }

    #[test]
    fn split_rows_integrate_a_kink_exactly() {
        // ∫_0^1 |x − 0.3| dx = (0.09 + 0.49)/2 = 0.29, exact when split at the kink.
        let rule = gauss_legendre(1);
        let mut s = 0.0;
        for_each_polar_node(0.0, 1.0, &[0.3, 5.0, -1.0], &rule, |x, w| s += w * (x - 0.3f64).abs());
        assert!((s - 0.29).abs() < 1e-15);
    }
}
