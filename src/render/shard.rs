//! One slice of a render split across machines (`render --shard I/N`, issue 37): shard I of N
//! takes the contiguous sample indices `spp·(I−1)/N .. spp·I/N` of the one-machine render's
//! `0 .. spp`. The renderers draw every sample from a counter-based RNG keyed by (pixel,
//! sample index, seed), so the N shards together draw exactly the one-machine render's
//! samples, and their spp-weighted mean is its image (`render::shard_merge`).

use std::ops::Range;

/// Shard `index` (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl Shard {
    /// Parse "I/N" with 1 ≤ I ≤ N (the message names what is wrong, not the flag: clap and
    /// the EXR reader add where the value came from).
    pub fn parse(s: &str) -> Result<Shard, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("'{s}' is not I/N (e.g. 2/8: the second of eight shards)"))?;
        let num = |t: &str, what: &str| {
            t.trim()
                .parse::<u32>()
                .map_err(|_| format!("'{s}': {what} '{t}' is not a whole number"))
        };
        let (index, count) = (num(i, "I")?, num(n, "N")?);
        if count == 0 || index == 0 || index > count {
            return Err(format!(
                "'{s}': need 1 ≤ I ≤ N (shards are numbered from 1)"
            ));
        }
        Ok(Shard { index, count })
    }

    /// The sample indices of this shard of a `spp`-sample render: as even a split as whole
    /// samples allow (sizes differ by at most one), in order, disjoint, covering `0 .. spp`.
    pub fn samples(&self, spp: u32) -> Range<u32> {
        let at = |i: u32| (u64::from(spp) * u64::from(i) / u64::from(self.count)) as u32;
        at(self.index - 1)..at(self.index)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::Shard;

    #[test]
    fn parses_i_of_n_and_refuses_the_rest() {
        assert_eq!(Shard::parse("2/8"), Ok(Shard { index: 2, count: 8 }));
        for bad in ["0/4", "5/4", "1/0", "4", "a/4", "1/b", "-1/4", "", "1/2/3"] {
            assert!(Shard::parse(bad).is_err(), "{bad} accepted");
        }
    }

    #[test]
    fn shards_tile_the_samples_evenly() {
        for spp in [1u32, 7, 16, 1000, u32::MAX] {
            for n in 1..=9u32.min(spp) {
                let mut next = 0u32;
                let (mut lo, mut hi) = (u32::MAX, 0);
                for i in 1..=n {
                    let r = Shard { index: i, count: n }.samples(spp);
                    assert_eq!(r.start, next, "spp {spp}, {i}/{n}: a gap or an overlap");
                    next = r.end;
                    lo = lo.min(r.len() as u32);
                    hi = hi.max(r.len() as u32);
                }
                assert_eq!(next, spp, "spp {spp}, N {n}: not every sample");
                assert!(hi - lo <= 1, "spp {spp}, N {n}: sizes {lo}..{hi}");
            }
        }
    }
}
