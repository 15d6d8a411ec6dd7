//! Each element's constraint set written as conic rows for the interior-point method:
//! `s_k = G_k x_k + h_k` in a product of cones ([`super::interior_cones`]), `x_k = (F, G1, G2)`
//! truncated to `dim`:
//!
//! | set | rows | `G_k` | `h_k` | cones |
//! |---|---|---|---|---|
//! | `F >= 0` | 1 | `[1]` | `0` | ray |
//! | associated, planar | 2 | `[[mu, 1], [mu, -1]]` | `0` | ray, ray |
//! | associated, 3-D | 3 | `diag(mu, 1, 1)` | `0` | second-order |
//! | Tresca, planar | 3 | `[[1, 0], [0, 1], [0, -1]]` | `(0, r, r)` | ray x 3 |
//! | Tresca, 3-D | 4 | `[[1, 0, 0], [0, 0, 0], [0, 1, 0], [0, 0, 1]]` | `(0, r, 0, 0)` | ray, second-order |

use crate::program::cone_program::BlockCone;

use super::interior_cones::Cone;

/// The conic rows of one element (at most 4 rows, at most 2 cones).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElementRows {
    /// `G_k`, rows x `dim` (leading part used).
    pub g: [[f64; 3]; 4],
    /// `h_k`.
    pub h: [f64; 4],
    /// Number of rows.
    pub rows: usize,
    /// The cones over the rows, in order.
    pub cones: [Option<Cone>; 3],
}

impl ElementRows {
    /// The rows of element `k` with `dim` unknowns under `cone`.
    pub fn new(cone: &BlockCone, k: usize, dim: usize) -> Self {
        use Cone::{Nonnegative as N, SecondOrder as Q};
        let z = [0.0; 3];
        match (cone, dim) {
            (BlockCone::Friction { mu }, 2) => ElementRows {
                g: [[*mu, 1.0, 0.0], [*mu, -1.0, 0.0], z, z],
                h: [0.0; 4],
                rows: 2,
                cones: [Some(N), Some(N), None],
            },
            (BlockCone::Friction { mu }, 3) => ElementRows {
                g: [[*mu, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], z],
                h: [0.0; 4],
                rows: 3,
                cones: [Some(Q), None, None],
            },
            (BlockCone::Tresca { radii }, 2) => ElementRows {
                g: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], z],
                h: [0.0, radii[k], radii[k], 0.0],
                rows: 3,
                cones: [Some(N), Some(N), Some(N)],
            },
            (BlockCone::Tresca { radii }, 3) => ElementRows {
                g: [[1.0, 0.0, 0.0], z, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                h: [0.0, radii[k], 0.0, 0.0],
                rows: 4,
                cones: [Some(N), Some(Q), None],
            },
            _ => ElementRows {
                g: [[1.0, 0.0, 0.0], z, z, z],
                h: [0.0; 4],
                rows: 1,
                cones: [Some(N), None, None],
            },
        }
    }

    /// The cones with their first row.
    pub fn cone_rows(&self) -> impl Iterator<Item = (Cone, usize)> + '_ {
        let mut row = 0;
        self.cones.iter().flatten().map(move |&c| {
            let r = row;
            row += c.dim();
            (c, r)
        })
    }

    /// `out = G_k x_k + h_k`.
    pub fn value(&self, x: [f64; 3], dim: usize, out: &mut [f64]) {
        for (r, o) in out.iter_mut().enumerate().take(self.rows) {
            *o = self.h[r] + (0..dim).map(|c| self.g[r][c] * x[c]).sum::<f64>();
        }
    }

    /// `G_k x_k` (without `h`).
    pub fn linear(&self, x: [f64; 3], dim: usize, out: &mut [f64]) {
        for (r, o) in out.iter_mut().enumerate().take(self.rows) {
            *o = (0..dim).map(|c| self.g[r][c] * x[c]).sum::<f64>();
        }
    }

    /// `G_k' u` over `dim` components.
    pub fn transpose(&self, u: &[f64], dim: usize) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate().take(dim) {
            *o = (0..self.rows).map(|r| self.g[r][c] * u[r]).sum();
        }
        out
    }
}
