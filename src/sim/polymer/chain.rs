//! A polymer as the integrator holds it: positions, the cell list, the noise key and the
//! scratch buffers of the force passes.

use super::params::PolymerParams;
use crate::geometry::cells::CellList;

/// A polymer and its integrator state.
#[derive(Clone, Debug)]
pub struct Polymer {
    pub(super) params: PolymerParams,
    pub(super) positions: Vec<[f64; 3]>,
    pub(super) forces: Vec<[f64; 3]>,
    pub(super) chain_of: Vec<u32>,
    pub(super) extra_bonds: Vec<(u32, u32)>,
    pub(super) extra_bond: (f64, f64),
    pub(super) cells: CellList,
    pub(super) noise_key: [u32; 2],
    pub(super) steps_taken: u64,
    pub(super) time: f64,
    pub(super) scratch: Scratch,
}

/// Work buffers of the force evaluation, kept between steps.
#[derive(Clone, Debug, Default)]
pub(super) struct Scratch {
    /// Pair forces by slot of the cell list, from the pairs found in the slot's own plane.
    pub(super) own: Vec<[f64; 3]>,
    /// Pair forces by slot, from the pairs found in the plane below the slot's.
    pub(super) spill: Vec<[f64; 3]>,
    /// Per bead `i`: the force of the bond `(i, i + 1)` on `i`, and its energy.
    pub(super) bonds: Vec<[f64; 4]>,
    /// Per bead `i`: the forces of the angle centred on `i` on beads `i - 1`, `i`, `i + 1`,
    /// and its energy.
    pub(super) angles: Vec<[f64; 10]>,
}

/// A plane's force buffers: its own slots, and the next plane's slots it spills into.
pub(super) type PlaneBuffers<'a> = (&'a mut [[f64; 3]], &'a mut [[f64; 3]]);

/// The radius of gyration of `positions`.
pub fn radius_of_gyration(positions: &[[f64; 3]]) -> f64 {
    let n = positions.len() as f64;
    if positions.is_empty() {
        return 0.0;
    }
    let mut centre = [0.0; 3];
    for p in positions {
        for k in 0..3 {
            centre[k] += p[k] / n;
        }
    }
    let sum: f64 = positions
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - centre[k]).powi(2)).sum::<f64>())
        .sum();
    (sum / n).sqrt()
}
