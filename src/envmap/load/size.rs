//! The size a header claims, checked before any pixel memory is allocated.

use super::error::LoadError;
use crate::envmap::header::{MAX_HEIGHT, MAX_WIDTH};
use crate::envmap::map::MapError;
use std::path::Path;

/// Checks a size read from a header before any pixel memory is allocated: not zero, at
/// most [`MAX_WIDTH`] x [`MAX_HEIGHT`], and 2:1.
pub(super) fn check_size(path: &Path, width: usize, height: usize) -> Result<(), LoadError> {
    let path = path.to_path_buf();
    if width == 0 || height == 0 {
        return Err(LoadError::ZeroSize { path, width, height });
    }
    if width > MAX_WIDTH || height > MAX_HEIGHT {
        return Err(LoadError::TooLarge { path, width, height });
    }
    if width != 2 * height {
        return Err(LoadError::Map { path, cause: MapError::Aspect { width, height } });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_size_order_of_checks() {
        let p = Path::new("m.exr");
        assert!(matches!(check_size(p, 0, 0), Err(LoadError::ZeroSize { .. })));
        assert!(matches!(check_size(p, 32768, 16384), Err(LoadError::TooLarge { .. })));
        assert!(matches!(check_size(p, 1, 1), Err(LoadError::Map { .. })));
        assert!(check_size(p, MAX_WIDTH, MAX_HEIGHT).is_ok());
        assert!(check_size(p, 2, 1).is_ok());
    }
}
