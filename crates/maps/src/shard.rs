//! Shards `K/N` of a plane for cluster job arrays: whole lines (continuation
//! chains: rows or columns), dealt by estimated cost so that shards are
//! disjoint, cover the plane and carry about equal work
//! (`grid::schedule::shard_lines`).

use crate::error::FieldError;

/// Most shards a plane may be split into (and at most one per line).
pub const MAX_SHARDS: usize = 100_000;

/// Shard K of N (1-based K).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, 1..=n.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Parses `K/N`.
    pub fn parse(text: &str) -> Result<Shard, FieldError> {
        let bad = |m: String| FieldError::field("shard", m);
        let (k, n) = text.split_once('/').ok_or_else(|| bad(format!("expected K/N, got '{text}'")))?;
        let k: usize = k.trim().parse().map_err(|_| bad(format!("K '{k}' is not a whole number")))?;
        let n: usize = n.trim().parse().map_err(|_| bad(format!("N '{n}' is not a whole number")))?;
        if n == 0 || k == 0 || k > n {
            return Err(bad(format!("need 1 <= K <= N, got {k}/{n}")));
        }
        if n > MAX_SHARDS {
            return Err(bad(format!("N must be at most {MAX_SHARDS}, got {n}")));
        }
        Ok(Shard { k, n })
    }

    /// Whether the shard holds every line of its plane (`1/1`).
    pub fn is_whole(self) -> bool {
        self.n == 1
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse() {
        assert_eq!(Shard::parse("2/3").unwrap(), Shard { k: 2, n: 3 });
        for bad in ["0/2", "3/2", "1/0", "x/2", "1-2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
