//! `--shard I/N`: one of N deterministic parts of a batch, so that a job array spreads a data
//! set over machines with no coordination.
//!
//! Part `I` (1-based) holds the meshes at positions `I − 1, I − 1 + N, I − 1 + 2N, …` of the
//! input list (a directory's mesh files sorted by name, or a list's lines in order): the parts
//! are disjoint, cover the input, and differ in size by at most one. Membership depends on the
//! whole list, so every part must see the same input.

use std::fmt;
use std::str::FromStr;

/// The `I`-th of `N` parts (`1 ≤ I ≤ N`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// Whether the mesh at `position` (0-based) of the input list belongs to this part.
    pub fn contains(self, position: usize) -> bool {
        position % self.count == self.index - 1
    }

    /// The file this part's summary is written to, `summary-I-of-N.csv`.
    pub fn summary_name(self) -> String {
        format!("summary-{}-of-{}.csv", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let malformed = || format!("`{text}` is not of the form I/N (e.g. 3/8)");
        let (index, count) = text.split_once('/').ok_or_else(malformed)?;
        let index: usize = index.trim().parse().map_err(|_| malformed())?;
        let count: usize = count.trim().parse().map_err(|_| malformed())?;
        if count == 0 || index == 0 || index > count {
            return Err(format!(
                "`{text}`: the part I must be one of 1…N (N ≥ 1); \
                 with a Slurm array --array=0-{} pass $((SLURM_ARRAY_TASK_ID + 1))/{}",
                count.max(1) - 1,
                count.max(1)
            ));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(count: usize) -> impl Iterator<Item = Shard> {
        (1..=count).map(move |index| Shard { index, count })
    }

    #[test]
    fn parts_are_disjoint_cover_the_input_and_are_balanced() {
        for count in 1..6 {
            for len in 0..20 {
                let sizes: Vec<usize> = all(count)
                    .map(|shard| (0..len).filter(|&p| shard.contains(p)).count())
                    .collect();
                assert_eq!(sizes.iter().sum::<usize>(), len);
                let (min, max) = (sizes.iter().min(), sizes.iter().max());
                assert!(max.unwrap() - min.unwrap() <= 1, "{sizes:?}");
                for p in 0..len {
                    assert_eq!(all(count).filter(|s| s.contains(p)).count(), 1);
                }
            }
        }
    }

    #[test]
    fn parsing() {
        let shard: Shard = "2/3".parse().unwrap();
        assert_eq!(shard.to_string(), "2/3");
        assert_eq!(shard.summary_name(), "summary-2-of-3.csv");
        assert!(shard.contains(1) && shard.contains(4) && !shard.contains(0));
        for bad in ["0/3", "4/3", "1/0", "3", "a/b", "-1/2", "1/2/3"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        assert!(
            "0/4"
                .parse::<Shard>()
                .unwrap_err()
                .contains("SLURM_ARRAY_TASK_ID + 1")
        );
    }
}
