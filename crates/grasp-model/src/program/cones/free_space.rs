//! The whole space: the set of a shared spring's load coordinates (a hand's base wrench, a
//! servo's force; [`crate::model::shared_spring`]), which no contact condition bounds. Its
//! unknowns only carry the spring's complementary energy and are tied to the fingers' forces
//! by equality rows.
//!
//! Its projection is the identity; it has no conic rows and no Clarabel rows (free
//! variables); the dual of its recession cone is `{0}`; it has no state to change.

use super::conic_rows::ConicRows;
use super::element_set::{ClarabelRows, ElementSet, StateMargin};
use super::projection::Projection;

/// `R^d`: no constraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FreeSpace;

impl ElementSet for FreeSpace {
    /// `v` itself, every direction free.
    fn project(&self, v: [f64; 3], _d: usize) -> Projection {
        Projection::inside(v)
    }

    /// No rows.
    fn conic_rows(&self, _d: usize) -> ConicRows {
        ConicRows {
            g: [[0.0; 3]; 4],
            h: [0.0; 4],
            rows: 0,
            cones: [None, None, None],
        }
    }

    /// No rows: a free variable.
    fn clarabel_rows(&self, _d: usize, _radius_floor: f64) -> ClarabelRows {
        ClarabelRows {
            normal: false,
            pair: None,
            second_order: None,
        }
    }

    /// The dual of the whole space is `{0}`, which no floor alone describes: membership is
    /// [`ElementSet::dual_contains`]'s test. The floor of `{0}`'s normal part is 0.
    fn dual_floor(&self, _w_g: f64) -> f64 {
        0.0
    }

    /// Only `w = 0` (within `slack`) is in the dual of the whole space.
    fn dual_contains(&self, w_f: f64, w_g: f64, slack: f64) -> bool {
        w_f.abs() <= slack && w_g <= slack
    }

    /// A cone (the whole space): no bounded part.
    fn support(&self, _w_g: f64, _radius_floor: f64) -> f64 {
        0.0
    }

    /// No boundary: the projection has one piece.
    fn state_margin(&self, _v: [f64; 3], _d: usize) -> StateMargin {
        StateMargin {
            distance: f64::INFINITY,
            stick_slip: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_projection_is_the_identity_with_every_direction_free() {
        let p = FreeSpace.project([-2.0, 3.0, 0.5], 3);
        assert_eq!(p.point, [-2.0, 3.0, 0.5]);
        assert_eq!(p.theta, [1.0; 3]);
        assert_eq!(FreeSpace.conic_rows(1).rows, 0);
        assert!(FreeSpace.dual_contains(1e-12, 0.0, 1e-9));
        assert!(!FreeSpace.dual_contains(1e-3, 0.0, 1e-9));
        assert!(!FreeSpace.dual_contains(0.0, 1e-3, 1e-9));
    }
}
