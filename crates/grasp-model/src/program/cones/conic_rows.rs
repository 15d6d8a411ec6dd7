//! An element set written as conic rows for the interior-point method: `s_k = G_k x_k + h_k` in
//! a product of symmetric cones ([`super::symmetric_cones`]), `x_k = (F, G1, G2)` truncated to
//! `dim`. Each set's file writes its own rows ([`super::element_set::ElementSet::conic_rows`]):
//!
//! | set | rows | `G_k` | `h_k` | cones |
//! |---|---|---|---|---|
//! | `F >= 0` | 1 | `[1]` | `0` | ray |
//! | associated, planar | 2 | `[[mu, 1], [mu, -1]]` | `0` | ray, ray |
//! | associated, 3-D | 3 | `diag(mu, 1, 1)` | `0` | second-order |
//! | Tresca, planar | 3 | `[[1, 0], [0, 1], [0, -1]]` | `(0, r, r)` | ray x 3 |
//! | Tresca, 3-D | 4 | `[[1, 0, 0], [0, 0, 0], [0, 1, 0], [0, 0, 1]]` | `(0, r, 0, 0)` | ray, second-order |

use super::symmetric_cones::SymmetricCone;

/// The conic rows of one element (at most 4 rows, at most 3 cones).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ConicRows {
    /// `G_k`, rows x `dim` (leading part used).
    pub g: [[f64; 3]; 4],
    /// `h_k`.
    pub h: [f64; 4],
    /// Number of rows.
    pub rows: usize,
    /// The cones over the rows, in order.
    pub cones: [Option<SymmetricCone>; 3],
}

impl ConicRows {
    /// The one row `s = F` in the nonnegative ray (a normal force alone).
    pub fn normal_force() -> Self {
        ConicRows {
            g: [[1.0, 0.0, 0.0], [0.0; 3], [0.0; 3], [0.0; 3]],
            h: [0.0; 4],
            rows: 1,
            cones: [Some(SymmetricCone::Nonnegative), None, None],
        }
    }

    /// The cones with their first row.
    pub fn cone_rows(&self) -> impl Iterator<Item = (SymmetricCone, usize)> + '_ {
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
