//! The stored form of a fit: what an engine's bake would ship, as named values with their
//! units, and the reconstruction they feed (`Fitted::stored`). Units and directions are
//! those of FORMULAS §1 (E/π; world directions, +Y up); SH coefficients follow the basis,
//! normalisation and index order of FORMULAS §2, named `L{l}_{m}` (`L1_-1`, …).
//!
//! Every entry is either **stored** (the scalars a probe or texel holds, counted by
//! `Encoder::stored_scalars`) or **derived** (recomputed at decode time from the stored
//! values, the surface normal N or the encoder's fixed constants, such as the zonal axis of a
//! ZH3 or the lobe axes of an SG basis): listed so a consumer need not re-derive them, never
//! counted.

use crate::math::colour::Rgb;
use glam::DVec3;
use serde::ser::{Serialize, SerializeSeq, Serializer};

/// The unit of an entry (FORMULAS §1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Unit {
    /// Irradiance as E/π (a constant environment of radiance 1 gives 1), or a coefficient of
    /// E/π in a basis.
    #[serde(rename = "E/pi")]
    Irradiance,
    /// Radiance, or a coefficient of radiance in a basis (before the cosine convolution).
    #[serde(rename = "radiance")]
    Radiance,
    /// A pure number: a ratio, a weight, a sharpness, a tangent-space coordinate.
    #[serde(rename = "unitless")]
    Unitless,
    /// A unit vector in world space, +Y up (FORMULAS §1).
    #[serde(rename = "direction")]
    Direction,
}

impl Unit {
    /// The label tables and the `fit` command print: `E/pi`, `radiance`, `unitless`,
    /// `direction`.
    pub fn label(self) -> &'static str {
        match self {
            Unit::Irradiance => "E/pi",
            Unit::Radiance => "radiance",
            Unit::Unitless => "unitless",
            Unit::Direction => "direction",
        }
    }
}

/// Prints [`Unit::label`]: `E/pi`, `radiance`, `unitless`, `direction` (padded to a width asked for).
impl std::fmt::Display for Unit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.label())
    }
}

/// Whether an entry is held by the probe or texel, or recomputed from what is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Stored: counted by `Encoder::stored_scalars`.
    Stored,
    /// Derived at decode time (from stored values, N, or the encoder's constants).
    Derived,
}

/// Prints `stored` or `derived` (as in JSON and CSV).
impl std::fmt::Display for Role {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(match self {
            Role::Stored => "stored",
            Role::Derived => "derived",
        })
    }
}

/// The value of an entry: one scalar, an RGB triple or a 3-vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// One number.
    Scalar(f64),
    /// Red, green, blue.
    Rgb(Rgb),
    /// x, y, z (world space, +Y up).
    Vector(DVec3),
}

impl Value {
    /// How many scalars the value holds: 1 or 3.
    pub fn scalars(&self) -> usize {
        match self {
            Value::Scalar(_) => 1,
            Value::Rgb(_) | Value::Vector(_) => 3,
        }
    }

    /// The scalars in order (r, g, b or x, y, z).
    pub fn components(&self) -> Vec<f64> {
        match *self {
            Value::Scalar(v) => vec![v],
            Value::Rgb(v) | Value::Vector(v) => v.to_array().to_vec(),
        }
    }

    /// `scalar`, `rgb` or `vector`.
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Scalar(_) => "scalar",
            Value::Rgb(_) => "rgb",
            Value::Vector(_) => "vector",
        }
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.components().iter().all(|c| c.is_finite())
    }
}

/// Prints the components separated by spaces (`0.25`, `0.1 0.2 0.3`), each in Rust's shortest
/// round-trip form, or with the precision asked for (`{:.4}`).
impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, c) in self.components().iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            match f.precision() {
                Some(p) => write!(f, "{c:.p$}")?,
                None => write!(f, "{c}")?,
            }
        }
        Ok(())
    }
}

/// A value serialises as the list of its components.
impl Serialize for Value {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let c = self.components();
        let mut seq = s.serialize_seq(Some(c.len()))?;
        for v in &c {
            seq.serialize_element(v)?;
        }
        seq.end()
    }
}

/// One named value of a stored form.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Entry {
    /// The papers' name: `L1_-1`, `k`, `zonal_axis`, `C_a`, `I_z`, `ratio`, ….
    pub name: String,
    /// Its unit.
    pub unit: Unit,
    /// Stored or derived.
    pub role: Role,
    /// The value.
    pub value: Value,
}

