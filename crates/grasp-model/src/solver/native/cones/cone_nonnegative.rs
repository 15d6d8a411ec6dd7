//! The nonnegative ray `F >= 0`: a frictionless element's normal force.

use super::projection::Projection;

/// Projection of `v[0]` onto `F >= 0`: itself with the direction free, or 0 with it fixed.
pub(crate) fn project_nonnegative(v: [f64; 3]) -> Projection {
    let mut p = Projection::inside(v);
    if v[0] < 0.0 {
        p.point[0] = 0.0;
        p.theta[0] = 0.0;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clips_negative_forces() {
        assert_eq!(project_nonnegative([-2.0, 0.0, 0.0]).point[0], 0.0);
        assert_eq!(project_nonnegative([-2.0, 0.0, 0.0]).theta[0], 0.0);
        assert_eq!(project_nonnegative([3.0, 0.0, 0.0]).point[0], 3.0);
        assert_eq!(project_nonnegative([3.0, 0.0, 0.0]).theta[0], 1.0);
    }
}
