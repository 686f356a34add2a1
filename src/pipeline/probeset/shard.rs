//! Shards of a probe set: shard I of N is a contiguous range of probe indices, so a set can be
//! scored in N pieces (on a batch engine) and the N state files merged exactly
//! (`probelab probes --shard I/N`, `probelab merge`).

use anyhow::Result;

/// Shard I of N: the contiguous range of probe indices [⌊I·T/N⌋, ⌊(I+1)·T/N⌋) of a set of T.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Index I of this shard, in [0, count).
    pub index: usize,
    /// Number of shards N.
    pub count: usize,
}

impl Shard {
    /// The whole set as one shard (0/1).
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses "I/N" with 0 ≤ I < N.
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || anyhow::anyhow!("--shard '{s}': expected I/N with 0 <= I < N, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) =
            (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The index range of this shard in a set of `total` probes.
    pub fn range(&self, total: u64) -> (u64, u64) {
        let at = |k: usize| ((k as u128 * total as u128) / self.count as u128) as u64;
        (at(self.index), at(self.index + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_ranges_partition_the_set() {
        for total in [0u64, 1, 7, 100, 3_000_000] {
            for n in 1..6 {
                let mut next = 0;
                for i in 0..n {
                    let (a, b) = Shard { index: i, count: n }.range(total);
                    assert_eq!(a, next);
                    next = b;
                }
                assert_eq!(next, total);
            }
        }
        assert_eq!(Shard::parse("2/5").unwrap(), Shard { index: 2, count: 5 });
        for bad in ["5/5", "1/0", "x/2", "3", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