/// The stored form of one fit: the reconstruction its entries feed, with the conventions
/// (which section of FORMULAS), and the entries in storage order.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Stored {
    /// How the entries reconstruct E/π(n), citing the FORMULAS section of each convention.
    pub basis: String,
    /// The entries, stored ones in the order a texel or probe would hold them.
    pub entries: Vec<Entry>,
}

/// The SH coefficient name of index `i` in FORMULAS §2's order: `L0_0`, `L1_-1`, `L1_0`,
/// `L1_1`, `L2_-2`, … (band l holds indices l² … l² + 2l, m = i − l² − l).
pub fn sh_name(i: usize) -> String {
    // Band l holds the indices l², …, l² + 2l, for any l (SH L3/L4 too).
    let l = (0..).find(|l: &usize| (l + 1) * (l + 1) > i).expect("some band holds i");
    let m = i as i64 - (l * l + l) as i64;
    format!("L{l}_{m}")
}

impl Stored {
    /// An empty stored form with its reconstruction description.
    pub fn new(basis: impl Into<String>) -> Self {
        Stored { basis: basis.into(), entries: Vec::new() }
    }

    /// Appends an entry.
    pub fn push(&mut self, role: Role, name: impl Into<String>, unit: Unit, value: Value) -> &mut Self {
        self.entries.push(Entry { name: name.into(), unit, role, value });
        self
    }

    /// Appends a stored RGB entry.
    pub fn rgb(&mut self, name: impl Into<String>, unit: Unit, v: Rgb) -> &mut Self {
        self.push(Role::Stored, name, unit, Value::Rgb(v))
    }

    /// Appends a stored scalar entry.
    pub fn scalar(&mut self, name: impl Into<String>, unit: Unit, v: f64) -> &mut Self {
        self.push(Role::Stored, name, unit, Value::Scalar(v))
    }

    /// Appends SH coefficients `c[0..]` as RGB entries named by [`sh_name`] (FORMULAS §2).
    pub fn sh(&mut self, role: Role, unit: Unit, c: &[Rgb]) -> &mut Self {
        for (i, v) in c.iter().enumerate() {
            self.push(role, sh_name(i), unit, Value::Rgb(*v));
        }
        self
    }

    /// The number of stored scalars (RGB and vectors count 3), which `Encoder::stored_scalars`
    /// promises; derived entries are not counted.
    pub fn scalar_count(&self) -> usize {
        self.entries.iter().filter(|e| e.role == Role::Stored).map(|e| e.value.scalars()).sum()
    }

    /// The first entry named `name`.
    pub fn get(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// The RGB of the entry `name`, if it is one.
    pub fn rgb_of(&self, name: &str) -> Option<Rgb> {
        match self.get(name)?.value {
            Value::Rgb(v) => Some(v),
            _ => None,
        }
    }

    /// The vector of the entry `name`, if it is one.
    pub fn vector_of(&self, name: &str) -> Option<DVec3> {
        match self.get(name)?.value {
            Value::Vector(v) => Some(v),
            _ => None,
        }
    }

    /// The scalar of the entry `name`, if it is one.
    pub fn scalar_of(&self, name: &str) -> Option<f64> {
        match self.get(name)?.value {
            Value::Scalar(v) => Some(v),
            _ => None,
        }
    }

    /// Whether every value is finite.
    pub fn is_finite(&self) -> bool {
        self.entries.iter().all(|e| e.value.is_finite())
    }

    /// This stored form with every entry turned derived (for a wrapper whose stored values
    /// are another's, such as the per-normal payload of an occlusion operator), names
    /// prefixed by `prefix`.
    pub fn as_derived(&self, prefix: &str) -> Vec<Entry> {
        self.entries
            .iter()
            .map(|e| Entry { name: format!("{prefix}{}", e.name), role: Role::Derived, ..e.clone() })
            .collect()
    }
}

/// FORMULAS §2–3 in one sentence: the basis of every SH irradiance entry list.
pub const SH_IRRADIANCE: &str = "E/pi(n) = sum_i c_i Y_i(n) over the entries L{l}_{m} (E/pi units: the radiance SH \
     times the cosine band scales 1, 2/3, 1/4, 0, -1/24 of docs/conventions.md section 3); Y_i the real orthonormal SH \
     with the Condon-Shortley phase in the order (0,0), (1,-1), (1,0), (1,1), (2,-2), ... of section 2; n a world \
     direction, +Y up (section 1)";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sh_names_follow_the_index_order_of_formulas_2() {
        let names: Vec<String> = (0..9).map(sh_name).collect();
        assert_eq!(names, ["L0_0", "L1_-1", "L1_0", "L1_1", "L2_-2", "L2_-1", "L2_0", "L2_1", "L2_2"]);
        assert_eq!(sh_name(16), "L4_-4");
        assert_eq!(sh_name(24), "L4_4");
        assert_eq!(sh_name(15), "L3_3");
    }

