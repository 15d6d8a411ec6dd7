//! The Tresca set of a coulomb iterate: `F >= 0` and `||G|| <= r` with the radius `r` fixed at
//! the previous iterate (model.md, "coulomb"). It is a product: the normal part is the
//! nonnegative ray, the tangential part a disc (an interval when planar). Outside the disc the
//! projection is `r b/||b||`, whose Jacobian fixes the radial direction (weight 0) and, in 3-D,
//! turns the tangential one with weight `r / ||b||`.

use super::conic_rows::ConicRows;
use super::element_set::{ClarabelRow, ClarabelRows, ElementSet, StateMargin};
use super::nonnegative_ray::{contact_margin, NonnegativeRay};
use super::projection::Projection;
use super::symmetric_cones::SymmetricCone;

/// `F >= 0` and `||G|| <= r`: the Tresca set of one coulomb iterate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrescaSet {
    /// The radius `r` in element force units, >= 0 (the exact radius: Clarabel's rows raise
    /// it to a floor, the native solver does not).
    pub radius: f64,
}

impl ElementSet for TrescaSet {
    /// The normal part on the ray, the tangential part on the disc (an interval when planar).
    fn project(&self, v: [f64; 3], d: usize) -> Projection {
        let radius = self.radius;
        let mut p = NonnegativeRay.project(v, d);
        if d == 1 {
            return p;
        }
        let (b1, b2) = (v[1], if d == 3 { v[2] } else { 0.0 });
        let beta = b1.hypot(b2);
        if beta <= radius {
            return p;
        }
        let (h1, h2) = (b1 / beta, b2 / beta);
        p.point[1] = radius * h1;
        p.point[2] = radius * h2;
        p.dirs[1] = [0.0, h1, h2];
        p.dirs[2] = [0.0, -h2, h1];
        p.theta[1] = 0.0;
        p.theta[2] = if d == 3 { radius / beta } else { 0.0 };
        p
    }

    /// Planar: the rays `F`, `r + G`, `r - G`; 3-D: the ray `F` and `(r, G1, G2)` in the
    /// second-order cone.
    fn conic_rows(&self, d: usize) -> ConicRows {
        let (r, z) = (self.radius, [0.0; 3]);
        let ray = Some(SymmetricCone::Nonnegative);
        match d {
            2 => ConicRows {
                g: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], z],
                h: [0.0, r, r, 0.0],
                rows: 3,
                cones: [ray, ray, ray],
            },
            3 => ConicRows {
                g: [[1.0, 0.0, 0.0], z, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                h: [0.0, r, 0.0, 0.0],
                rows: 4,
                cones: [ray, Some(SymmetricCone::SecondOrder), None],
            },
            _ => ConicRows::normal_force(),
        }
    }

    /// `F >= 0` of its own; planar: the pair `r + G >= 0`, `r - G >= 0`; 3-D: `(r, G1, G2)` in
    /// the second-order cone; `r` (in `b`) at least `radius_floor`.
    fn clarabel_rows(&self, d: usize, radius_floor: f64) -> ClarabelRows {
        let r = self.radius.max(radius_floor);
        let row = |a: [f64; 3], b| ClarabelRow {
            a,
            structural_f: false,
            b,
        };
        ClarabelRows {
            normal: true,
            pair: (d == 2).then(|| [row([0.0, -1.0, 0.0], r), row([0.0, 1.0, 0.0], r)]),
            second_order: (d == 3).then(|| {
                [
                    row([0.0; 3], r),
                    row([0.0, -1.0, 0.0], 0.0),
                    row([0.0, 0.0, -1.0], 0.0),
                ]
            }),
        }
    }

    /// The recession cone is the ray times `{0}`: `w_F >= 0`, `w_G` free.
    fn dual_floor(&self, _w_g: f64) -> f64 {
        0.0
    }

    /// The disc's support function, `r ||w_G||` (the radius at least `radius_floor`).
    fn support(&self, w_g: f64, radius_floor: f64) -> f64 {
        self.radius.max(radius_floor) * w_g
    }

    /// The nearer of the contact / separation boundary and the disc's rim (the latter only for
    /// an element in contact with friction unknowns).
    fn state_margin(&self, v: [f64; 3], d: usize) -> StateMargin {
        let contact = contact_margin(v);
        let beta = v[1].hypot(if d == 3 { v[2] } else { 0.0 });
        let slip = StateMargin {
            distance: (beta - self.radius).abs(),
            stick_slip: true,
        };
        if d == 1 || slip.distance >= contact.distance || v[0] <= 0.0 {
            contact
        } else {
            slip
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::cones::projection::assert_jacobian_matches_differences;

    fn project_tresca(radius: f64, v: [f64; 3], d: usize) -> Projection {
        TrescaSet { radius }.project(v, d)
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        assert_jacobian_matches_differences(|v| project_tresca(0.6, v, 3), [0.5, 0.8, -0.9]);
    }

    #[test]
    fn planar_clips_to_the_interval() {
        let p = project_tresca(0.5, [1.0, -2.0, 0.0], 2);
        assert_eq!(p.point[1], -0.5);
        assert_eq!(p.theta[1], 0.0);
    }
}
