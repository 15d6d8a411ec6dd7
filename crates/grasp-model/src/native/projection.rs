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
