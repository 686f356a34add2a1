//! A map file's header, read before the `exr` and `image` decoders allocate anything, so that
//! the memory a load takes is bounded by what the file holds.
//!
//! OpenEXR ([`exr`]): the header is at most [`MAX_EXR_HEADER_BYTES`] with at most
//! [`MAX_EXR_ATTRIBUTES`] attributes; a single-part image's data window must equal its display
//! window (the display window is the lat-long sphere), neither inverted, within [`MAX_WIDTH`] x
//! [`MAX_HEIGHT`] (checked before anything else about the windows); the map must fit the memory
//! limit ([`memory_limit`]); and the offset table must lie inside the file with every entry
//! pointing into the file past it. Radiance ([`hdr`]): the header, through the resolution
//! line, is at most [`MAX_HDR_HEADER_BYTES`], its lines end in LF (not CR LF); its `EXPOSURE=`
//! and `COLORCORR=` values are read (Radiance's rule: the file's pixel values are the radiance
//! times their product, per channel for `COLORCORR`), its `PRIMARIES=` line, and `PIXASPECT=`
//! must be 1; the size is held to the same limits. A header this module cannot make sense of is left to the decoder, whose error says
//! what is wrong; every refusal here says which limit or rule the file breaks.

use crate::math::primaries::Chromaticities;
use std::io::{self, BufRead, Read};

/// Largest accepted map width in pixels. A header claiming more is refused before any
/// pixel memory is allocated.
pub const MAX_WIDTH: usize = 16384;
/// Largest accepted map height in pixels (with [`MAX_WIDTH`], at most 2^27 texels).
pub const MAX_HEIGHT: usize = 8192;
/// Largest accepted OpenEXR header (every part's attributes, through the terminating null
/// bytes), in bytes: 4 MiB.
pub const MAX_EXR_HEADER_BYTES: u64 = 4 << 20;
/// Most attributes an OpenEXR file's headers may hold, over all parts.
pub const MAX_EXR_ATTRIBUTES: usize = 1024;
/// Largest accepted Radiance header, through the resolution line, in bytes: 64 KiB.
pub const MAX_HDR_HEADER_BYTES: u64 = 64 << 10;
/// Bytes a loaded map takes per texel: three f32 and the loader's bit of coverage, rounded up.
/// A 16384x8192 map takes 1.75 GB by this count (measured peak of `eval` on one: benches/README.md).
pub const BYTES_PER_TEXEL: u64 = 13;
/// The environment variable that sets the memory limit for one map, in bytes
/// ([`memory_limit`]).
pub const MEMORY_LIMIT_VAR: &str = "PROBELAB_MAP_MEMORY";

