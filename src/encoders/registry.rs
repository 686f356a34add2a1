//! The encoder registry: one line per encoder kind, and building an encoder by its id. Adding
//! an encoder means adding its file and one entry here; nothing else in the program names an
//! encoder.

use crate::encoders::ambient_cube;
use crate::encoders::ambient_dice;
use crate::encoders::encoder::{self, Encoder, Params};
use crate::encoders::geomerics;
use crate::encoders::hbasis;
use crate::encoders::lightmap::{ahd, hhd};
use crate::encoders::probe_occlusion as occ;
use crate::encoders::quantise;
use crate::encoders::self_bounce;
use crate::encoders::sg;
use crate::encoders::sh;
use crate::encoders::sh_high;
use crate::encoders::zh3;
use anyhow::{bail, Context, Result};

/// A kind of encoder: its id, a one-line summary, and its factory from TOML settings.
pub struct EncoderKind {
    /// Name used in experiment files, tables and `--encoders`.
    pub id: &'static str,
    /// One-line description for listings.
    pub summary: &'static str,
    /// Builds the encoder from its TOML settings; an unknown or out-of-range setting is an error.
    pub build: fn(&mut Params) -> Result<Box<dyn Encoder>>,
}

/// The baseline every reduction is measured against (`reduction_vs_sh1` of probe sets): SH L1,
/// what a game stores today (ZH3 talk).
pub const BASELINE: &str = "sh1";

/// The encoders `eval` and `probes` score when none are named (`--encoders`'s default, and the
/// Python package's): SH L1 and L2, comma-separated as `--encoders` takes them.
pub const DEFAULT_IDS: &str = "sh1,sh2";

