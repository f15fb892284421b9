//! Snapshot sums grouped into consecutive blocks, for batch-means standard errors of
//! time-correlated samples.
use crate::sampling::snapshot::field::FIELDS;
use serde::{Deserialize, Serialize};

/// A value of the summed snapshots and its standard error (spread of the block values /
/// sqrt(blocks)).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Estimate {
    pub mean: f64,
    pub se: f64,
}

impl Estimate {
    /// The mean of block values and its batch-means standard error (sample standard
    /// deviation over sqrt(blocks); zero spread for a single block).
    pub fn of_blocks(values: &[f64]) -> Estimate {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        Estimate {
            mean,
            se: (var / n).sqrt(),
        }
    }
}

/// `blocks` consecutive groups of `per_block` snapshots, each holding the summed
/// snapshot (`FIELDS x n_bins`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BlockSums {
    pub n_bins: usize,
    pub per_block: usize,
    /// Summed snapshots, one `FIELDS * n_bins` vector per block.
    pub sums: Vec<Vec<f64>>,
    /// Snapshots added so far.
    pub taken: usize,
}

impl BlockSums {
    /// Room for `blocks * per_block` snapshots.
    pub fn new(n_bins: usize, blocks: usize, per_block: usize) -> Self {
        Self {
            n_bins,
            per_block,
            sums: vec![vec![0.0; FIELDS * n_bins]; blocks],
            taken: 0,
        }
    }

    /// Whether every block holds `FIELDS x n_bins` sums: false for sums of an older
    /// snapshot layout, or of a scene with another bin count.
    pub fn fits(&self, n_bins: usize) -> bool {
        self.n_bins == n_bins && self.sums.iter().all(|s| s.len() == FIELDS * n_bins)
    }

    /// Number of snapshots when full.
    pub fn capacity(&self) -> usize {
        self.per_block * self.sums.len()
    }

    /// Whether every block is full.
    pub fn full(&self) -> bool {
        self.taken >= self.capacity()
    }

    /// The block the next snapshot goes to.
    pub fn current(&mut self) -> &mut [f64] {
        let b = (self.taken / self.per_block).min(self.sums.len() - 1);
        &mut self.sums[b]
    }

    /// Marks one more snapshot as added to [`BlockSums::current`].
    pub fn commit(&mut self) {
        self.taken += 1;
    }

    /// Sum over all blocks.
    pub fn total(&self) -> Vec<f64> {
        let mut t = vec![0.0; FIELDS * self.n_bins];
        for b in &self.sums {
            for (x, y) in t.iter_mut().zip(b) {
                *x += y;
            }
        }
        t
    }

    /// Each number that `values(sums, snapshots)` makes of summed snapshots, with its
    /// batch-means standard error: the mean from all snapshots, the error from the spread
    /// of the per-block values (sample standard deviation over sqrt(blocks)).
    pub fn estimates(&self, values: impl Fn(&[f64], usize) -> Vec<f64>) -> Vec<Estimate> {
        let n = self.taken.min(self.capacity());
        let mean = values(&self.total(), n);
        let per_block: Vec<Vec<f64>> = self
            .sums
            .iter()
            .map(|b| values(b, self.per_block))
            .collect();
        let m = per_block.len() as f64;
        mean.iter()
            .enumerate()
            .map(|(c, &mean)| {
                let avg = per_block.iter().map(|v| v[c]).sum::<f64>() / m;
                let var = per_block.iter().map(|v| (v[c] - avg).powi(2)).sum::<f64>() / (m - 1.0);
                Estimate {
                    mean,
                    se: (var / m).sqrt(),
                }
            })
            .collect()
    }
}