/// Why a header is refused. The loader prefixes the file path.
#[derive(Debug, thiserror::Error)]
pub enum HeaderError {
    /// The header does not end within its size limit.
    #[error("{format} header is longer than the limit of {limit} bytes ({what}); refusing to read it")]
    TooLong {
        /// "OpenEXR" or "Radiance HDR".
        format: &'static str,
        /// The limit in bytes.
        limit: u64,
        /// Where the limit was reached.
        what: String,
    },
    /// The version field marks a multi-part file, but a part lacks what every part of one has.
    #[error("the OpenEXR version field's multi-part bit (0x1000) is set, but the header lacks the attributes every part of a multi-part file has (name, type, chunkCount): the bit is wrong (a single-part file with a stray flag) or the header is corrupt")]
    MultiPartBit,
    /// The OpenEXR header holds more attributes than [`MAX_EXR_ATTRIBUTES`].
    #[error("OpenEXR header holds more than the limit of {MAX_EXR_ATTRIBUTES} attributes; refusing to read it")]
    TooManyAttributes,
    /// The file ends inside its header or offset table.
    #[error("file is truncated (or a length field in it is corrupt): the data ends at {len} bytes, inside the {what}")]
    Truncated {
        /// The file's length in bytes.
        len: u64,
        /// The part of the file being read.
        what: String,
    },
    /// An attribute's declared size cannot be right.
    #[error("OpenEXR attribute '{name}' of type '{kind}' declares {size} bytes, {why}")]
    Attribute {
        /// The attribute's name (cut to 40 characters).
        name: String,
        /// Its type name (cut to 40 characters).
        kind: String,
        /// The size it declares.
        size: i64,
        /// What is wrong with that size.
        why: &'static str,
    },
    /// A window's maximum is below its minimum.
    #[error("OpenEXR {which} window {window} is inverted ({axis} max < {axis} min): it holds no pixel")]
    Inverted {
        /// "data" or "display".
        which: &'static str,
        /// The window as (x min,y min)-(x max,y max).
        window: Window,
        /// The inverted axis, 'x' or 'y'.
        axis: char,
    },
    /// The size is above [`MAX_WIDTH`] x [`MAX_HEIGHT`].
    #[error("header claims an image of {width}x{height} pixels, above the limit of {MAX_WIDTH}x{MAX_HEIGHT}; refusing to decode it")]
    TooLarge {
        /// Width the header claims, in pixels.
        width: u64,
        /// Height the header claims, in pixels.
        height: u64,
    },
    /// The data window is not the display window.
    #[error("OpenEXR data window {data} differs from display window {display}: the display window is the lat-long sphere, and only images whose data window covers exactly it are supported")]
    Windows {
        /// The data window.
        data: Window,
        /// The display window.
        display: Window,
    },
    /// The map needs more memory than the limit.
    #[error("a {width}x{height} map needs {needed} bytes ({BYTES_PER_TEXEL} per texel), above the memory limit of {limit} bytes ({source_of_limit}); refusing to decode it")]
    Memory {
        /// Width in pixels.
        width: u64,
        /// Height in pixels.
        height: u64,
        /// Bytes the map needs.
        needed: u64,
        /// The limit in bytes.
        limit: u64,
        /// Where the limit comes from.
        source_of_limit: String,
    },
    /// An offset-table entry points into the header or the table itself.
    #[error("OpenEXR offset table entry {index} of {count} points at byte {offset}, inside the header or the table (the chunks start at byte {first}); the offset table is corrupt")]
    Offset {
        /// Index of the entry.
        index: u64,
        /// Entries in the table.
        count: u64,
        /// The entry's value.
        offset: u64,
        /// The first byte after the table.
        first: u64,
    },
    /// A header variable (`EXPOSURE=`, `COLORCORR=`, `PRIMARIES=`, `PIXASPECT=`) breaks its
    /// rule.
    #[error("Radiance header line {line}: {name}={value}: {rule}")]
    Variable {
        /// The header line (1-based).
        line: usize,
        /// The variable's name.
        name: String,
        /// The value as written (cut to 40 characters).
        value: String,
        /// The rule it breaks.
        rule: &'static str,
    },
    /// A Radiance header line ends in CR LF.
    #[error("Radiance header line {line} ends in CR LF: a Radiance file's lines end in LF alone. The file was converted as text (a text-mode transfer or a git checkout with CRLF line ends), which also corrupts its binary pixels; get it again as a binary file")]
    CrLf {
        /// The header line (1-based).
        line: usize,
    },
    /// The memory limit's environment variable is not a number of bytes.
    #[error("{MEMORY_LIMIT_VAR}={value}: expected a number of bytes (a whole number)")]
    BadLimit {
        /// The variable's value (cut to 40 characters).
        value: String,
    },
    /// Reading the file failed.
    #[error("cannot read file: {0}")]
    Io(io::Error),
}

/// An OpenEXR `box2i` window: x min, y min, x max, y max (inclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window(pub [i32; 4]);

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x0, y0, x1, y1] = self.0;
        write!(f, "({x0},{y0})-({x1},{y1})")
    }
}

impl Window {
    /// Width and height, or the inverted axis.
    fn size(self) -> Result<(u64, u64), char> {
        let [x0, y0, x1, y1] = self.0.map(i64::from);
        match (x1 - x0 + 1, y1 - y0 + 1) {
            (w, _) if w <= 0 => Err('x'),
            (_, h) if h <= 0 => Err('y'),
            (w, h) => Ok((w as u64, h as u64)),
        }
    }
}

/// The attributes of a single-part header the checks need.
#[derive(Default)]
struct ExrFields {
    data: Option<Window>,
    display: Option<Window>,
    compression: Option<u8>,
    /// Tile width, tile height and level mode byte.
    tiles: Option<(u32, u32, u8)>,
    /// Which of the attributes every part of a multi-part file must have (`name`, `type`,
    /// `chunkCount`) this part has, one bit each.
    part_attributes: u8,
}