/// Every encoder kind, in the order tables list them.
pub const REGISTRY: &[EncoderKind] = &[
    EncoderKind { id: "sh0", summary: "SH band 0 only (constant)", build: sh::build_sh0 },
    EncoderKind { id: "sh1", summary: "SH L1 irradiance (bands 0-1)", build: sh::build_sh1 },
    EncoderKind { id: "sh2", summary: "SH L2 irradiance (bands 0-2)", build: sh::build_sh2 },
    EncoderKind { id: "probe_unoccluded", summary: "L2 probe, unoccluded (leaks)", build: occ::build_unoccluded },
    EncoderKind { id: "probe_hemi_full", summary: "L2 x hemisphere, rotated Gram", build: occ::build_hemi_full },
    EncoderKind { id: "probe_cone_full", summary: "L2 x cone, rotated Gram", build: occ::build_cone_full },
    EncoderKind { id: "probe_hemi_q2l", summary: "quadratic-to-linear multiply", build: occ::build_hemi_q2l },
    EncoderKind { id: "hlsh", summary: "HLSH: hemisphere multiply, I_z pinned", build: occ::build_hlsh },
    EncoderKind { id: "probe_hhd_lum", summary: "hemisphere multiply, luminance HHD", build: occ::build_hhd_lum },
    EncoderKind { id: "cone_multiply", summary: "HLSH cone multiply", build: occ::build_cone_multiply },
    EncoderKind { id: "ao_scale", summary: "L2 probe irradiance x cone AO", build: occ::build_ao_scale },
    EncoderKind { id: "bent_normal", summary: "L2 probe at the cone centre x AO", build: occ::build_bent_normal },
    EncoderKind { id: "sh1_q13", summary: "SH L1, ratio-quantised to 13 bytes", build: quantise::build_sh1_q13 },
    EncoderKind { id: "sh2_q28", summary: "SH L2, ratio-quantised to 28 bytes", build: quantise::build_sh2_q28 },
    EncoderKind {
        id: "geomerics",
        summary: "Geomerics L1 reconstruction, normalised",
        build: geomerics::build_geomerics,
    },
    EncoderKind {
        id: "geomerics_peer",
        summary: "Geomerics as the peer tool (R0=L00, R1=L1/2)",
        build: geomerics::build_geomerics_peer,
    },
    EncoderKind {
        id: "zh3_hallucinate",
        summary: "ZH3 hallucinated, curve fit, Rec.709 axis",
        build: zh3::build_hallucinate,
    },
    EncoderKind {
        id: "zh3_hallucinate_channel",
        summary: "ZH3 hallucinated, curve fit, per-channel axes",
        build: zh3::build_hallucinate_channel,
    },
    EncoderKind {
        id: "zh3_hallucinate_ambdir",
        summary: "ZH3 hallucinated, ambient+directional model",
        build: zh3::build_hallucinate_ambdir,
    },
    EncoderKind {
        id: "zh3_hallucinate_sphere",
        summary: "ZH3 hallucinated, sphere-light model",
        build: zh3::build_hallucinate_sphere,
    },
    EncoderKind {
        id: "zh3_stored_channel",
        summary: "ZH3 stored, per-channel L1 axes",
        build: zh3::build_stored_channel,
    },
    EncoderKind {
        id: "zh3_stored_shared",
        summary: "ZH3 stored, shared equal-weight L1 axis",
        build: zh3::build_stored_shared,
    },
    EncoderKind {
        id: "zh3_solved_channel",
        summary: "ZH3 stored, axis solved per channel (L-BFGS)",
        build: zh3::build_solved_channel,
    },
    EncoderKind {
        id: "zh3_solved_shared",
        summary: "ZH3 stored, shared axis solved (L-BFGS)",
        build: zh3::build_solved_shared,
    },
    EncoderKind {
        id: "zh3_hallucinate_solved",
        summary: "ZH3 hallucinated from a solved L1, shared axis",
        build: zh3::build_hallucinate_solved,
    },
    EncoderKind { id: "zh3_q16", summary: "ZH3 stored, solved shared axis, 16 bytes", build: zh3::build_q16 },
    EncoderKind {
        id: "zh3_hallucinate_q13",
        summary: "ZH3 hallucinated, Rec.709 axis, 13 bytes",
        build: zh3::build_hallucinate_q13,
    },
    EncoderKind { id: "ahd_linear_sphere", summary: "AHD, L1 direction, sphere Gram", build: ahd::build_linear_sphere },
    EncoderKind { id: "ahd_linear_hemi", summary: "AHD, L1 direction, hemisphere Gram", build: ahd::build_linear_hemi },
    EncoderKind {
        id: "ahd_search_sphere",
        summary: "AHD, golden-section tilt, sphere Gram",
        build: ahd::build_search_sphere,
    },
    EncoderKind {
        id: "ahd_search_hemi",
        summary: "AHD, golden-section tilt, hemisphere Gram",
        build: ahd::build_search_hemi,
    },
    EncoderKind {
        id: "ahd_irradz_2018",
        summary: "AHD, I_z fixed, 2018 null-space fit",
        build: ahd::build_irradz_2018,
    },
    EncoderKind {
        id: "hhd_linear_sphere",
        summary: "HHD IrradZ, L1 direction, sphere Gram",
        build: hhd::build_linear_sphere,
    },
    EncoderKind {
        id: "hhd_linear_hemi",
        summary: "HHD IrradZ, L1 direction, hemisphere Gram",
        build: hhd::build_linear_hemi,
    },
    EncoderKind {
        id: "hhd_search_sphere",
        summary: "HHD IrradZ, golden-section tilt, sphere Gram",
        build: hhd::build_search_sphere,
    },
    EncoderKind {
        id: "hhd_search_hemi",
        summary: "HHD IrradZ, golden-section tilt, hemisphere Gram",
        build: hhd::build_search_hemi,
    },
    EncoderKind { id: "hhd_from_sh1", summary: "HHD from linear SH, talk's closed form", build: hhd::build_from_sh1 },
    EncoderKind { id: "sh3", summary: "SH L3 irradiance (bands 0-3; peer SHL3)", build: sh_high::build_sh3 },
    EncoderKind { id: "sh4", summary: "SH L4 irradiance (bands 0-4; peer SHL4)", build: sh_high::build_sh4 },
    EncoderKind {
        id: "sh2_windowed",
        summary: "SH L2, Laplacian window (peer SHL2W, full band energy)",
        build: sh_high::build_sh2_windowed,
    },
    EncoderKind {
        id: "sh2_windowed_peer",
        summary: "SH L2 windowed as the peer (its band-energy slip)",
        build: sh_high::build_sh2_windowed_peer,
    },
    EncoderKind {
        id: "ambient_cube",
        summary: "ambient cube, NNLS to exact E/pi (peer AC)",
        build: ambient_cube::build_ambient_cube,
    },
    EncoderKind {
        id: "ambient_cube_proj",
        summary: "ambient cube, exact E/pi at the axes (peer ACPROJ)",
        build: ambient_cube::build_ambient_cube_proj,
    },
    EncoderKind {
        id: "ambient_dice",
        summary: "ambient dice, Bezier, LS to exact E/pi (peer AD)",
        build: ambient_dice::build_ambient_dice,
    },
    EncoderKind {
        id: "ambient_dice_ycocg",
        summary: "ambient dice, Bezier Y + linear Co/Cg (peer ADYCoCg)",
        build: ambient_dice::build_ambient_dice_ycocg,
    },
    EncoderKind {
        id: "ambient_dice_srbf",
        summary: "ambient dice, 12 cosine SRBF lobes (peer ADRBF)",
        build: ambient_dice::build_ambient_dice_srbf,
    },
    EncoderKind { id: "sg_naive", summary: "12 SGs, naive projection (peer SG)", build: sg::build_naive },
    EncoderKind { id: "sg_ls", summary: "12 SGs, least squares (peer SGLS)", build: sg::build_ls },
    EncoderKind {
        id: "sg_ls_ambient",
        summary: "12 SGs + ambient, least squares (peer SGLSA)",
        build: sg::build_ls_ambient,
    },
    EncoderKind { id: "sg_nnls", summary: "12 SGs, non-negative least squares (peer SGNNLS)", build: sg::build_nnls },
    EncoderKind { id: "sg_ra", summary: "12 SGs, running average (peer SGRA)", build: sg::build_ra },
    EncoderKind { id: "sg_nnra", summary: "12 SGs, non-negative running average (peer SGNNRA)", build: sg::build_nnra },
    EncoderKind {
        id: "hbasis4",
        summary: "H-basis 4, E/pi over the hemisphere about N (peer H4)",
        build: hbasis::build_hbasis4,
    },
    EncoderKind {
        id: "hbasis6",
        summary: "H-basis 6, E/pi over the hemisphere about N (peer H6)",
        build: hbasis::build_hbasis6,
    },
    EncoderKind {
        id: "with_self_bounce",
        summary: "inner encoder + (1 - H) albedo I_z self-bounce",
        build: build_self_bounce,
    },
];

