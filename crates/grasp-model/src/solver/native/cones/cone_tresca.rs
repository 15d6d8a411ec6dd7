//! The Tresca set of a coulomb iterate: `F >= 0` and `||G|| <= r` with the radius `r` fixed at
//! the previous iterate (model.md, "coulomb"). It is a product: the normal part is the
//! nonnegative ray, the tangential part a disc (an interval when planar). Outside the disc the
//! projection is `r b/||b||`, whose Jacobian fixes the radial direction (weight 0) and, in 3-D,
//! turns the tangential one with weight `r / ||b||`.

use super::projection::Projection;

/// Projection of `v` (first `d` entries) onto `{F >= 0} x {||G|| <= radius}`.
pub(crate) fn project_tresca(radius: f64, v: [f64; 3], d: usize) -> Projection {
    let mut p = Projection::inside(v);
    if v[0] < 0.0 {
        p.point[0] = 0.0;
        p.theta[0] = 0.0;
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::native::cones::projection::assert_jacobian_matches_differences;

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
