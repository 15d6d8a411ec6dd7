//! The constraint set of one element and its projection, the building block of the
//! semismooth Newton method ([`crate::solver::native::newton::semismooth_newton`]).
//!
//! For an element with `d` unknowns (`d = 1 + n_tangential`: `(F)`, `(F, G)` or `(F, G1, G2)`,
//! scaled by the element force unit) the projection `pi = Proj_K(v)` onto its set `K` is
//! returned with one element of its generalized (Clarke) Jacobian written as
//! `D = sum_j theta_j d_j d_j'`: orthonormal directions `d_j` and weights `theta_j in [0, 1]`.
//! `theta = 1`: the direction is free (the element moves with `v`); `theta = 0`: fixed (the
//! projection does not move); in between: the tangential direction of a sliding element,
//! which turns with `v`.

use super::cone_friction::project_friction;
use super::cone_nonnegative::project_nonnegative;
use super::cone_tresca::project_tresca;
use super::projection::Projection;

/// The constraint set of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ElementCone {
    /// `F >= 0` (frictionless finger).
    Nonnegative,
    /// `||G|| <= mu F`, the associated Coulomb cone (energy model).
    Friction {
        /// Friction coefficient, > 0.
        mu: f64,
    },
    /// `F >= 0`, `||G|| <= r`: the Tresca disc of a coulomb iterate.
    Tresca {
        /// Radius in element force units, > 0.
        radius: f64,
    },
}

impl ElementCone {
    /// Projects `v` (its first `d` entries) onto the set.
    pub fn project(&self, v: [f64; 3], d: usize) -> Projection {
        match *self {
            ElementCone::Nonnegative => project_nonnegative(v),
            ElementCone::Friction { mu } => project_friction(mu, v, d),
            ElementCone::Tresca { radius } => project_tresca(radius, v, d),
        }
    }
}