/// `with_self_bounce`, handed the registry's [`build`] for its inner encoder (the wrapper does
/// not import the registry that lists it).
fn build_self_bounce(p: &mut Params) -> Result<Box<dyn Encoder>> {
    self_bounce::build(p, |kind, settings| Ok(build(kind, None, settings)?.encoder))
}

/// The ids of every registered encoder, comma-separated (for error messages).
pub fn known_ids() -> String {
    REGISTRY.iter().map(|k| k.id).collect::<Vec<_>>().join(", ")
}

/// The family of the registered kind `id` built with its default settings; None for an id
/// the registry does not have (or whose defaults do not build).
pub fn family_of(id: &str) -> Option<encoder::Family> {
    build(id, None, toml::Table::new()).ok().map(|n| n.encoder.family())
}

/// A configured encoder with the name it appears under in tables.
pub struct NamedEncoder {
    /// Name shown in tables (the kind, unless the experiment renames it).
    pub name: String,
    /// The configured encoder.
    pub encoder: Box<dyn Encoder>,
}

/// Builds an encoder of `kind` with settings `params`, shown as `name` (default: the kind).
pub fn build(kind: &str, name: Option<&str>, params: toml::Table) -> Result<NamedEncoder> {
    let Some(k) = REGISTRY.iter().find(|k| k.id == kind) else {
        let ids: Vec<&str> = REGISTRY.iter().map(|k| k.id).collect();
        let hint = crate::math::nearest::did_you_mean(kind, &ids);
        bail!("unknown encoder '{}'{hint}; valid encoders: {}", crate::math::echo::value(kind), known_ids());
    };
    let mut p = Params::new(params);
    let encoder = (k.build)(&mut p).with_context(|| format!("configuring encoder '{kind}'"))?;
    Ok(NamedEncoder { name: name.unwrap_or(kind).to_string(), encoder })
}

