//! What a continuation split into segments continues ([`SegmentSpec`]): the parameter, its
//! values, the period and how the values are cut into segments. Kept in the store's plan
//! (`cases/plan.json`), so that `rubsim merge` assembles the segments of any shard without the
//! command line that made them.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// A continuation of the period-`period` orbit over `range`, cut into `segments` segments
/// ([`super::segments`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentSpec {
    /// The scene key continued in at the fixed ν `speed_ratio`; `None`: the speed ν itself.
    pub key: Option<String>,
    /// The fixed ν = ω/ω_n of a branch in a key (`None` for a branch in speed).
    pub speed_ratio: Option<f64>,
    /// `[from, to, step]`: ν for a branch in speed, the key's own units otherwise; continued
    /// from `from` towards `to` (downwards when `to < from`).
    pub range: [f64; 3],
    /// Period of the orbits in revolutions, the same for every segment.
    pub period: usize,
    /// Number of segments.
    pub segments: usize,
}

impl SegmentSpec {
    /// The branch's values in the order continued: speeds
    /// ([`crate::analysis::continuation::speeds`]) or a key's values
    /// ([`crate::analysis::continuation::values`]).
    ///
    /// # Errors
    /// As those.
    pub fn values(&self) -> Result<Vec<f64>> {
        let [a, b, h] = self.range;
        match self.key {
            None => crate::analysis::continuation::speeds(a, b, h),
            Some(_) => crate::analysis::continuation::values(a, b, h),
        }
    }

    /// The index ranges `[first, last]` of the values of each segment: consecutive segments
    /// share their end value (segment `j` ends where `j + 1` starts), so every interval
    /// between two values belongs to exactly one segment, and the segments hold as many
    /// intervals as whole numbers allow (a point costs about as much at any value: one Newton
    /// of a few iterations; a segment's first point also its settling run).
    ///
    /// # Errors
    /// [`Error::Study`] for no segment, or more segments than intervals between the values.
    pub fn bounds(&self) -> Result<Vec<[usize; 2]>> {
        let m = self.values()?.len().saturating_sub(1);
        let n = self.segments;
        if n == 0 || n > m {
            return Err(Error::study(
                "--segments",
                format!(
                    "{n} segment(s) of a branch of {} values: each segment needs at least one step, so 1 to {m}",
                    m + 1
                ),
            ));
        }
        Ok((0..n).map(|j| [j * m / n, (j + 1) * m / n]).collect())
    }

    /// The command as the store's scene hash takes it ([`super::scene_hash`]): `continue` and
    /// every number of the spec, so that segments of another range, period or cut are never
    /// mixed.
    pub fn command(&self) -> String {
        format!(
            "continue {}",
            serde_json::to_string(self).unwrap_or_default()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(segments: usize) -> SegmentSpec {
        SegmentSpec {
            key: None,
            speed_ratio: None,
            range: [1.0, 2.0, 0.1],
            period: 1,
            segments,
        }
    }

    #[test]
    fn segments_share_their_ends_and_cover_every_interval_once() {
        assert_eq!(spec(3).bounds().unwrap(), [[0, 3], [3, 6], [6, 10]]);
        assert_eq!(spec(10).bounds().unwrap().last(), Some(&[9, 10]));
        assert_eq!(spec(1).bounds().unwrap(), [[0, 10]]);
        for n in 1..=10 {
            let b = spec(n).bounds().unwrap();
            assert_eq!((b[0][0], b[n - 1][1]), (0, 10));
            assert!(b.windows(2).all(|w| w[0][1] == w[1][0]));
            assert!(b.iter().all(|[a, z]| z > a), "{b:?}");
        }
    }

    #[test]
    fn more_segments_than_steps_are_refused() {
        let e = spec(11).bounds().unwrap_err().to_string();
        assert!(e.contains("1 to 10"), "{e}");
        assert!(spec(0).bounds().is_err());
    }
}
