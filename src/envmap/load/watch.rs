//! Telling truncation from corruption: a reader that records whether a decoder tried to read
//! past the end of the file.

use super::error::LoadError;
use std::io::{self, BufReader, Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A reader that records whether anyone tried to read past the end of the data, so that a
/// decoder error can be reported as truncation.
pub(super) struct EofWatch<R> {
    inner: R,
    hit_eof: Arc<AtomicBool>,
}

impl<R: Read> Read for EofWatch<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        if n == 0 && !buf.is_empty() {
            self.hit_eof.store(true, Ordering::Relaxed);
        }
        Ok(n)
    }
}

impl<R: Seek> Seek for EofWatch<R> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.inner.seek(pos)
    }
}

/// Rewinds `file` and wraps it in a buffered [`EofWatch`]; returns the reader and its flag.
pub(super) fn watched<'f, R: Read + Seek>(
    path: &Path,
    file: &'f mut R,
) -> Result<(BufReader<EofWatch<&'f mut R>>, Arc<AtomicBool>), LoadError> {
    file.seek(SeekFrom::Start(0)).map_err(|cause| LoadError::Io {
        path: path.to_path_buf(),
        action: "seek in file",
        cause,
    })?;
    let flag = Arc::new(AtomicBool::new(false));
    Ok((BufReader::new(EofWatch { inner: file, hit_eof: flag.clone() }), flag))
}
