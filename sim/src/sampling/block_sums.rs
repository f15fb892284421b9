//! Snapshot sums grouped into consecutive blocks, for batch-means standard errors of
//! time-correlated samples.
use crate::sampling::snapshot::field::FIELDS;
use serde::{Deserialize, Serialize};

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
}
