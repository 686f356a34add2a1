//! The `effects` entries: `"hemisphere"`, a cone with its cosines and tilts, a self-bounce
//! with its albedos, each checked and turned into an [`Effect`].

use super::file::EffectEntry;
use super::model::Effect;
use anyhow::{bail, Result};

/// One `effects` entry as an [`Effect`]: its kind, its keys (no unknown one) and their values
/// checked.
pub(super) fn parse_effect(e: EffectEntry) -> Result<Effect> {
    let floats = |t: &toml::Table, key: &str| -> Result<Vec<f64>> {
        match t.get(key) {
            None => bail!("effects: cone needs '{key}'"),
            Some(toml::Value::Float(f)) => Ok(vec![*f]),
            Some(toml::Value::Integer(i)) => Ok(vec![*i as f64]),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| match v {
                    toml::Value::Float(f) => Ok(*f),
                    toml::Value::Integer(i) => Ok(*i as f64),
                    _ => bail!("effects: '{key}' must hold numbers"),
                })
                .collect(),
            Some(v) => bail!(
                "effects: '{key}' must be a number or a list, got {v}",
                v = crate::math::echo::value(&v.to_string())
            ),
        }
    };
    match e {
        EffectEntry::Name(n) if n == "hemisphere" => Ok(Effect::Hemisphere),
        EffectEntry::Name(n) if n == "self_bounce" => {
            bail!("effects: 'self_bounce' needs an albedo: {{ kind = \"self_bounce\", albedo = [0.2, 0.5, 0.8] }}")
        }
        EffectEntry::Name(n) => bail!(
            "effects: unknown effect '{n}' (valid: hemisphere, cone, self_bounce)",
            n = crate::math::echo::value(&n.to_string())
        ),
        EffectEntry::Table(t) => match t.get("kind").and_then(|v| v.as_str()) {
            Some("hemisphere") if t.len() == 1 => Ok(Effect::Hemisphere),
            Some("cone") => {
                if let Some(k) = t.keys().find(|k| !["kind", "cos_alpha", "tilt_deg"].contains(&k.as_str())) {
                    bail!(
                        "effects: cone has unknown key '{k}' (valid: cos_alpha, tilt_deg)",
                        k = crate::math::echo::value(&k.to_string())
                    );
                }
                let cos_alpha = floats(&t, "cos_alpha")?;
                if cos_alpha.iter().any(|c| !(-1.0..1.0).contains(c)) {
                    bail!("effects: cone cos_alpha must lie in [-1, 1)");
                }
                let tilt_deg = if t.contains_key("tilt_deg") { floats(&t, "tilt_deg")? } else { vec![0.0] };
                if tilt_deg.iter().any(|t| !t.is_finite()) {
                    bail!("effects: cone tilt_deg must be finite");
                }
                if cos_alpha.is_empty() || tilt_deg.is_empty() {
                    bail!("effects: cone cos_alpha and tilt_deg need at least one value each");
                }
                Ok(Effect::Cone { cos_alpha, tilt_deg })
            }
            Some("self_bounce") => {
                if let Some(k) = t.keys().find(|k| !["kind", "albedo"].contains(&k.as_str())) {
                    bail!(
                        "effects: self_bounce has unknown key '{k}' (valid: albedo)",
                        k = crate::math::echo::value(&k.to_string())
                    );
                }
                if !t.contains_key("albedo") {
                    bail!("effects: 'self_bounce' needs 'albedo' (a number or a list, each in [0, 1])");
                }
                let albedo = floats(&t, "albedo")?;
                if albedo.is_empty() {
                    bail!("effects: self_bounce 'albedo' needs at least one value");
                }
                if let Some(a) = albedo.iter().find(|a| !(0.0..=1.0).contains(*a)) {
                    bail!("effects: self_bounce 'albedo' {a} must lie in [0, 1]");
                }
                Ok(Effect::SelfBounce { albedo })
            }
            Some(k) => bail!(
                "effects: unknown effect kind '{k}' (valid: hemisphere, cone, self_bounce)",
                k = crate::math::echo::value(k)
            ),
            None => bail!("effects: a table entry needs kind = \"hemisphere\", \"cone\" or \"self_bounce\""),
        },
    }
}