/// A reader that counts the bytes taken and reports the end of the file as truncation.
struct Counted<'r, R> {
    inner: &'r mut R,
    at: u64,
    len: u64,
}

impl<R: Read> Counted<'_, R> {
    fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N], HeaderError> {
        let mut buf = [0u8; N];
        self.inner.read_exact(&mut buf).map_err(|e| self.eof(e, what))?;
        self.at += N as u64;
        Ok(buf)
    }

    fn skip(&mut self, n: u64, what: &str) -> Result<(), HeaderError> {
        let got = io::copy(&mut (&mut *self.inner).take(n), &mut io::sink()).map_err(HeaderError::Io)?;
        self.at += got;
        if got < n {
            return Err(HeaderError::Truncated { len: self.len, what: what.to_string() });
        }
        Ok(())
    }

    /// A null-terminated string of at most 255 bytes (OpenEXR's long names).
    fn name(&mut self, what: &str) -> Result<Vec<u8>, HeaderError> {
        let mut s = Vec::new();
        loop {
            let [b] = self.bytes::<1>(what)?;
            if b == 0 {
                return Ok(s);
            }
            if s.len() == 255 {
                let shown = crate::math::echo::value(&String::from_utf8_lossy(&s));
                return Err(HeaderError::Attribute {
                    name: shown,
                    kind: String::new(),
                    size: 0,
                    why: "after a name longer than 255 bytes (not an OpenEXR header)",
                });
            }
            s.push(b);
        }
    }

    fn eof(&self, e: io::Error, what: &str) -> HeaderError {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            HeaderError::Truncated { len: self.len, what: what.to_string() }
        } else {
            HeaderError::Io(e)
        }
    }
}

/// Reads and checks an OpenEXR file's header and offset table from `reader` (at the file's
/// start; `len` is the file's length), before the decoder allocates anything. Returns the
/// size of a single-part flat image whose windows were checked, or `None` when the header is
/// one the decoder must judge (several parts, deep data, a missing window).
pub fn exr(reader: &mut impl Read, len: u64) -> Result<Option<(usize, usize)>, HeaderError> {
    let mut r = Counted { inner: reader, at: 0, len };
    let head = r.bytes::<8>("OpenEXR header")?;
    let version = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
    let (tiled, deep, multi) = (version & 0x200 != 0, version & 0x800 != 0, version & 0x1000 != 0);
    let mut attributes = 0usize;
    let mut parts = Vec::new();
    loop {
        let (fields, count) = exr_part(&mut r, &mut attributes)?;
        if count == 0 && multi {
            break; // the empty header that ends a multi-part file's list
        }
        if multi && fields.part_attributes != 0b111 {
            return Err(HeaderError::MultiPartBit);
        }
        parts.push(fields);
        if !multi {
            break;
        }
    }
    let [fields] = parts.as_slice() else { return Ok(None) };
    let (Some(data), Some(display)) = (fields.data, fields.display) else { return Ok(None) };
    if deep {
        return Ok(None);
    }
    let (width, height) = check_windows(data, display)?;
    check_memory(width, height)?;
    if let Some(chunks) = chunk_count(fields, tiled, width, height) {
        check_offsets(&mut r, chunks)?;
    }
    Ok(Some((width as usize, height as usize)))
}