/// Builds encoders from a comma-separated list of kinds (the `--encoders` option).
/// An empty list, or a kind listed twice, is an error (as in experiment files).
pub fn build_list(list: &str) -> Result<Vec<NamedEncoder>> {
    let kinds: Vec<&str> = list.split(',').map(str::trim).filter(|s| !s.is_empty()).collect();
    let list = crate::math::echo::value(list);
    if kinds.is_empty() {
        bail!("--encoders '{list}': list at least one encoder (valid: {})", known_ids());
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(k) = kinds.iter().find(|k| !seen.insert(**k)) {
        bail!("--encoders '{list}': '{}' appears twice", crate::math::echo::value(k));
    }
    kinds.into_iter().map(|k| build(k, None, toml::Table::new())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every registered encoder declares its family: none falls back to `Other`, and the
    /// wrapper takes its inner encoder's.
    #[test]
    fn every_registered_encoder_declares_a_family() {
        use crate::encoders::encoder::Family;
        for k in REGISTRY {
            let e = build(k.id, None, toml::Table::new()).unwrap();
            assert_ne!(e.encoder.family(), Family::Other, "{} declares no family", k.id);
        }
        let mut inner = toml::Table::new();
        inner.insert("inner".into(), toml::Value::String("zh3_hallucinate".into()));
        assert_eq!(build("with_self_bounce", None, inner).unwrap().encoder.family(), Family::Zh3);
    }

    /// Every registered encoder states its bytes a probe: what its fit writes when it reports
    /// `bytes` (the quantised encodings), else two bytes (a half float) per stored scalar.
    #[test]
    fn every_registered_encoder_states_its_bytes() {
        use crate::encoders::encoder::FitInput;
        use crate::math::colour::Rgb;
        use crate::math::sh::{constant, delta_light};
        let sh = constant(Rgb::splat(0.3)) + delta_light(glam::DVec3::new(0.0, 0.6, 0.8), Rgb::new(2.0, 1.5, 1.0));
        let mut quantised = 0;
        for k in REGISTRY {
            let e = build(k.id, None, toml::Table::new()).unwrap().encoder;
            let written = e.fit(&FitInput::sphere(&sh)).diagnostics().iter().find(|(n, _)| *n == "bytes").map(|d| d.1);
            quantised += written.is_some() as usize;
            let expected = written.unwrap_or(2.0 * e.stored_scalars() as f64);
            assert_eq!(e.stored_bytes() as f64, expected, "{}", k.id);
        }
        assert_eq!(quantised, 4, "sh1_q13, sh2_q28 and the talk's two ZH3 formats");
    }

    #[test]
    fn ids_are_unique_and_match_the_built_encoder() {
        for (i, k) in REGISTRY.iter().enumerate() {
            assert!(REGISTRY[i + 1..].iter().all(|o| o.id != k.id), "duplicate {}", k.id);
            let e = build(k.id, None, toml::Table::new()).unwrap();
            assert_eq!(e.encoder.id(), k.id);
        }
    }

    #[test]
    fn unknown_encoder_lists_valid_ones() {
        let e = build("sh9", None, toml::Table::new()).err().unwrap().to_string();
        assert!(e.contains("unknown encoder 'sh9'") && e.contains("sh1"), "{e}");
        let e = build_list("sh1,sh22").err().unwrap().to_string();
        assert!(e.contains("unknown encoder 'sh22' (did you mean 'sh2'?); valid"), "{e}");
        let e = build_list("SH2").err().unwrap().to_string();
        assert!(e.contains("unknown encoder 'SH2' (did you mean 'sh2'?); valid"), "{e}");
        let mut t = toml::Table::new();
        t.insert("bogus".into(), toml::Value::Integer(1));
        let e = format!("{:#}", build("sh1", None, t).err().unwrap());
        assert!(e.contains("bogus"), "{e}");
    }
}
