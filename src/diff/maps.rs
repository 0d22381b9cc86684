//! The maps a comparison reads: every replicate of both conditions on the same bins.

use crate::error::{Error, Result};
use crate::io::MatrixReader;

/// Maps compared must share their bins: the first one that does not is named.
pub fn check_same_bins(readers: &[&dyn MatrixReader]) -> Result<()> {
    let reference = readers[0];
    for reader in &readers[1..] {
        let Some(why) = reference.bins().difference(reader.bins()) else {
            continue;
        };
        let what = if reference.bins().chroms() != reader.bins().chroms() {
            "chromosomes"
        } else {
            "bins"
        };
        return Err(Error::Data(format!(
            "{}: other {what} than {} ({why}); the maps compared must share their bins",
            reader.source(),
            reference.source()
        )));
    }
    Ok(())
}

/// Both conditions need a replicate.
pub fn check_conditions(n_maps: usize, n_first: usize) -> Result<()> {
    if n_first == 0 || n_first >= n_maps {
        return Err(Error::Argument(format!(
            "{} maps in A and {} in B: each condition needs at least one replicate",
            n_first,
            n_maps.saturating_sub(n_first)
        )));
    }
    Ok(())
}

/// Synthetic replicates for the comparisons' tests: Poisson counts around a given mean.
#[cfg(test)]
pub(super) mod synthetic {
    use crate::genome::{BinTable, Chrom};
    use crate::io::InMemory;
    use crate::matrix::{CountType, MatrixBuilder};
    use crate::random::{poisson, stream_rng};

    /// One chromosome of `n_bins` 1 kb bins, pixels up to `max_distance` bins apart, each a
    /// Poisson draw (seed `seed`) of `mean(i, j)`.
    pub fn replicate(
        n_bins: u64,
        max_distance: u64,
        seed: u64,
        mean: impl Fn(u64, u64) -> f64,
    ) -> InMemory {
        let bins = BinTable::fixed(vec![Chrom::new("chr1", n_bins * 1_000)], 1_000).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        let mut rng = stream_rng(seed, 0xd1ff, 0);
        for i in 0..n_bins {
            for j in i..(i + max_distance + 1).min(n_bins) {
                let count = poisson(&mut rng, mean(i, j));
                if count > 0 {
                    builder.push(i, j, count as f64).unwrap();
                }
            }
        }
        InMemory::new(format!("replicate {seed}"), builder.build())
    }
}