/// Reads one part's attributes (through its terminating null byte), counting them into
/// `attributes`; returns the fields the checks need and how many attributes the part held.
fn exr_part(r: &mut Counted<'_, impl Read>, attributes: &mut usize) -> Result<(ExrFields, usize), HeaderError> {
    const WHAT: &str = "OpenEXR header";
    let too_long = |what: String| HeaderError::TooLong { format: "OpenEXR", limit: MAX_EXR_HEADER_BYTES, what };
    let mut fields = ExrFields::default();
    let mut count = 0;
    loop {
        if r.at > MAX_EXR_HEADER_BYTES {
            return Err(too_long(format!("no end of header within the first {} bytes", r.at)));
        }
        let name = r.name(WHAT)?;
        if name.is_empty() {
            return Ok((fields, count));
        }
        count += 1;
        *attributes += 1;
        if *attributes > MAX_EXR_ATTRIBUTES {
            return Err(HeaderError::TooManyAttributes);
        }
        let kind = r.name(WHAT)?;
        let size = i64::from(i32::from_le_bytes(r.bytes::<4>(WHAT)?));
        let shown = |b: &[u8]| crate::math::echo::value(&String::from_utf8_lossy(b));
        let bad = |why| HeaderError::Attribute { name: shown(&name), kind: shown(&kind), size, why };
        if size < 0 {
            return Err(bad("a negative size"));
        }
        let end = r.at + size as u64;
        if end > MAX_EXR_HEADER_BYTES {
            return Err(too_long(format!("attribute '{}' would end at byte {end}", shown(&name))));
        }
        let window = |r: &mut Counted<'_, _>| -> Result<Window, HeaderError> {
            let b = r.bytes::<16>(WHAT)?;
            Ok(Window(std::array::from_fn(|k| {
                i32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]])
            })))
        };
        match (name.as_slice(), kind.as_slice(), size) {
            (b"dataWindow", b"box2i", 16) => fields.data = Some(window(r)?),
            (b"displayWindow", b"box2i", 16) => fields.display = Some(window(r)?),
            (b"compression", b"compression", 1) => fields.compression = Some(r.bytes::<1>(WHAT)?[0]),
            (b"tiles", b"tiledesc", 9) => {
                let b = r.bytes::<9>(WHAT)?;
                let x = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                fields.tiles = Some((x, u32::from_le_bytes([b[4], b[5], b[6], b[7]]), b[8]));
            }
            _ => {
                let bit = [&b"name"[..], b"type", b"chunkCount"].iter().position(|n| *n == name.as_slice());
                fields.part_attributes |= bit.map_or(0, |k| 1 << k);
                r.skip(size as u64, WHAT)?
            }
        }
    }
}

/// The windows' checks, in order: neither inverted, the data window within [`MAX_WIDTH`] x
/// [`MAX_HEIGHT`], the data window equal to the display window. Returns the size.
fn check_windows(data: Window, display: Window) -> Result<(u64, u64), HeaderError> {
    let (width, height) = data.size().map_err(|axis| HeaderError::Inverted { which: "data", window: data, axis })?;
    display.size().map_err(|axis| HeaderError::Inverted { which: "display", window: display, axis })?;
    check_size(width, height)?;
    if data != display {
        return Err(HeaderError::Windows { data, display });
    }
    Ok((width, height))
}

/// A size within [`MAX_WIDTH`] x [`MAX_HEIGHT`].
fn check_size(width: u64, height: u64) -> Result<(), HeaderError> {
    if width > MAX_WIDTH as u64 || height > MAX_HEIGHT as u64 {
        return Err(HeaderError::TooLarge { width, height });
    }
    Ok(())
}

/// The map's bytes ([`BYTES_PER_TEXEL`] each) within [`memory_limit`].
fn check_memory(width: u64, height: u64) -> Result<(), HeaderError> {
    let needed = width * height * BYTES_PER_TEXEL;
    match memory_limit()? {
        Some((limit, source_of_limit)) if needed > limit => {
            Err(HeaderError::Memory { width, height, needed, limit, source_of_limit })
        }
        _ => Ok(()),
    }
}

/// The memory one map may take, in bytes, and where that figure comes from:
/// [`MEMORY_LIMIT_VAR`] if set, else the memory the machine has available now (`MemAvailable`
/// in `/proc/meminfo`), else no limit (another system, or no `/proc`).
pub fn memory_limit() -> Result<Option<(u64, String)>, HeaderError> {
    if let Some(v) = std::env::var_os(MEMORY_LIMIT_VAR) {
        let text = v.to_string_lossy();
        let limit =
            text.trim().parse::<u64>().map_err(|_| HeaderError::BadLimit { value: crate::math::echo::value(&text) })?;
        return Ok(Some((limit, format!("set by {MEMORY_LIMIT_VAR}"))));
    }
    let Ok(info) = std::fs::read_to_string("/proc/meminfo") else { return Ok(None) };
    let kib = info
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:")?.trim().strip_suffix("kB")?.trim().parse::<u64>().ok());
    Ok(kib.map(|k| (k * 1024, format!("the memory available now; set {MEMORY_LIMIT_VAR}=BYTES to change it"))))
}

