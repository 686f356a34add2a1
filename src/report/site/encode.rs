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
        let cases = [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("fooba", "Zm9vYmE=")];
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

    #[test]
    fn seven_significant_digits() {
        assert_eq!(sig7(0.123456789), 0.1234568);
        assert_eq!(sig7(-98765432.1), -98765430.0);
        assert_eq!(sig7(f64::INFINITY), 0.0);
    }
}
