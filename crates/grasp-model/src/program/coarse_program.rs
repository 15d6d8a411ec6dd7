//! The same program on grids twice as coarse: the twin a grid continuation solves first
//! (`crate::solver::grid_continuation`), and the maps between the two programs' unknowns.
//!
//! A coarse element is a 2 x 2 block of fine elements (fine element `(i, j)`, `k = i ny + j`,
//! lies in coarse element `(i / 2, j / 2)`), its unknown the block's total force, in the same
//! element force units `Fu` as the fine program (the scales are the fine model's, so the
//! equality rows and their multipliers mean the same in both programs). With the fine forces
//! spread evenly over each block, `x_f = R' x_c / 4`:
//!
//! - `E_c = E_f R' / 4`: a coarse column is the mean of its children's, the scaled wrench of a
//!   unit force at the block's centroid (a wrench is affine in its point of application), so
//!   `E_c x_c = E_f x_f` exactly and `e` is the same;
//! - `q_c = R q_f / 4`: the block's mean gap (and offsets and slip memory);
//! - the cones are the fine finger's, a Tresca radius the sum of its children's (a force);
//! - `P_c` is the coarse patch's own compliance (elements twice as wide), built with the
//!   coarse model (`crate::model::grid_coarsening`).
//!
//! A block left as it is (a finger whose grid is not coarsened, a shared spring) maps one to
//! one.

use std::sync::Arc;

use nalgebra::DMatrix;

use crate::program::cone_program::{ConeProgram, FingerBlock};
use crate::program::cones::finger_cones::FingerCones;

/// How one block's unknowns map between the fine program and its coarse twin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BlockMap {
    /// The block's first unknown in the fine program.
    fine_offset: usize,
    /// Its first unknown in the coarse program.
    coarse_offset: usize,
    /// Unknowns per element.
    dim: usize,
    /// The fine grid, `[nx, ny]` (a shared spring: `[coordinates, 1]`).
    grid: [usize; 2],
    /// 2 when the block's grid is coarsened, 1 when it is kept.
    factor: usize,
}

impl BlockMap {
    fn fine_elements(&self) -> usize {
        self.grid[0] * self.grid[1]
    }

    fn coarse_elements(&self) -> usize {
        (self.grid[0] / self.factor) * (self.grid[1] / self.factor)
    }

    /// The coarse element of fine element `k`.
    fn parent(&self, k: usize) -> usize {
        let ny = self.grid[1];
        let (i, j) = (k / ny, k % ny);
        (i / self.factor) * (ny / self.factor) + j / self.factor
    }

    /// Fine elements per coarse one.
    fn children(&self) -> f64 {
        (self.factor * self.factor) as f64
    }

    /// Calls `f(fine unknown, coarse unknown)` for every fine unknown of the block.
    fn each_pair(&self, mut f: impl FnMut(usize, usize)) {
        let (nf, nc) = (self.fine_elements(), self.coarse_elements());
        for c in 0..self.dim {
            for k in 0..nf {
                f(
                    self.fine_offset + c * nf + k,
                    self.coarse_offset + c * nc + self.parent(k),
                );
            }
        }
    }
}

/// The coarse twin of a program and the maps of its blocks.
#[derive(Debug, Clone)]
pub(crate) struct CoarseProgram {
    /// The coarse program (its data as last restricted from the fine one).
    pub program: ConeProgram,
    maps: Vec<BlockMap>,
}

impl CoarseProgram {
    /// The twin of `fine` whose fingers have grids `grids` (`[nx, ny]`, one per finger
    /// block), each coarsened when its `coarsen` is true (both counts even), its data
    /// restricted from `fine`'s.
    pub(crate) fn new(fine: &ConeProgram, grids: &[[usize; 2]], coarsen: &[bool]) -> Self {
        let mut maps = Vec::with_capacity(fine.blocks.len());
        let mut coarse_offset = 0;
        for (i, b) in fine.blocks.iter().enumerate() {
            let (grid, factor) = match grids.get(i) {
                Some(&g) => (g, if coarsen[i] { 2 } else { 1 }),
                None => ([b.elements, 1], 1),
            };
            let map = BlockMap {
                fine_offset: b.offset,
                coarse_offset,
                dim: 1 + b.n_tangential,
                grid,
                factor,
            };
            coarse_offset += map.coarse_elements() * map.dim;
            maps.push(map);
        }
        let blocks = fine
            .blocks
            .iter()
            .zip(&maps)
            .map(|(b, m)| FingerBlock {
                offset: m.coarse_offset,
                elements: m.coarse_elements(),
                n_tangential: b.n_tangential,
                cone: b.cone.clone(),
            })
            .collect();
        let equality = coarse_equality(&fine.equality, &maps, coarse_offset);
        let program = fine.with_layout(blocks, Arc::new(equality));
        let mut coarse = CoarseProgram { program, maps };
        coarse.restrict(fine);
        coarse
    }

    /// Writes `fine`'s data into the coarse program: the block means of `q`, the same `e`
    /// and cones (Tresca radii summed over each block).
    pub(crate) fn restrict(&mut self, fine: &ConeProgram) {
        let q = &mut self.program.q;
        q.iter_mut().for_each(|v| *v = 0.0);
        for m in &self.maps {
            let share = 1.0 / m.children();
            m.each_pair(|f, c| q[c] += share * fine.q[f]);
        }
        self.program
            .equality_rhs
            .copy_from_slice(&fine.equality_rhs);
        for ((cb, fb), m) in self
            .program
            .blocks
            .iter_mut()
            .zip(&fine.blocks)
            .zip(&self.maps)
        {
            cb.cone = match &fb.cone {
                FingerCones::Tresca { radii } => {
                    let mut sums = vec![0.0; m.coarse_elements()];
                    (0..m.fine_elements()).for_each(|k| sums[m.parent(k)] += radii[k]);
                    FingerCones::Tresca { radii: sums }
                }
                other => other.clone(),
            };
        }
    }

    /// The fine forces of coarse ones: each block's force spread evenly over its children
    /// (`x_f = R' x_c / 4`); the multipliers carry over as they are.
    pub(crate) fn prolong(&self, coarse_x: &[f64], fine_unknowns: usize) -> Vec<f64> {
        let mut x = vec![0.0; fine_unknowns];
        for m in &self.maps {
            let share = 1.0 / m.children();
            m.each_pair(|f, c| x[f] = share * coarse_x[c]);
        }
        x
    }
}

/// `E_c = E_f R' / 4` (module docs): each coarse column the mean of its children's.
fn coarse_equality(fine: &DMatrix<f64>, maps: &[BlockMap], unknowns: usize) -> DMatrix<f64> {
    let rows = fine.nrows();
    let mut e = DMatrix::zeros(rows, unknowns);
    for m in maps {
        let share = 1.0 / m.children();
        m.each_pair(|f, c| {
            for r in 0..rows {
                e[(r, c)] += share * fine[(r, f)];
            }
        });
    }
    e
}
