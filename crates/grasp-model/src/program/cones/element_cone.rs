//! The constraint set of one element, by its law: one enum ([`ElementCone`]) whose variants
//! are the sets of the cone files, each answering the verbs of
//! [`super::element_set::ElementSet`] in its own file. Adding a set is a file with its
//! `ElementSet` implementation, a variant here and its storage in `super::finger_cones`.

use super::conic_rows::ConicRows;
use super::element_set::{ClarabelRows, ElementSet, StateMargin};
use super::free_space::FreeSpace;
use super::friction_cone::FrictionCone;
use super::nonnegative_ray::NonnegativeRay;
use super::projection::Projection;
use super::tresca_set::TrescaSet;

/// The constraint set of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ElementCone {
    /// `F >= 0` (frictionless finger).
    Nonnegative(NonnegativeRay),
    /// `||G|| <= mu F`, the associated Coulomb cone (energy model).
    Friction(FrictionCone),
    /// `F >= 0`, `||G|| <= r`: the Tresca set of a coulomb iterate.
    Tresca(TrescaSet),
    /// No constraint: a shared spring's load coordinate.
    Free(FreeSpace),
}

impl ElementCone {
    /// The variant's set, for its verbs.
    fn set(&self) -> &dyn ElementSet {
        match self {
            ElementCone::Nonnegative(s) => s,
            ElementCone::Friction(s) => s,
            ElementCone::Tresca(s) => s,
            ElementCone::Free(s) => s,
        }
    }
}

/// Every verb goes to the variant's set; the projection, which every Newton step calls for
/// every element, without the indirection of [`ElementCone::set`].
impl ElementSet for ElementCone {
    fn project(&self, v: [f64; 3], d: usize) -> Projection {
        match self {
            ElementCone::Nonnegative(s) => s.project(v, d),
            ElementCone::Friction(s) => s.project(v, d),
            ElementCone::Tresca(s) => s.project(v, d),
            ElementCone::Free(s) => s.project(v, d),
        }
    }

    fn conic_rows(&self, d: usize) -> ConicRows {
        self.set().conic_rows(d)
    }

    fn clarabel_rows(&self, d: usize, radius_floor: f64) -> ClarabelRows {
        self.set().clarabel_rows(d, radius_floor)
    }

    fn dual_floor(&self, w_g: f64) -> f64 {
        self.set().dual_floor(w_g)
    }

    fn dual_contains(&self, w_f: f64, w_g: f64, slack: f64) -> bool {
        self.set().dual_contains(w_f, w_g, slack)
    }

    fn support(&self, w_g: f64, radius_floor: f64) -> f64 {
        self.set().support(w_g, radius_floor)
    }

    fn state_margin(&self, v: [f64; 3], d: usize) -> StateMargin {
        self.set().state_margin(v, d)
    }
}
