//! The symmetric cones the interior-point method (`crate::solver::native::interior`) writes
//! every element set in ([`super::conic_rows`]), and their Jordan algebra
//! (Vandenberghe, "The CVXOPT linear and quadratic cone program solvers", 2010): the
//! nonnegative ray and the second-order cone of dimension 3, `{(u0, u1): u0 >= ||u1||}`.
//!
//! For each cone: the product `u o v`, its inverse `lambda \ r` (the `x` with
//! `lambda o x = r`), the identity `e`, the Nesterov-Todd scaling `W` (symmetric, with
//! `W z = W^-1 s`) and the largest step keeping a point inside.

/// One symmetric cone of the interior-point method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SymmetricCone {
    /// `u >= 0`, one row.
    Nonnegative,
    /// `u0 >= ||(u1, u2)||`, three rows.
    SecondOrder,
}

impl SymmetricCone {
    /// Rows of the cone.
    pub fn dim(&self) -> usize {
        match self {
            SymmetricCone::Nonnegative => 1,
            SymmetricCone::SecondOrder => 3,
        }
    }

    /// The identity `e`.
    pub fn identity(&self, out: &mut [f64]) {
        out.fill(0.0);
        out[0] = 1.0;
    }

    /// `u o v`.
    pub fn product(&self, u: &[f64], v: &[f64], out: &mut [f64]) {
        match self {
            SymmetricCone::Nonnegative => out[0] = u[0] * v[0],
            SymmetricCone::SecondOrder => {
                out[0] = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
                out[1] = u[0] * v[1] + v[0] * u[1];
                out[2] = u[0] * v[2] + v[0] * u[2];
            }
        }
    }

    /// `x` with `lambda o x = r` (`lambda` in the interior).
    pub fn inverse_product(&self, lambda: &[f64], r: &[f64], out: &mut [f64]) {
        match self {
            SymmetricCone::Nonnegative => out[0] = r[0] / lambda[0],
            SymmetricCone::SecondOrder => {
                let det = lambda[0] * lambda[0] - lambda[1] * lambda[1] - lambda[2] * lambda[2];
                let x0 = (lambda[0] * r[0] - lambda[1] * r[1] - lambda[2] * r[2]) / det;
                out[0] = x0;
                out[1] = (r[1] - x0 * lambda[1]) / lambda[0];
                out[2] = (r[2] - x0 * lambda[2]) / lambda[0];
            }
        }
    }

    /// `u0 - ||u1||` (the smallest eigenvalue; `u` itself for the ray).
    pub fn margin(&self, u: &[f64]) -> f64 {
        match self {
            SymmetricCone::Nonnegative => u[0],
            SymmetricCone::SecondOrder => u[0] - u[1].hypot(u[2]),
        }
    }

    /// The largest `alpha <= limit` with `u + alpha du` in the cone (`u` in the interior).
    pub fn step_to_boundary(&self, u: &[f64], du: &[f64], limit: f64) -> f64 {
        match self {
            SymmetricCone::Nonnegative => {
                if du[0] < 0.0 {
                    (-u[0] / du[0]).min(limit)
                } else {
                    limit
                }
            }
            SymmetricCone::SecondOrder => soc_step(u, du, limit),
        }
    }

