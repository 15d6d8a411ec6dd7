//! The readings of one finger's marker grid: per marker the displacement of the pad's surface
//! at its point relative to the finger's core, m, under the finger's solved element forces,
//! each element's force a uniform traction over its rectangle.
//!
//! The displacement is the finger body's share of the model's own compliance, evaluated at
//! the marker's point (which need not be an element's centre): the exact rectangle integrals
//! of Boussinesq's and Cerruti's surface displacements (`crate::model::influence`, Johnson
//! eqs. 3.22c, 3.86a-c) with the finger's `E`, `nu` alone, the object taken rigid. With
//! `(s_n, s_1, s_2) = C_f f` that share (`s_n` the gap's increase from the finger's side,
//! `s_1`, `s_2` the finger's part of the object-minus-finger tangential displacement), a marker
//! reads `[s_n, -s_1, -s_2]`: the normal component positive when the pad's surface is pushed
//! into the finger (away from the object, along `-n`), the tangential ones the surface's own
//! displacement along `t1`, `t2`. A rigid finger reads 0.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::model::influence::{BlockKernels, GridSpec, PairConstants, RectangleIntegrals};
use crate::model::material::Material;
use crate::scene::sensor_kind::GridLayout;
use crate::solve::solution::ElementSolution;

/// One finger's marker readings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MarkerReadings {
    /// Markers along the grid's sides `[nx, ny]`.
    pub count: [usize; 2],
    /// Each marker's point from the contact point along `t1`, `t2`, m, row-major
    /// (`k = i ny + j`, `i` along the grid's first side).
    pub position_m: Vec<[f64; 2]>,
    /// Each marker's displacement `[normal, t1, t2]`, m, row-major, relative to the finger's
    /// core: `normal` positive when the pad's surface is pushed into the finger (away from
    /// the object, along `-n`); `t1`, `t2` the surface's displacement along them.
    pub displacement_m: Vec<[f64; 3]>,
}

impl MarkerReadings {
    /// The largest tangential displacement `|(u_t1, u_t2)|`, m, and its marker's index.
    pub fn largest_tangential(&self) -> (usize, f64) {
        largest(&self.displacement_m, |u| u[1].hypot(u[2]))
    }

    /// The normal displacement of largest magnitude, m (signed as the readings), and its
    /// marker's index.
    pub fn largest_normal(&self) -> (usize, f64) {
        let (k, _) = largest(&self.displacement_m, |u| u[0].abs());
        (k, self.displacement_m.get(k).map_or(0.0, |u| u[0]))
    }
}

/// The index and value of the largest `size` over `values` (the first on ties; 0 when none).
fn largest(values: &[[f64; 3]], size: impl Fn(&[f64; 3]) -> f64) -> (usize, f64) {
    values
        .iter()
        .enumerate()
        .map(|(k, u)| (k, size(u)))
        .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
}

/// The readings of markers laid out by `layout` over a finger of material `finger` with
/// solved `elements` (their element grid `patch`): per marker, the sum over the loaded
/// elements of the finger's surface influence coefficients at the marker times the element's
/// force (the module's signs).
pub fn read_markers(
    layout: &GridLayout,
    finger: &Material,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> MarkerReadings {
    let position_m = layout.points_m();
    let displacement_m = match finger {
        Material::Rigid => vec![[0.0; 3]; position_m.len()],
        Material::Elastic { .. } => {
            let kernels = BlockKernels::new(patch, &PairConstants::new(finger, &Material::Rigid));
            let loaded = loaded_elements(elements);
            position_m
                .par_iter()
                .map(|p| surface_displacement(*p, &kernels, patch, &loaded))
                .collect()
        }
    };
    MarkerReadings {
        count: layout.count,
        position_m,
        displacement_m,
    }
}

/// The elements of `elements` that carry a force.
pub(crate) fn loaded_elements(elements: &[ElementSolution]) -> Vec<&ElementSolution> {
    elements.iter().filter(|e| e.is_loaded()).collect()
}

/// The pad's surface displacement at `point` (m, along `t1`, `t2`; a marker's reading): the
/// finger's share `s = C_f f` summed over `loaded` (`kernels` the finger's against a rigid
/// object), read as `[s_n, -s_1, -s_2]`. The tangential-from-normal
/// entries are the normal-from-tangential ones at the opposite offset (Betti; the kernels
/// `X / rho^2`, `Y / rho^2` are odd), `-n1`, `-n2` at this offset.
pub(crate) fn surface_displacement(
    point: [f64; 2],
    kernels: &BlockKernels,
    patch: &GridSpec,
    loaded: &[&ElementSolution],
) -> [f64; 3] {
    let mut s = [0.0; 3];
    for e in loaded {
        let r = RectangleIntegrals::for_offset(
            point[0] - e.local_m[0],
            point[1] - e.local_m[1],
            patch.hx,
            patch.hy,
        );
        let [f, g1, g2] = e.force_n();
        let (n1, n2, t12) = (kernels.n1(&r), kernels.n2(&r), kernels.t12(&r));
        s[0] += kernels.nn(&r) * f + n1 * g1 + n2 * g2;
        s[1] += -n1 * f + kernels.t11(&r) * g1 + t12 * g2;
        s[2] += -n2 * f + t12 * g1 + kernels.t22(&r) * g2;
    }
    // `0.0 - x`, not `-x`: a zero reads +0.
    [s[0], 0.0 - s[1], 0.0 - s[2]]
}
