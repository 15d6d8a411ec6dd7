//! The wrench directions only the force-controlled fingers' normal forces can balance: a
//! disturbance with a component along one of them has no equilibrium at any magnitude, since
//! those forces' totals are commanded (a push along the squeeze axis of two force-controlled
//! pads, say). Found once per model by linear algebra, they spare the margins' search the
//! solve that would certify the same.
//!
//! A wrench-space vector `y` (scaled equilibrium coordinates) is fixed by the loads when
//! `y' e_j = 0` for the column `e_j` of every unknown but the force-controlled fingers'
//! normal forces, and `y' e_k` is the same for every element `k` of each force-controlled
//! finger `i`, `c_i`: then `y' E x = sum_i c_i P_i` whatever the contact forces, and a
//! disturbance `s d` needs `s y' d = 0`. Such `y` are the directions the columns of the free
//! unknowns and the differences of a force-controlled finger's normal columns leave out.

use nalgebra::{DMatrix, Vector3};

use crate::model::equilibrium::RowReduction;
use crate::model::grasp_model::{Control, GraspModel};

/// A disturbance is judged unresisted by the loads when its component along the fixed
/// directions is at least this fraction of its norm (the axis directions' are 0 or 1). Then at
/// the smallest magnitude the search tries, `1e-6` of the load scale, the commanded totals
/// would be off by at least `1e-8` of it, far above the solves' tolerance (`1e-10` of it):
/// every solve would report no equilibrium. Smaller components are left to the solves.
const FIXED_FRACTION: f64 = 1e-2;

/// The directions fixed by the commanded loads of one model (columns; none without
/// force-controlled fingers or when the free unknowns resist every direction).
pub(crate) struct LoadFixedDirections {
    fixed: DMatrix<f64>,
}

impl LoadFixedDirections {
    /// No fixed direction (before a model is known).
    pub(crate) fn none() -> Self {
        LoadFixedDirections {
            fixed: DMatrix::zeros(0, 0),
        }
    }

    /// The fixed directions of `model` (module docs).
    pub(crate) fn of(model: &GraspModel) -> Self {
        let mut cols: Vec<Vec<f64>> = Vec::new();
        for (i, f) in model.fingers.iter().enumerate() {
            let commanded = matches!(f.control, Control::NormalLoad { .. });
            for c in 0..=f.n_tangential {
                let first = model.equilibrium.apply(&model.unit_wrench(i, 0, c));
                for k in 0..f.patch.len() {
                    let col = model.equilibrium.apply(&model.unit_wrench(i, k, c));
                    match (commanded && c == 0, k) {
                        (true, 0) => {}
                        (true, _) => {
                            cols.push(col.iter().zip(&first).map(|(a, b)| a - b).collect())
                        }
                        (false, _) => cols.push(col),
                    }
                }
            }
        }
        let rows = model.equilibrium.rows();
        let fixed = match cols.is_empty() {
            // Nothing but single-element commanded fingers: every direction is fixed.
            true => DMatrix::identity(rows, rows),
            false => RowReduction::new(&DMatrix::from_fn(rows, cols.len(), |r, c| cols[c][r])).null,
        };
        LoadFixedDirections { fixed }
    }

    /// Whether a disturbance of force `force` at the centre of mass and couple `torque` (any
    /// units, one magnitude) has a component along the fixed directions of at least
    /// [`FIXED_FRACTION`] of its norm, so that no magnitude above zero has an equilibrium.
    pub(crate) fn fixes(
        &self,
        model: &GraspModel,
        force: &Vector3<f64>,
        torque: &Vector3<f64>,
    ) -> bool {
        let w = model
            .equilibrium
            .apply(&model.wrench_at_center_of_mass(force, torque));
        if self.fixed.nrows() != w.len() {
            return false;
        }
        let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        let along = (0..self.fixed.ncols())
            .map(|c| (0..w.len()).map(|r| self.fixed[(r, c)] * w[r]).sum::<f64>())
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
        norm > 0.0 && along >= FIXED_FRACTION * norm
    }
}