    /// The Nesterov-Todd scaling of `(s, z)` (both in the interior), row-major 3 x 3 for the
    /// second-order cone, `[sqrt(s/z)]` for the ray.
    pub fn nt_scaling(&self, s: &[f64], z: &[f64]) -> Scaling {
        match self {
            SymmetricCone::Nonnegative => {
                let w = (s[0] / z[0]).sqrt();
                Scaling {
                    w: [[w, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                    w_inv: [[1.0 / w, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                }
            }
            SymmetricCone::SecondOrder => soc_scaling(s, z),
        }
    }
}

/// A scaling matrix `W` and its inverse (symmetric; the leading `dim x dim` block is used).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scaling {
    pub w: [[f64; 3]; 3],
    pub w_inv: [[f64; 3]; 3],
}

impl Scaling {
    /// `out = M u` for `M` = `w` or `w_inv`, over the cone's rows.
    pub fn apply(m: &[[f64; 3]; 3], u: &[f64], out: &mut [f64]) {
        for (r, o) in out.iter_mut().enumerate() {
            *o = (0..u.len()).map(|c| m[r][c] * u[c]).sum();
        }
    }
}

/// `u0^2 - ||u1||^2`.
fn jdet(u: &[f64]) -> f64 {
    u[0] * u[0] - u[1] * u[1] - u[2] * u[2]
}

/// NT scaling of the second-order cone (Vandenberghe 2010, section 4.1):
/// `sb = s / sqrt(det s)`, `zb = z / sqrt(det z)`, `g = sqrt((1 + sb.zb) / 2)`,
/// `wb = (sb + J zb) / (2 g)`, `eta = (det s / det z)^(1/4)`,
/// `W = eta [[wb0, wb1'], [wb1, I + wb1 wb1' / (1 + wb0)]]`, and `W^-1` the same with
/// `-wb1` over `eta`.
fn soc_scaling(s: &[f64], z: &[f64]) -> Scaling {
    let (ds, dz) = (jdet(s).sqrt(), jdet(z).sqrt());
    let sb = [s[0] / ds, s[1] / ds, s[2] / ds];
    let zb = [z[0] / dz, z[1] / dz, z[2] / dz];
    let g = ((1.0 + sb[0] * zb[0] + sb[1] * zb[1] + sb[2] * zb[2]) / 2.0).sqrt();
    let wb = [
        (sb[0] + zb[0]) / (2.0 * g),
        (sb[1] - zb[1]) / (2.0 * g),
        (sb[2] - zb[2]) / (2.0 * g),
    ];
    let eta = (ds / dz).sqrt();
    let block = |sign: f64, scale: f64| {
        let k = 1.0 / (1.0 + wb[0]);
        [
            [scale * wb[0], scale * sign * wb[1], scale * sign * wb[2]],
            [
                scale * sign * wb[1],
                scale * (1.0 + k * wb[1] * wb[1]),
                scale * k * wb[1] * wb[2],
            ],
            [
                scale * sign * wb[2],
                scale * k * wb[1] * wb[2],
                scale * (1.0 + k * wb[2] * wb[2]),
            ],
        ]
    };
    Scaling {
        w: block(1.0, eta),
        w_inv: block(-1.0, 1.0 / eta),
    }
}

/// The largest `alpha <= limit` keeping `u + alpha du` in the second-order cone: the first
/// positive root of `det(u + alpha du) = 0` (a quadratic) with `u0 + alpha du0 >= 0`.
fn soc_step(u: &[f64], du: &[f64], limit: f64) -> f64 {
    let a = jdet(du);
    let b = 2.0 * (u[0] * du[0] - u[1] * du[1] - u[2] * du[2]);
    let c = jdet(u);
    let mut alpha = limit;
    // Roots of a t^2 + b t + c (c > 0): the smallest positive one bounds the step.
    let roots: Vec<f64> = if a.abs() < 1e-300 {
        if b < 0.0 {
            vec![-c / b]
        } else {
            vec![]
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            vec![]
        } else {
            let sq = disc.sqrt();
            let q = -0.5 * (b + b.signum() * sq);
            let mut r = vec![q / a];
            if q != 0.0 {
                r.push(c / q);
            }
            r
        }
    };
    for t in roots {
        if t > 0.0 && t < alpha {
            alpha = t;
        }
    }
    if du[0] < 0.0 {
        alpha = alpha.min(-u[0] / du[0]);
    }
    alpha
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `W z = W^-1 s` (the NT point), `W W^-1 = I`, `W` symmetric.
    #[test]
    fn nt_scaling_maps_z_and_s_to_the_same_point() {
        let c = SymmetricCone::SecondOrder;
        let (s, z) = ([2.0, 0.5, -1.0], [1.5, -0.3, 0.8]);
        let sc = c.nt_scaling(&s, &z);
        let (mut wz, mut ws) = ([0.0; 3], [0.0; 3]);
        Scaling::apply(&sc.w, &z, &mut wz);
        Scaling::apply(&sc.w_inv, &s, &mut ws);
        for r in 0..3 {
            assert!((wz[r] - ws[r]).abs() < 1e-13, "{wz:?} vs {ws:?}");
            for col in 0..3 {
                let id: f64 = (0..3).map(|k| sc.w[r][k] * sc.w_inv[k][col]).sum();
                assert!((id - if r == col { 1.0 } else { 0.0 }).abs() < 1e-13);
                assert!((sc.w[r][col] - sc.w[col][r]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn inverse_product_inverts_the_product() {
        let c = SymmetricCone::SecondOrder;
        let (l, x) = ([2.0, 0.3, -0.4], [0.7, -1.1, 0.2]);
        let (mut r, mut back) = ([0.0; 3], [0.0; 3]);
        c.product(&l, &x, &mut r);
        c.inverse_product(&l, &r, &mut back);
        for k in 0..3 {
            assert!((back[k] - x[k]).abs() < 1e-14);
        }
    }

    #[test]
    fn step_to_boundary_lands_on_the_boundary() {
        let c = SymmetricCone::SecondOrder;
        let (u, du) = ([1.0, 0.2, 0.1], [-0.3, 0.9, -0.2]);
        let a = c.step_to_boundary(&u, &du, 1e9);
        let v = [u[0] + a * du[0], u[1] + a * du[1], u[2] + a * du[2]];
        assert!(c.margin(&v).abs() < 1e-12, "{a} -> {v:?}");
    }
}
