//! A projection onto an element's constraint set with one element of its generalized (Clarke)
//! Jacobian, `D = sum_j theta_j d_j d_j'` (see [`super::element_cone`]); each cone file
//! returns one.

/// A projection with its Jacobian `sum_j theta_j d_j d_j'` (entries beyond `d` unused).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Projection {
    /// `Proj_K(v)`.
    pub point: [f64; 3],
    /// Orthonormal directions `d_j` (columns).
    pub dirs: [[f64; 3]; 3],
    /// Jacobian weights `theta_j in [0, 1]`.
    pub theta: [f64; 3],
}

impl Projection {
    /// The identity: `v` lies in the set, every direction is free.
    pub fn inside(v: [f64; 3]) -> Self {
        Projection {
            point: v,
            dirs: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            theta: [1.0; 3],
        }
    }
}

/// Test helper: asserts that the Jacobian `sum_j theta_j d_j d_j'` that `project` returns at
/// `v` matches central differences of its projected point (step 1e-7, entries to 1e-6: the
/// truncation error of the difference on a smooth piece of the projection).
#[cfg(test)]
pub(crate) fn assert_jacobian_matches_differences(
    project: impl Fn([f64; 3]) -> Projection,
    v: [f64; 3],
) {
    let p = project(v);
    let h = 1e-7;
    for c in 0..3 {
        let (mut vp, mut vm) = (v, v);
        vp[c] += h;
        vm[c] -= h;
        let (pp, pm) = (project(vp).point, project(vm).point);
        for r in 0..3 {
            let fd = (pp[r] - pm[r]) / (2.0 * h);
            let jac: f64 = (0..3)
                .map(|j| p.theta[j] * p.dirs[j][r] * p.dirs[j][c])
                .sum();
            assert!((fd - jac).abs() < 1e-6, "D[{r}][{c}] = {jac} vs {fd}");
        }
    }
}
