//! Reading an OpenEXR map: the header checked before any pixel is decoded (one flat part,
//! square pixels, R, G, B channels of half or float samples at full resolution, no channel
//! named twice), then the pixels ([`super::exr_blocks`]), every one stored exactly once
//! ([`super::coverage`]).

use super::colour::Stated;
use super::error::LoadError;
use super::exr_blocks::{decode, exr_error, Target};
use super::format::Decoded;
use super::guard::guarded;
use super::size::check_size;
use super::watch::watched;
use crate::envmap::header;
use crate::math::primaries::Chromaticities;
use exr::prelude::{ChannelDescription, MetaData, SampleType, Vec2};
use std::io::{Read, Seek};
use std::path::Path;
use std::sync::atomic::Ordering;

/// Reads an OpenEXR file: header first (validated by [`check_exr_header`]), then the
/// pixels of the selected R, G, B channels as f32. Returns width, height and row-major
/// texels (row 0 at the top of the data window), the primaries the file states (its
/// `chromaticities` attribute), and the texels' pixel sha256 when it was formed while
/// decoding (`envmap::identity`; not when colour is still to be converted).
pub(super) fn read_exr(
    path: &Path,
    file: &mut (impl Read + Seek),
    len: u64,
) -> Result<(Decoded, Stated, Option<String>), LoadError> {
    const FORMAT: &str = "OpenEXR";
    let (mut reader, _) = watched(path, file)?;
    header::exr(&mut reader, len).map_err(|cause| LoadError::Header { path: path.to_path_buf(), cause })?;
    let (reader, hit_eof) = watched(path, file)?;
    let meta = guarded(path, FORMAT, || {
        MetaData::read_from_buffered(reader, false)
            .map_err(|e| exr_error(path, len, hit_eof.load(Ordering::Relaxed), e))
    })?;
    let (width, height, rgb) = check_exr_header(path, &meta)?;
    let primaries = meta.headers[0].shared_attributes.chromaticities.map(|c| {
        let xy = |v: Vec2<f32>| [f64::from(v.x()), f64::from(v.y())];
        Chromaticities { primaries: [xy(c.red), xy(c.green), xy(c.blue)], white: xy(c.white) }
    });
    let progress = (width >= crate::envmap::PROGRESS_WIDTH)
        .then(|| crate::io::progress::Progress::new(height as u64, &format!("decoding {}", path.display())));
    let (reader, hit_eof) = watched(path, file)?;
    // The texels are final as decoded unless primaries other than Rec.709 are converted.
    let hash = primaries.is_none_or(|p| p.is_rec709());
    let target = Target { width, height, rgb, hash, progress: progress.as_ref() };
    let (texels, pixel_sha256) = decode(path, reader, len, &hit_eof, &target)?;
    Ok(((width, height, texels), Stated { primaries, ..Stated::default() }, pixel_sha256))
}

