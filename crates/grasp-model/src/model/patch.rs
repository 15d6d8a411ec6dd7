//! Patch geometry: where each element of a contact's grid is and its initial gap.

use crate::model::influence::GridSpec;

/// A rectangular patch of `nx x ny` elements centred on the contact point.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Grid (counts and element sizes).
    pub grid: GridSpec,
    /// Element centres in patch coordinates `(x along t1, y along t2)`, m, row-major
    /// (`k = i ny + j`).
    pub centres_m: Vec<[f64; 2]>,
    /// Initial gap `c_k`, m, at each element centre (model.md; thesis eqs. 14-16).
    pub gap_m: Vec<f64>,
}

impl Patch {
    /// Builds a patch of size `[lx, ly]` m with `[nx, ny]` elements and curvatures
    /// `[1/R1, 1/R2]` (1/m, summed over finger and object along `t1`, `t2`): the initial gap is
    /// the parabolic separation `c = x^2/2 (1/R1) + y^2/2 (1/R2)` (Johnson section 4.1,
    /// eq. 4.4 with principal curvatures).
    pub fn new(size_m: [f64; 2], grid: [usize; 2], curvature_per_m: [f64; 2]) -> Self {
        let (nx, ny) = (grid[0], grid[1]);
        let (hx, hy) = (size_m[0] / nx as f64, size_m[1] / ny as f64);
        let mut centres_m = Vec::with_capacity(nx * ny);
        let mut gap_m = Vec::with_capacity(nx * ny);
        for i in 0..nx {
            let x = (i as f64 + 0.5) * hx - 0.5 * size_m[0];
            for j in 0..ny {
                let y = (j as f64 + 0.5) * hy - 0.5 * size_m[1];
                centres_m.push([x, y]);
                gap_m.push(0.5 * (curvature_per_m[0] * x * x + curvature_per_m[1] * y * y));
            }
        }
        Patch {
            grid: GridSpec { nx, ny, hx, hy },
            centres_m,
            gap_m,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.centres_m.len()
    }

    /// True for a patch without elements.
    pub fn is_empty(&self) -> bool {
        self.centres_m.is_empty()
    }

    /// Element area `A = hx hy`, m^2.
    pub fn element_area_m2(&self) -> f64 {
        self.grid.hx * self.grid.hy
    }

    /// True when element `k` lies on the boundary ring of the patch.
    pub fn on_boundary(&self, k: usize) -> bool {
        let (i, j) = (k / self.grid.ny, k % self.grid.ny);
        i == 0 || j == 0 || i + 1 == self.grid.nx || j + 1 == self.grid.ny
    }
}
