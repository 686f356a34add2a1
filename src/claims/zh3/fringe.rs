//! Claim Z2's fringing, where the talk puts it (ZH3 talk, "Colour shifting": "sometimes, if
//! the zonal axes are significantly different for each colour channel, the ZH3 basis functions
//! interfere"): how far apart the channels' zonal axes are (the axis divergence), and the
//! maps ordered by it. The fringe itself (ZH3 against the SH3 it approximates, whose L0 and
//! L1 it shares, so every difference comes from the zonal approximation of L2) is
//! `math::colour::xy_error` against the SH3, taken in `axis::z2`.

use crate::claims::measure::{Cell, Measure};
use crate::encoders::encoder::Fitted;
use glam::DVec3;

/// The per-channel zonal axes' names in a ZH3 fit's stored description.
const AXES: [&str; 3] = ["zonal_axis_r", "zonal_axis_g", "zonal_axis_b"];

/// The axis divergence of a per-channel ZH3, in degrees: the largest angle between two
/// channels' zonal axes, taken as lines (0°–90°), since a zonal function about a and about −a
/// is the same function with its L1 coefficient negated (FORMULAS §5). 0 when fewer than two
/// channels have an axis (a channel without L1 has no zonal term), or for a shared axis.
pub(super) fn axis_divergence(fit: &dyn Fitted) -> f64 {
    let stored = fit.stored();
    let axes: Vec<DVec3> = AXES.iter().filter_map(|n| stored.vector_of(n)).collect();
    let mut widest: f64 = 0.0;
    for (i, a) in axes.iter().enumerate() {
        for b in &axes[i + 1..] {
            widest = widest.max(a.dot(*b).abs().min(1.0).acos().to_degrees());
        }
    }
    widest
}

/// The stored ZH3 pair Z2 judges, per-channel axes then the shared axis.
const PAIR: [&str; 2] = ["zh3_stored_channel", "zh3_stored_shared"];

/// Z2's rows of the stored pair from `zh3_chroma` (exact metric), the maps and scenes ordered
/// by the axis divergence of their per-channel solved axes, widest first (ties in the table's
/// order): the maps where the talk says fringing appears come first. Measure
/// `zh3_axis_divergence`.
pub(super) fn by_divergence(chroma: &Measure) -> Measure {
    let col = |name: &str| chroma.columns.iter().position(|c| c == name);
    let text = |r: &[Cell], i: Option<usize>| match i.map(|i| &r[i]) {
        Some(Cell::Text(s)) => s.clone(),
        _ => String::new(),
    };
    let num = |r: &[Cell], i: Option<usize>| match i.map(|i| &r[i]) {
        Some(Cell::Num(x)) => *x,
        _ => 0.0,
    };
    let (map, enc, metric) = (col("map"), col("encoder"), col("metric"));
    let (fr, xy, div, l1) =
        (col("fringe_xy"), col("xy_err"), col("axis_divergence_deg"), col("l1_axis_divergence_deg"));
    let rows: Vec<&Vec<Cell>> =
        chroma.rows.iter().filter(|r| text(r, metric) == "exact" && PAIR.contains(&text(r, enc).as_str())).collect();
    let mut maps: Vec<(String, f64)> = Vec::new();
    for r in &rows {
        if !maps.iter().any(|(m, _)| *m == text(r, map)) {
            maps.push((text(r, map), num(r, div)));
        }
    }
    // A stable sort: equal divergences keep the table's order.
    maps.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut m = Measure::new(
        "zh3_axis_divergence",
        "Z2, ordered by axis divergence (widest first): for each map or constructed scene, the largest angle \
         between two channels' zonal axes taken as lines (0-90 degrees) - axis_divergence_deg for the \
         per-channel solved axes (zh3_solved_channel), l1_axis_divergence_deg for the per-channel L1 axes \
         (zh3_stored_channel) - beside the stored pair's fringe_xy (the luminance-weighted RMS CIE 1931 xy \
         distance of the ZH3 to the SH3 it approximates: the colour its zonal band adds) and xy_err (the same \
         distance to the exact reference); sphere, 256x128 normals, weights solid angle x luminance Y",
        &["map", "encoder", "axis_divergence_deg", "l1_axis_divergence_deg", "fringe_xy", "xy_err"],
    );
    for (name, _) in &maps {
        for r in rows.iter().filter(|r| text(r, map) == *name) {
            let cells = vec![text(r, map), text(r, enc)];
            let nums = [num(r, div), num(r, l1), num(r, fr), num(r, xy)];
            m.row(cells.into_iter().map(Cell::from).chain(nums.into_iter().map(Cell::from)).collect());
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::zh3::cases::{enc, fit};
    use crate::math::colour::Rgb;
    use crate::math::sh::delta_light;

    /// Two channels lit from +x and +y are 90° apart; a channel lit from −x lies on the same
    /// line as one lit from +x (0°); a shared axis has no divergence.
    #[test]
    fn divergence_is_the_widest_angle_between_axis_lines() {
        let e = enc("zh3_stored_channel", &[]).unwrap();
        let sh = |a: DVec3, b: DVec3| delta_light(a, Rgb::new(1.0, 0.0, 0.0)) + delta_light(b, Rgb::new(0.0, 1.0, 1.0));
        let right = axis_divergence(fit(e.as_ref(), &sh(DVec3::X, DVec3::Y)).as_ref());
        assert!((right - 90.0).abs() < 1e-9, "{right}");
        let opposite = axis_divergence(fit(e.as_ref(), &sh(DVec3::X, DVec3::NEG_X)).as_ref());
        assert!(opposite.abs() < 1e-6, "{opposite}");
        let shared = enc("zh3_stored_shared", &[]).unwrap();
        assert_eq!(axis_divergence(fit(shared.as_ref(), &sh(DVec3::X, DVec3::Y)).as_ref()), 0.0);
    }

    /// The order: widest divergence first, only the stored pair's exact rows.
    #[test]
    fn rows_are_ordered_by_divergence() {
        let cols = ["map", "encoder", "metric", "xy_err", "fringe_xy", "axis_divergence_deg", "l1_axis_divergence_deg"];
        let mut c = Measure::new("zh3_chroma", "", &cols);
        for (map, div) in [("a", 10.0), ("b", 40.0), ("c", 20.0)] {
            for e in ["zh3_stored_channel", "zh3_stored_shared", "sh1"] {
                for metric in ["exact", "probulator"] {
                    let t: Vec<Cell> = vec![map.into(), e.into(), metric.into()];
                    c.row(t.into_iter().chain([0.1, 0.2, div, 5.0].map(Cell::from)).collect());
                }
            }
        }
        let m = by_divergence(&c);
        let order: Vec<String> = m.rows.iter().map(|r| format!("{:?}", r[0])).collect();
        assert_eq!(m.rows.len(), 6);
        assert_eq!(order[0], format!("{:?}", Cell::from("b")));
        assert_eq!(order[2], format!("{:?}", Cell::from("c")));
        assert_eq!(order[4], format!("{:?}", Cell::from("a")));
    }
}
