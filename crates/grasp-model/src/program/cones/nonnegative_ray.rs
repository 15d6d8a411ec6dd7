//! The nonnegative ray `F >= 0`: a frictionless element's normal force (thesis eq. 20, the
//! contact condition without friction).
//!
//! Its projection clips `F` at 0; its dual is itself; it is one row of the interior point's
//! nonnegative cone and of Clarabel's.

use super::conic_rows::ConicRows;
use super::element_set::{ClarabelRows, ElementSet, StateMargin};
use super::projection::Projection;

/// `F >= 0` (the tangential unknowns, if any, are unconstrained by it; a frictionless finger
/// has none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NonnegativeRay;

impl ElementSet for NonnegativeRay {
    /// `v[0]` itself with the direction free, or 0 with it fixed.
    fn project(&self, v: [f64; 3], _d: usize) -> Projection {
        let mut p = Projection::inside(v);
        if v[0] < 0.0 {
            p.point[0] = 0.0;
            p.theta[0] = 0.0;
        }
        p
    }

    /// One row `s = F` in the nonnegative cone.
    fn conic_rows(&self, _d: usize) -> ConicRows {
        ConicRows::normal_force()
    }

    /// Its own `F >= 0` row.
    fn clarabel_rows(&self, _d: usize, _radius_floor: f64) -> ClarabelRows {
        ClarabelRows {
            normal: true,
            pair: None,
            second_order: None,
        }
    }

    /// The ray is self-dual: `w_F >= 0`.
    fn dual_floor(&self, _w_g: f64) -> f64 {
        0.0
    }

    /// A cone: no bounded part.
    fn support(&self, _w_g: f64, _radius_floor: f64) -> f64 {
        0.0
    }

    /// The one boundary is contact / separation at `v[0] = 0`.
    fn state_margin(&self, v: [f64; 3], _d: usize) -> StateMargin {
        contact_margin(v)
    }
}

/// The distance of `v` from the contact / separation boundary `v[0] = 0` (shared by the sets
/// whose normal part is the ray).
pub(crate) fn contact_margin(v: [f64; 3]) -> StateMargin {
    StateMargin {
        distance: v[0].abs(),
        stick_slip: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clips_negative_forces() {
        let project = |v| NonnegativeRay.project(v, 1);
        assert_eq!(project([-2.0, 0.0, 0.0]).point[0], 0.0);
        assert_eq!(project([-2.0, 0.0, 0.0]).theta[0], 0.0);
        assert_eq!(project([3.0, 0.0, 0.0]).point[0], 3.0);
        assert_eq!(project([3.0, 0.0, 0.0]).theta[0], 1.0);
    }
}
