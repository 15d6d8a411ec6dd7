//! What every element set of the program answers, one trait ([`ElementSet`]) with the same
//! verbs in every cone file (`nonnegative_ray`, `friction_cone`, `tresca_set`): its projection
//! (the semismooth Newton method), its conic rows (the interior-point method's barrier), its
//! rows in Clarabel's form, its dual test and support term (certificates of infeasibility) and
//! the distance of a point from the pieces of its projection (the solution's derivative).
//!
//! An element has `d = 1 + n_tangential` unknowns, `x_k = (F, G1[, G2])`, scaled by the element
//! force unit `Fu`; every method reads the first `d` entries of its arrays.

use super::conic_rows::ConicRows;
use super::projection::Projection;

/// How close a projection input is to a change of the element's state, and which change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StateMargin {
    /// Distance of the projection input `x_k - gamma y_k` from the nearest boundary between
    /// the pieces of the projection (scaled forces).
    pub distance: f64,
    /// True when that boundary is between stick and slip; false for contact / separation.
    pub stick_slip: bool,
}

/// One row of Clarabel's form `A x + s = b`, `s` in a cone: the entries of `A` on the
/// element's unknowns `(F, G1, G2)` and the row's `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ClarabelRow {
    /// Entries of `A` on `(F, G1, G2)` (an entry of 0 is left out unless structural).
    pub a: [f64; 3],
    /// True when the entry on `F` is kept even when zero (a friction coefficient, which later
    /// solves may change in place).
    pub structural_f: bool,
    /// The row's right-hand side (a Tresca radius, element force units).
    pub b: f64,
}

/// An element set in Clarabel's cones: its own `F >= 0` row (nonnegative cone), the planar
/// pair of nonnegative rows bounding `G`, or one second-order cone of dimension 3 (scalar
/// first). The assembler (`crate::solver::clarabel`) places each kind in its group of rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ClarabelRows {
    /// `-F + s = 0`, `s >= 0`: the normal force's own row, when the set needs one.
    pub normal: bool,
    /// Two nonnegative rows bounding a planar element's `G`.
    pub pair: Option<[ClarabelRow; 2]>,
    /// A 3-D element's second-order cone `(s0, s1, s2)`, `s0 >= ||(s1, s2)||`.
    pub second_order: Option<[ClarabelRow; 3]>,
}

/// The verbs every element set implements (one file per set).
pub(crate) trait ElementSet {
    /// The projection of `v` (first `d` entries) onto the set, with one element of its
    /// generalised (Clarke) Jacobian (Qi & Sun's semismooth Newton method).
    fn project(&self, v: [f64; 3], d: usize) -> Projection;

    /// The set as conic rows `s = G x_k + h` in the interior-point method's symmetric cones
    /// (`super::symmetric_cones`): the barrier that method uses for it.
    fn conic_rows(&self, d: usize) -> ConicRows;

    /// The set's rows in Clarabel's form, Tresca radii raised to at least `radius_floor`
    /// (element force units).
    fn clarabel_rows(&self, d: usize, radius_floor: f64) -> ClarabelRows;

    /// The smallest normal part `w_F` of a vector `w = (w_F, w_G)` in the dual of the set's
    /// recession cone, given `||w_G||` (Farkas' lemma: the dual test of a certificate of
    /// infeasibility).
    fn dual_floor(&self, w_g: f64) -> f64;

    /// True when `w = (w_F, w_G)` (`w_G` given by its norm) lies in the dual of the set's
    /// recession cone, to within `slack`.
    fn dual_contains(&self, w_f: f64, w_g: f64, slack: f64) -> bool {
        w_f >= self.dual_floor(w_g) - slack
    }

    /// The support term of the set's bounded part at `w`, `sup_{G in the set} -w_G'G`, given
    /// `||w_G||`, radii raised to at least `radius_floor` (0 for a cone).
    fn support(&self, w_g: f64, radius_floor: f64) -> f64;

    /// The distance of the projection input `v` from the boundaries between the pieces of the
    /// projection, and which boundary is nearest.
    fn state_margin(&self, v: [f64; 3], d: usize) -> StateMargin;
}
