//! How the site's data are written: float arrays as base64 of little-endian float32 (a
//! `Float32Array` in the page), and a JSON value as a script that sets one global.

/// The standard base64 alphabet (RFC 4648 §4).
const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Base64 (RFC 4648, padded) of `bytes`.
pub(super) fn base64(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// `values` as float32, little-endian, in base64. Values beyond float32 saturate at its largest
/// finite value (E/π of a real map is far inside it); a NaN, which no encoder returns (the
/// encoder contract), would be written as 0.
pub(super) fn f32_base64(values: impl IntoIterator<Item = f64>) -> String {
    let mut bytes = Vec::new();
    for v in values {
        let v = if v.is_nan() { 0.0 } else { v.clamp(f32::MIN as f64, f32::MAX as f64) as f32 };
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    base64(&bytes)
}

/// A grid encoding's values as their difference from the reference the page decodes (`reference`
/// as float32), in steps of `scale` = max |difference| / 32767: base64 of little-endian int16,
/// and `scale`. The page adds `q · scale` to its reference: a value comes back within `scale`/2
/// (plus float32 rounding), 1/65534 of the encoding's largest error, so its RMSE keeps four
/// digits and the site half the bytes of float32 values.
pub(super) fn i16_difference_base64(values: &[f64], reference: &[f64]) -> (String, f64) {
    let diff: Vec<f64> = values.iter().zip(reference).map(|(v, r)| v - f64::from(*r as f32)).collect();
    let largest = diff.iter().map(|d| d.abs()).filter(|d| d.is_finite()).fold(0.0, f64::max);
    let scale = largest / f64::from(i16::MAX);
    let mut bytes = Vec::with_capacity(2 * diff.len());
    for d in diff {
        let q = if scale > 0.0 && d.is_finite() { (d / scale).round().clamp(-32767.0, 32767.0) as i16 } else { 0 };
        bytes.extend_from_slice(&q.to_le_bytes());
    }
    (base64(&bytes), scale)
}

/// `v` rounded to 7 significant digits (float32's precision), so JSON prints it short; 0 for
/// a value that is not finite (none is: stored forms are finite, the encoder contract).
pub(super) fn sig7(v: f64) -> f64 {
    if v.is_finite() {
        format!("{v:.6e}").parse().unwrap_or(0.0)
    } else {
        0.0
    }
}

/// The script that sets `window.<global>` to `value` (the site's data travel as scripts: a
/// page opened from `file://` may not fetch).
pub(super) fn script(global: &str, key: Option<&str>, value: &serde_json::Value) -> String {
    let json = serde_json::to_string(value).unwrap_or_else(|_| "null".into());
    match key {
        None => format!("window.{global} = {json};\n"),
        Some(k) => format!(
            "window.{global} = window.{global} || {{}};\nwindow.{global}[{}] = {json};\n",
            serde_json::Value::String(k.to_string())
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 4648 §10's test vectors.
    #[test]
    fn base64_matches_the_rfc_vectors() {
        let cases =
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("fooba", "Zm9vYmE=")];
        for (plain, coded) in cases {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    /// 1.0f32 is 0x3f800000: little-endian 00 00 80 3f.
    #[test]
    fn floats_are_little_endian_float32() {
        assert_eq!(f32_base64([1.0]), base64(&[0, 0, 0x80, 0x3f]));
        assert_eq!(f32_base64([f64::NAN]), base64(&[0, 0, 0, 0]));
    }

    /// Decoded as the page decodes it (reference as float32, plus q · scale), every value comes
    /// back within half a step; the largest difference is ±32767 steps exactly.
    #[test]
    fn differences_come_back_within_half_a_step() {
        let reference = [1.0, 0.3, 2.5, 0.0];
        let values = [1.01, 0.299, 2.4, 1e-3];
        let (coded, scale) = i16_difference_base64(&values, &reference);
        assert_eq!(scale, (2.5 - 2.4) / 32767.0);
        assert_eq!(coded.len(), base64(&[0; 8]).len());
        let bytes: Vec<u8> = (0..4)
            .flat_map(|i| {
                let d = values[i] - f64::from(reference[i] as f32);
                ((d / scale).round() as i16).to_le_bytes()
            })
            .collect();
        assert_eq!(coded, base64(&bytes));
        assert_eq!(i16::from_le_bytes([bytes[4], bytes[5]]), -32767);
        for i in 0..4 {
            let q = f64::from(i16::from_le_bytes([bytes[2 * i], bytes[2 * i + 1]]));
            let back = f64::from(reference[i] as f32) + q * scale;
            assert!((back - values[i]).abs() <= scale / 2.0 + 1e-15, "{i}: {back} vs {}", values[i]);
        }
        assert_eq!(i16_difference_base64(&[1.0, 2.0], &[1.0, 2.0]), (base64(&[0; 4]), 0.0));
    }

    #[test]
    fn seven_significant_digits() {
        assert_eq!(sig7(0.123456789), 0.1234568);
        assert_eq!(sig7(-98765432.1), -98765430.0);
        assert_eq!(sig7(f64::INFINITY), 0.0);
    }
}