/// How many chunks (offset-table entries) a single-part image of this size stores, or `None`
/// for a compression or tile description the decoder must judge.
fn chunk_count(fields: &ExrFields, tiled: bool, width: u64, height: u64) -> Option<u64> {
    if !tiled {
        let lines = match fields.compression? {
            0..=2 => 1,
            3 | 5 => 16,
            4 | 6..=8 => 32,
            9 => 256,
            _ => return None,
        };
        return Some(height.div_ceil(lines));
    }
    let (tx, ty, mode) = fields.tiles?;
    let (tx, ty) = (u64::from(tx), u64::from(ty));
    if tx == 0 || ty == 0 {
        return None;
    }
    let up = match mode >> 4 {
        0 => false,
        1 => true,
        _ => return None,
    };
    let level = |full: u64, l: u32| if up { full.div_ceil(1 << l) } else { full >> l }.max(1);
    let levels = |full: u64| if up { full.next_power_of_two().trailing_zeros() } else { full.ilog2() } + 1;
    let tiles = |w: u64, h: u64| w.div_ceil(tx) * h.div_ceil(ty);
    match mode & 0x0f {
        0 => Some(tiles(width, height)),
        1 => Some((0..levels(width.max(height))).map(|l| tiles(level(width, l), level(height, l))).sum()),
        2 => Some(
            (0..levels(width))
                .flat_map(|lx| (0..levels(height)).map(move |ly| (lx, ly)))
                .map(|(lx, ly)| tiles(level(width, lx), level(height, ly)))
                .sum(),
        ),
        _ => None,
    }
}

/// Reads the offset table (at `r`, `chunks` entries) without holding it: the table must end
/// inside the file, and every entry point past it and before the end.
fn check_offsets(r: &mut Counted<'_, impl Read>, chunks: u64) -> Result<(), HeaderError> {
    let first = r.at + 8 * chunks;
    let what = || format!("OpenEXR offset table ({chunks} entries, ending at byte {first})");
    if first > r.len {
        return Err(HeaderError::Truncated { len: r.len, what: what() });
    }
    for index in 0..chunks {
        let offset = u64::from_le_bytes(r.bytes::<8>(&what())?);
        if offset >= r.len {
            let what = format!("OpenEXR chunks (offset table entry {index} of {chunks} points at byte {offset})");
            return Err(HeaderError::Truncated { len: r.len, what });
        }
        if offset < first {
            return Err(HeaderError::Offset { index, count: chunks, offset, first });
        }
    }
    Ok(())
}

/// A Radiance header as [`hdr`] read it.
#[derive(Debug, PartialEq)]
pub struct HdrHeader {
    /// The size on the resolution line, when it reads as numbers (the decoder judges the rest).
    pub size: Option<(usize, usize)>,
    /// The product of the header's `EXPOSURE=` values (1 without any).
    pub exposure: f64,
    /// The per-channel product of the header's `COLORCORR=` values (1, 1, 1 without any):
    /// Radiance applies them as it applies `EXPOSURE`, one factor per primary.
    pub colorcorr: [f64; 3],
    /// The `PRIMARIES=` line's chromaticities, when there is one (none: Rec.709).
    pub primaries: Option<Chromaticities>,
}

