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

use super::projection::Projection;

/// Projection of `v` (first `d` entries: `F`, then `G`) onto `K_mu`, `mu > 0`.
pub(crate) fn project_friction(mu: f64, v: [f64; 3], d: usize) -> Projection {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::native::cones::projection::assert_jacobian_matches_differences;

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
