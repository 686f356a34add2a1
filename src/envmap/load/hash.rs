//! The sha256 of a file's bytes, in lower-case hex: a loaded map's identity
//! ([`crate::envmap::EnvMap::sha256`]), a probe file's, and a result table's.

use sha2::{Digest, Sha256};
use std::io::{self, Read};

/// Lower-case hex sha256 of `bytes`: a map file's identity ([`crate::envmap::EnvMap::sha256`]), and a result
/// table's (`regression::provenance`).
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lower-case hex sha256 of everything `reader` yields, read in 1 MiB pieces (a probe file's
/// identity, `pipeline::probeset`, without holding the file in memory).
pub fn sha256_hex_of(mut reader: impl Read) -> io::Result<String> {
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        match reader.read(&mut buf) {
            Ok(0) => return Ok(hex(&h.finalize())),
            Ok(n) => h.update(&buf[..n]),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