impl HdrHeader {
    /// Reads one header variable line into the header (`EXPOSURE=`, `COLORCORR=`,
    /// `PRIMARIES=`, `PIXASPECT=`; other lines are comments or commands Radiance keeps).
    fn variable(&mut self, line: usize, text: &str) -> Result<(), HeaderError> {
        let Some((name, value)) = text.split_once('=') else { return Ok(()) };
        let bad = |rule: &'static str| HeaderError::Variable {
            line,
            name: name.to_string(),
            value: crate::math::echo::value(value),
            rule,
        };
        let numbers = |n: usize| -> Option<Vec<f64>> {
            let v: Vec<f64> = value.split_whitespace().map(|w| w.parse::<f64>().ok()).collect::<Option<_>>()?;
            (v.len() == n && v.iter().all(|x| x.is_finite())).then_some(v)
        };
        let positive = |v: &f64| *v > 0.0;
        match name {
            "EXPOSURE" => {
                let e = numbers(1).filter(|v| positive(&v[0])).map(|v| v[0] * self.exposure);
                self.exposure = e.filter(|e| e.is_finite() && *e > 0.0).ok_or(bad(POSITIVE_PRODUCT))?;
            }
            "COLORCORR" => {
                let v = numbers(3).filter(|v| v.iter().all(positive)).ok_or(bad(THREE_POSITIVE))?;
                let c: [f64; 3] = std::array::from_fn(|k| self.colorcorr[k] * v[k]);
                self.colorcorr = c.iter().all(|x| x.is_finite() && *x > 0.0).then_some(c).ok_or(bad(THREE_POSITIVE))?;
            }
            "PRIMARIES" => {
                let v = numbers(8).ok_or(bad(EIGHT_NUMBERS))?;
                let pair = |k: usize| [v[2 * k], v[2 * k + 1]];
                self.primaries = Some(Chromaticities { primaries: [pair(0), pair(1), pair(2)], white: pair(3) });
            }
            "PIXASPECT" => {
                let square = numbers(1).is_some_and(|v| (v[0] - 1.0).abs() <= 1e-6);
                if !square {
                    return Err(bad(SQUARE_PIXELS));
                }
            }
            _ => {}
        }
        Ok(())
    }
}

/// The rule an `EXPOSURE=` value breaks.
const POSITIVE_PRODUCT: &str =
    "expected a positive finite number (the product of every EXPOSURE value must be one too)";
/// The rule a `COLORCORR=` value breaks.
const THREE_POSITIVE: &str =
    "expected three positive finite numbers, one per primary (their products over every COLORCORR line too)";
/// The rule a `PRIMARIES=` value breaks.
const EIGHT_NUMBERS: &str = "expected eight finite numbers: red, green, blue and white x y";
/// The rule a `PIXASPECT=` value breaks.
const SQUARE_PIXELS: &str = "a lat-long map's texels are square in angle (width = 2 x height); \
     a pixel aspect other than 1 would stretch the sphere, so the map is refused";

/// Reads a Radiance header from `reader` (at the file's start) through the resolution line, at most [`MAX_HDR_HEADER_BYTES`]: the product of its
/// `EXPOSURE=` values, and the size (within [`MAX_WIDTH`] x [`MAX_HEIGHT`] and the memory
/// limit). A header that ends early is left to the decoder.
pub fn hdr(reader: &mut impl BufRead) -> Result<HdrHeader, HeaderError> {
    let mut limited = reader.take(MAX_HDR_HEADER_BYTES);
    let mut head = HdrHeader { size: None, exposure: 1.0, colorcorr: [1.0; 3], primaries: None };
    let mut line = Vec::new();
    let mut in_header = true;
    let mut number = 0;
    loop {
        number += 1;
        line.clear();
        let n = limited.read_until(b'\n', &mut line).map_err(HeaderError::Io)?;
        if n == 0 || line.last() != Some(&b'\n') {
            if limited.limit() == 0 {
                let what = format!("no resolution line within the first {MAX_HDR_HEADER_BYTES} bytes");
                return Err(HeaderError::TooLong { format: "Radiance HDR", limit: MAX_HDR_HEADER_BYTES, what });
            }
            return Ok(head); // cut short: the decoder says so
        }
        if line.ends_with(b"\r\n") {
            return Err(HeaderError::CrLf { line: number });
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end_matches('\n');
        if in_header {
            in_header = !text.is_empty();
            head.variable(number, text)?;
            continue;
        }
        head.size = resolution(text);
        if let Some((w, h)) = head.size {
            check_size(w as u64, h as u64)?;
            check_memory(w as u64, h as u64)?;
        }
        return Ok(head);
    }
}

/// Width and height of a resolution line `±Y H ±X W` (or `±X W ±Y H`), if it reads as one.
fn resolution(line: &str) -> Option<(usize, usize)> {
    let t: Vec<&str> = line.split_whitespace().collect();
    let [a, n, b, m] = t[..] else { return None };
    let (n, m) = (n.parse::<usize>().ok()?, m.parse::<usize>().ok()?);
    match (a.ends_with('Y'), b.ends_with('X'), a.ends_with('X'), b.ends_with('Y')) {
        (true, true, _, _) => Some((m, n)),
        (_, _, true, true) => Some((n, m)),
        _ => None,
    }
}
