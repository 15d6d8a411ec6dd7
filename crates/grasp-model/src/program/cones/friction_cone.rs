//! The associated Coulomb cone `K_mu = {(F, G): ||G|| <= mu F}` (model.md, "The grasp
//! program"; thesis eqs. 21-24 planar, 27 in 3-D), with `G` of dimension 1 (planar) or 2.
//!
//! Its dual cone is `{(u, w): u >= mu ||w||}` and its polar `{(a, b): mu ||b|| <= -a}`. For
//! `v = (a, b)`, `beta = ||b||`:
//!
//! - `beta <= mu a`: `v` is in the cone (stick): `Proj(v) = v`, Jacobian `I`;
//! - `mu beta <= -a`: `v` is in the polar cone (separation): `Proj(v) = 0`, Jacobian `0`;
//! - otherwise (slip) the projection onto the boundary ray through `b`:
//!   `Proj(v) = s (1, mu b/beta)`, `s = (a + mu beta) / (1 + mu^2)`, whose Jacobian has the ray
//!   direction `e = (1, mu bh)/sqrt(1 + mu^2)` with weight 1, the cone normal
//!   `n = (mu, -bh)/sqrt(1 + mu^2)` with weight 0 and, in 3-D, the tangential direction
//!   `t = (0, bh_perp)` with weight `s mu / beta` (in (0, 1) in this case): the slip direction
//!   turns with `b`.

use super::conic_rows::ConicRows;
use super::element_set::{ClarabelRow, ClarabelRows, ElementSet, StateMargin};
use super::projection::Projection;
use super::symmetric_cones::SymmetricCone;

/// The associated Coulomb cone `||G|| <= mu F` of the energy model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrictionCone {
    /// Friction coefficient frozen for this solve, > 0.
    pub mu: f64,
}

impl ElementSet for FrictionCone {
    /// The three regions of the module docs: stick (inside), separation (polar), slip (the
    /// boundary ray through `b`).
    fn project(&self, v: [f64; 3], d: usize) -> Projection {
        let mu = self.mu;
        let a = v[0];
        let (b1, b2) = (v[1], if d == 3 { v[2] } else { 0.0 });
        let beta = b1.hypot(b2);
        if beta <= mu * a {
            return Projection::inside(v);
        }
        if mu * beta <= -a {
            return Projection {
                point: [0.0; 3],
                dirs: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                theta: [0.0; 3],
            };
        }
        // Slip: beta > 0 here (beta = 0 would need a < 0 and a > 0).
        let (h1, h2) = (b1 / beta, b2 / beta);
        let norm = (1.0 + mu * mu).sqrt();
        let s = (a + mu * beta) / (1.0 + mu * mu);
        let e = [1.0 / norm, mu * h1 / norm, mu * h2 / norm];
        let n = [mu / norm, -h1 / norm, -h2 / norm];
        let t = [0.0, -h2, h1];
        Projection {
            point: [s, s * mu * h1, s * mu * h2],
            dirs: [e, n, t],
            theta: [1.0, 0.0, if d == 3 { s * mu / beta } else { 0.0 }],
        }
    }

    /// Planar: the two rays `mu F + G >= 0`, `mu F - G >= 0`; 3-D: `(mu F, G1, G2)` in the
    /// second-order cone.
    fn conic_rows(&self, d: usize) -> ConicRows {
        let (mu, z) = (self.mu, [0.0; 3]);
        match d {
            2 => ConicRows {
                g: [[mu, 1.0, 0.0], [mu, -1.0, 0.0], z, z],
                h: [0.0; 4],
                rows: 2,
                cones: [
                    Some(SymmetricCone::Nonnegative),
                    Some(SymmetricCone::Nonnegative),
                    None,
                ],
            },
            3 => ConicRows {
                g: [[mu, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], z],
                h: [0.0; 4],
                rows: 3,
                cones: [Some(SymmetricCone::SecondOrder), None, None],
            },
            _ => ConicRows::normal_force(),
        }
    }

    /// Planar: the pair `mu F + G >= 0`, `mu F - G >= 0`; 3-D: `(mu F, G1, G2)` in the
    /// second-order cone; `mu` kept as a structural entry (no `F >= 0` row of its own: the cone
    /// implies it).
    fn clarabel_rows(&self, d: usize, _radius_floor: f64) -> ClarabelRows {
        let row = |a: [f64; 3], structural_f| ClarabelRow {
            a,
            structural_f,
            b: 0.0,
        };
        let mu = self.mu;
        ClarabelRows {
            normal: false,
            pair: (d == 2).then(|| [row([-mu, -1.0, 0.0], true), row([-mu, 1.0, 0.0], true)]),
            second_order: (d == 3).then(|| {
                [
                    row([-mu, 0.0, 0.0], true),
                    row([0.0, -1.0, 0.0], false),
                    row([0.0, 0.0, -1.0], false),
                ]
            }),
        }
    }

    /// The dual cone `{(u, w): u >= mu ||w||}`.
    fn dual_floor(&self, w_g: f64) -> f64 {
        self.mu * w_g
    }

    /// A cone: no bounded part.
    fn support(&self, _w_g: f64, _radius_floor: f64) -> f64 {
        0.0
    }

    /// The distances to the cone's boundary (stick / slip) and to the polar cone's (slip /
    /// separation), each along its normal, the nearer one named.
    fn state_margin(&self, v: [f64; 3], d: usize) -> StateMargin {
        let mu = self.mu;
        let beta = v[1].hypot(if d == 3 { v[2] } else { 0.0 });
        let norm = (1.0 + mu * mu).sqrt();
        let to_cone = StateMargin {
            distance: (mu * v[0] - beta).abs() / norm,
            stick_slip: true,
        };
        let to_polar = StateMargin {
            distance: (v[0] + mu * beta).abs() / norm,
            stick_slip: false,
        };
        if beta <= mu * v[0] {
            to_cone
        } else if mu * beta <= -v[0] || to_polar.distance < to_cone.distance {
            to_polar
        } else {
            to_cone
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::cones::projection::assert_jacobian_matches_differences;

    fn project_friction(mu: f64, v: [f64; 3], d: usize) -> Projection {
        FrictionCone { mu }.project(v, d)
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// Moreau: `v = Proj_K(v) + Proj_polar(v)` with the two parts orthogonal, and the
    /// projection in the cone; checked on points of all three regions.
    #[test]
    fn projection_is_the_moreau_decomposition() {
        let mu = 0.4;
        for v in [
            [1.0, 0.2, -0.1],
            [-1.0, 0.1, 0.05],
            [0.3, 1.0, -0.5],
            [-0.1, 2.0, 0.0],
            [0.0, 0.0, 1.0],
        ] {
            let p = project_friction(mu, v, 3).point;
            let r = [v[0] - p[0], v[1] - p[1], v[2] - p[2]];
            assert!(p[1].hypot(p[2]) <= mu * p[0] + 1e-15, "{v:?} -> {p:?}");
            assert!(
                mu * r[1].hypot(r[2]) <= -r[0] + 1e-15,
                "polar part of {v:?}"
            );
            assert!(dot(p, r).abs() < 1e-15, "{v:?}");
        }
    }

    /// The Jacobian weights and directions against central differences of the projection.
    #[test]
    fn jacobian_matches_finite_differences() {
        let mu = 0.7;
        assert_jacobian_matches_differences(|v| project_friction(mu, v, 3), [0.3, 0.9, -0.4]);
    }
}