/// Validates OpenEXR meta data before any pixel is read: no deep data, one part, a size
/// accepted by [`check_size`], a pixel aspect ratio of 1, no channel named twice, and R, G, B
/// channels (see [`select_rgb`]) holding full-resolution half or float samples. Returns the
/// size and the three channels' indices in the channel list.
pub(super) fn check_exr_header(path: &Path, meta: &MetaData) -> Result<(usize, usize, [usize; 3]), LoadError> {
    let p = || path.to_path_buf();
    if meta.requirements.has_deep_data || meta.headers.iter().any(|h| h.deep) {
        return Err(LoadError::Deep { path: p() });
    }
    let header = match meta.headers.as_slice() {
        [h] => h,
        [] => return Err(LoadError::Exr { path: p(), message: "the file has no header".into() }),
        hs => {
            let names = hs
                .iter()
                .enumerate()
                .map(|(i, h)| match &h.own_attributes.layer_name {
                    Some(n) => format!("'{n}'"),
                    None => format!("part {i} unnamed"),
                })
                .collect::<Vec<_>>()
                .join(", ");
            return Err(LoadError::MultiPart { path: p(), parts: hs.len(), names });
        }
    };
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    check_size(path, width, height)?;
    let aspect = header.shared_attributes.pixel_aspect;
    if (aspect - 1.0).abs() > 1e-6 || !aspect.is_finite() {
        return Err(LoadError::PixelAspect { path: p(), aspect });
    }
    let list = &header.channels.list;
    // Counted in one pass: a 4 MiB header can list some 200,000 channels.
    let mut counts = std::collections::HashMap::new();
    for c in list {
        *counts.entry(c.name.to_string()).or_insert(0usize) += 1;
    }
    if let Some(c) = list.iter().find(|c| counts[&c.name.to_string()] > 1) {
        let name = c.name.to_string();
        let (channel, count) = (crate::math::echo::value(&name), counts[&name]);
        return Err(LoadError::DuplicateChannel { path: p(), channel, count });
    }
    let chosen = select_rgb(path, list)?;
    for &i in &chosen {
        let c = &list[i];
        if c.sample_type == SampleType::U32 {
            return Err(LoadError::IntegerChannel { path: p(), channel: c.name.to_string() });
        }
        if (c.sampling.x(), c.sampling.y()) != (1, 1) {
            return Err(LoadError::Subsampled {
                path: p(),
                channel: c.name.to_string(),
                x: c.sampling.x(),
                y: c.sampling.y(),
            });
        }
    }
    Ok((width, height, chosen))
}

/// Picks the indices of the red, green and blue channels: the unprefixed `R`, `G`, `B` if
/// all three exist, otherwise `L.R`, `L.G`, `L.B` of the one layer `L` that has all three.
/// Several such layers is an ambiguity error; none is a missing-channel error naming what
/// is missing from the most complete candidate set and every channel the file has.
fn select_rgb(path: &Path, list: &[ChannelDescription]) -> Result<[usize; 3], LoadError> {
    let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
    let find = |prefix: &str, c: char| {
        let full = if prefix.is_empty() { c.to_string() } else { format!("{prefix}.{c}") };
        names.iter().position(|n| *n == full)
    };
    let full_set = |prefix: &str| match (find(prefix, 'R'), find(prefix, 'G'), find(prefix, 'B')) {
        (Some(r), Some(g), Some(b)) => Some([r, g, b]),
        _ => None,
    };
    if let Some(set) = full_set("") {
        return Ok(set);
    }
    // Layer prefixes that have at least one of R, G, B, in channel-list order.
    let mut prefixes: Vec<&str> = Vec::new();
    for n in &names {
        let prefix = n.strip_suffix(".R").or(n.strip_suffix(".G")).or(n.strip_suffix(".B"));
        if let Some(p) = prefix {
            if !prefixes.contains(&p) {
                prefixes.push(p);
            }
        }
    }
    let complete: Vec<&str> = prefixes.iter().copied().filter(|p| full_set(p).is_some()).collect();
    match complete.as_slice() {
        [only] => {
            if let Some(set) = full_set(only) {
                return Ok(set);
            }
        }
        [] => {}
        several => {
            let layers = several.iter().map(|p| format!("'{p}'")).collect::<Vec<_>>().join(", ");
            return Err(LoadError::AmbiguousChannels { path: path.to_path_buf(), layers });
        }
    }
    // Report against the candidate set with the most channels present (unprefixed on ties).
    let present_count = |p: &str| ['R', 'G', 'B'].iter().filter(|&&c| find(p, c).is_some()).count();
    let mut best = "";
    for p in &prefixes {
        if present_count(p) > present_count(best) {
            best = p;
        }
    }
    let missing = ['R', 'G', 'B']
        .iter()
        .filter(|&&c| find(best, c).is_none())
        .map(|&c| if best.is_empty() { c.to_string() } else { format!("{best}.{c}") })
        .collect::<Vec<_>>()
        .join(", ");
    let present = if names.is_empty() { "(none)".to_string() } else { names.join(", ") };
    Err(LoadError::MissingChannel { path: path.to_path_buf(), missing, present })
}