    /// What `{}` prints is what JSON and CSV call them, so a program's output matches theirs.
    #[test]
    fn units_roles_and_values_print_as_the_tables_name_them() {
        assert_eq!(format!("{}|{:9}|", Unit::Irradiance, Unit::Direction), "E/pi|direction|");
        assert_eq!(format!("{:8}|{}", Role::Stored, Role::Derived), "stored  |derived");
        assert_eq!(Value::Scalar(0.25).to_string(), "0.25");
        assert_eq!(format!("{:.2}", Value::Rgb(DVec3::new(0.1, 0.2, 0.3))), "0.10 0.20 0.30");
    }

    #[test]
    fn values_count_their_scalars() {
        assert_eq!(Value::Scalar(2.0).scalars(), 1);
        assert_eq!(Value::Rgb(Rgb::ONE).scalars(), 3);
        assert_eq!(Value::Vector(DVec3::Y).scalars(), 3);
        assert_eq!(Value::Vector(DVec3::new(1.0, 2.0, 3.0)).components(), [1.0, 2.0, 3.0]);
        assert_eq!(Value::Scalar(-0.5).components(), [-0.5]);
        assert_eq!(
            [Value::Scalar(0.0).kind(), Value::Rgb(Rgb::ZERO).kind(), Value::Vector(DVec3::X).kind()],
            ["scalar", "rgb", "vector"]
        );
    }

    #[test]
    fn only_stored_entries_are_counted() {
        let mut s = Stored::new("test");
        assert_eq!(s.scalar_count(), 0);
        s.sh(Role::Stored, Unit::Irradiance, &[Rgb::ONE; 4]);
        s.scalar("ratio", Unit::Unitless, 0.5);
        s.push(Role::Derived, "zonal_axis", Unit::Direction, Value::Vector(DVec3::Y));
        assert_eq!(s.scalar_count(), 13);
        assert_eq!(s.entries.len(), 6);
        assert_eq!(s.rgb_of("L1_1"), Some(Rgb::ONE));
        assert_eq!(s.scalar_of("ratio"), Some(0.5));
        assert_eq!(s.vector_of("zonal_axis"), Some(DVec3::Y));
        // The wrong kind, or no such entry, is None.
        assert_eq!(s.rgb_of("ratio"), None);
        assert_eq!(s.scalar_of("L0_0"), None);
        assert_eq!(s.vector_of("nothing"), None);
        let d = s.as_derived("inner.");
        assert_eq!(d.len(), 6);
        assert!(d.iter().all(|e| e.role == Role::Derived && e.name.starts_with("inner.")));
    }

    #[test]
    fn finiteness_looks_at_every_component() {
        let mut s = Stored::new("test");
        s.rgb("a", Unit::Radiance, Rgb::new(1.0, 2.0, 3.0));
        assert!(s.is_finite());
        s.push(Role::Derived, "b", Unit::Direction, Value::Vector(DVec3::new(0.0, f64::NAN, 0.0)));
        assert!(!s.is_finite());
        assert!(!Value::Rgb(Rgb::new(0.0, 0.0, f64::INFINITY)).is_finite());
        assert!(Value::Scalar(-1e300).is_finite());
    }

    #[test]
    fn units_have_stable_labels_and_serialise_as_them() {
        let all = [Unit::Irradiance, Unit::Radiance, Unit::Unitless, Unit::Direction];
        let labels: Vec<&str> = all.iter().map(|u| u.label()).collect();
        assert_eq!(labels, ["E/pi", "radiance", "unitless", "direction"]);
        for u in all {
            assert_eq!(serde_json::to_string(&u).unwrap(), format!("\"{}\"", u.label()));
        }
        let mut s = Stored::new("b");
        s.scalar("x", Unit::Unitless, 0.25);
        let j = serde_json::to_string(&s).unwrap();
        assert_eq!(j, r#"{"basis":"b","entries":[{"name":"x","unit":"unitless","role":"stored","value":[0.25]}]}"#);
    }
}
