//! The readings of one finger's taxel grid: per taxel the three-axis force (normal, `t1`,
//! `t2`, N) that crosses its square at the grid's depth under the finger's solved element
//! forces, each element's force a uniform traction over its rectangle.
//!
//! At depth `d > 0` the force is the taxel's integral of the traction at depth (Love 1929 and
//! Cerruti over each element's rectangle, exact: `crate::model::influence_at_depth`),
//! integrated over the taxel by composite Gauss-Legendre quadrature
//! (`super::taxel_grid::TaxelGrid::quadrature`). At `d = 0` each element's force is binned
//! onto the taxels by the area they share, exactly.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::OutOfMemory;
use crate::model::influence::GridSpec;
use crate::model::influence_at_depth::{
    overlap_area_m2, reading_per_area_at_depth, ElementOffset, RotatedSquare,
};
use crate::sensors::taxel_grid::{QuadraturePoint, TaxelGrid};
use crate::sensors::taxel_lattice::taxels_on_lattice;
use crate::sensors::taxel_matrix::taxels_by_matrix;
use crate::solve::solution::ElementSolution;

/// One finger's taxel readings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaxelReadings {
    /// The finger's name.
    pub finger: String,
    /// Taxels along the grid's sides `[nx, ny]`.
    pub count: [usize; 2],
    /// Depth of the taxels below the pad's surface, m.
    pub depth_m: f64,
    /// Side of each taxel, m.
    pub size_m: f64,
    /// Each taxel's centre from the contact point along `t1`, `t2`, m, row-major
    /// (`k = i ny + j`, `i` along the grid's first side).
    pub centre_m: Vec<[f64; 2]>,
    /// Each taxel's force `[normal, t1, t2]`, N, row-major: the force crossing its square,
    /// signed as the element forces (normal along `n`, into the object; the whole plane at
    /// any depth carries the finger's resultant).
    pub force_n: Vec<[f64; 3]>,
}

impl TaxelReadings {
    /// Sum of the taxels' normal forces, N.
    pub fn total_normal_n(&self) -> f64 {
        self.force_n.iter().map(|f| f[0]).sum()
    }

    /// Sum of the taxels' shear forces `[t1, t2]`, N.
    pub fn total_shear_n(&self) -> [f64; 2] {
        let t1 = self.force_n.iter().map(|f| f[1]).sum();
        let t2 = self.force_n.iter().map(|f| f[2]).sum();
        [t1, t2]
    }

    /// The largest taxel force magnitude `|(Fn, Ft1, Ft2)|`, N, and its taxel's index.
    pub fn largest(&self) -> (usize, f64) {
        let norm = |f: &[f64; 3]| (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        self.force_n
            .iter()
            .enumerate()
            .map(|(k, f)| (k, norm(f)))
            .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
    }
}

/// The readings of `grid` over a finger's solved `elements` (their element grid `patch`),
/// named `finger`, the cheaper way: on the element lattice as a convolution
/// (`super::taxel_lattice`) when the grid lies on it (`TaxelGridSpec::lattice`), else at depth
/// by a kept taxel-by-element matrix (`super::taxel_matrix`) when it fits, else
/// [`read_taxels`]; the three are the same sums regrouped. [`OutOfMemory`] when the lattice's
/// table cannot be allocated.
pub fn read_taxels_fastest(
    finger: &str,
    grid: &TaxelGrid,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> Result<TaxelReadings, OutOfMemory> {
    let force_n = match grid.spec.lattice(&patch.element_grid()) {
        Some(lattice) => taxels_on_lattice(&grid.spec, &lattice, patch, elements)?,
        None => match taxels_by_matrix(grid, patch, elements) {
            Some(force_n) => force_n,
            None => return Ok(read_taxels(finger, grid, patch, elements)),
        },
    };
    Ok(TaxelReadings {
        finger: finger.to_string(),
        count: grid.spec.count,
        depth_m: grid.spec.depth_m,
        size_m: grid.spec.size_m,
        centre_m: grid.squares().iter().map(|s| s.centre_m).collect(),
        force_n,
    })
}

/// The readings of `grid` over a finger's solved `elements` (their element grid `patch`),
/// named `finger`, taxel by taxel: at depth, Love 1929 / Cerruti (Johnson 3.2-3.3, 3.6) per
/// element integrated over each taxel by the grid's quadrature; at depth 0, the element forces
/// binned by area.
pub fn read_taxels(
    finger: &str,
    grid: &TaxelGrid,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> TaxelReadings {
    let squares = grid.squares();
    let depth_m = grid.spec.depth_m;
    let quadrature = grid.quadrature();
    let force_n = squares
        .par_iter()
        .map(|sq| match depth_m > 0.0 {
            true => taxel_at_depth(sq, &quadrature, depth_m, patch, elements),
            false => taxel_on_surface(sq, patch, elements),
        })
        .collect();
    TaxelReadings {
        finger: finger.to_string(),
        count: grid.spec.count,
        depth_m,
        size_m: grid.spec.size_m,
        centre_m: squares.iter().map(|s| s.centre_m).collect(),
        force_n,
    }
}

/// One taxel's force at depth `depth_m`: `sum_q w_q sum_e K(x_q - x_e) f_e`.
fn taxel_at_depth(
    sq: &RotatedSquare,
    quadrature: &[QuadraturePoint],
    depth_m: f64,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> [f64; 3] {
    let (sin, cos) = sq.angle_rad.sin_cos();
    let loaded: Vec<&ElementSolution> = elements.iter().filter(|e| e.is_loaded()).collect();
    let mut out = [0.0; 3];
    for q in quadrature {
        let [u, v] = q.offset_m;
        let point = [
            sq.centre_m[0] + u * cos - v * sin,
            sq.centre_m[1] + u * sin + v * cos,
        ];
        for e in &loaded {
            let offset = ElementOffset {
                offset_m: [point[0] - e.local_m[0], point[1] - e.local_m[1]],
                side_m: [patch.hx, patch.hy],
            };
            let k = reading_per_area_at_depth(&offset, depth_m);
            let f = e.force_n();
            for (r, row) in k.iter().enumerate() {
                out[r] += q.weight_m2 * (row[0] * f[0] + row[1] * f[1] + row[2] * f[2]);
            }
        }
    }
    out
}

/// One taxel's force on the surface: each element's force times the share of its area the
/// taxel covers.
fn taxel_on_surface(
    sq: &RotatedSquare,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> [f64; 3] {
    let corners = sq.corners_m();
    let area = patch.hx * patch.hy;
    let reach = sq.half_side_m * std::f64::consts::SQRT_2;
    let mut out = [0.0; 3];
    for e in elements {
        let [cx, cy] = e.local_m;
        let near = (cx - sq.centre_m[0]).abs() <= reach + patch.hx / 2.0
            && (cy - sq.centre_m[1]).abs() <= reach + patch.hy / 2.0;
        if !near {
            continue;
        }
        let lo = [cx - patch.hx / 2.0, cy - patch.hy / 2.0];
        let hi = [cx + patch.hx / 2.0, cy + patch.hy / 2.0];
        let share = overlap_area_m2(lo, hi, &corners) / area;
        let f = e.force_n();
        for r in 0..3 {
            out[r] += share * f[r];
        }
    }
    out
}
