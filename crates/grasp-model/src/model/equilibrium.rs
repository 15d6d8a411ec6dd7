//! Force and moment equilibrium of the object (thesis eqs. 48-49; model.md).
//!
//! Wrenches are `(force N, moment N m)` in the world frame with moments about the model's
//! reference point `O`. In a planar scene with plane normal `p` and in-plane basis `e1, e2`
//! (`e1 x e2 = p`) only three rows remain: `f.e1`, `f.e2`, `m.p`.

use nalgebra::{DMatrix, Vector3, Vector6};

/// An equilibrium row is independent when its eigenvalue of `E E'` exceeds this fraction of
/// the largest (about 1e-6 in singular values: well above round-off of `E`'s entries, which
/// are O(1) after scaling, and well below any real lever arm).
const RANK_CUTOFF: f64 = 1e-12;

/// The plane of motion of a planar scene: an orthonormal in-plane basis `e1, e2` and the
/// plane's normal `normal = e1 x e2` (world frame, unit vectors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPlane {
    /// First in-plane axis.
    pub e1: Vector3<f64>,
    /// Second in-plane axis.
    pub e2: Vector3<f64>,
    /// Normal of the plane, `e1 x e2`: the axis of the one moment row.
    pub normal: Vector3<f64>,
}

/// A wrench `(force, moment about O)`.
pub type Wrench = Vector6<f64>;

/// Wrench on the object of a unit force along `dir` applied at `point` (moment about `origin`).
pub fn unit_wrench(dir: &Vector3<f64>, point: &Vector3<f64>, origin: &Vector3<f64>) -> Wrench {
    let m = (point - origin).cross(dir);
    Wrench::new(dir.x, dir.y, dir.z, m.x, m.y, m.z)
}

/// Maps world wrenches to the scaled equilibrium coordinates of the cone program:
/// force components divided by nothing, moment components divided by the length scale `L`
/// (so both are in newtons), then projected on the plane in a planar scene.
#[derive(Debug, Clone, PartialEq)]
pub struct EquilibriumMap {
    /// `rows x 6` matrix `S` (rows = 6 in 3-D, 3 planar).
    pub select: DMatrix<f64>,
}

impl EquilibriumMap {
    /// Builds the map for a 3-D scene (`planar = None`) or a planar one.
    pub fn new(length_scale_m: f64, planar: Option<MotionPlane>) -> Self {
        let inv_l = 1.0 / length_scale_m;
        let select = match planar {
            None => {
                let mut s = DMatrix::<f64>::identity(6, 6);
                for r in 3..6 {
                    s[(r, r)] = inv_l;
                }
                s
            }
            Some(MotionPlane { e1, e2, normal: p }) => {
                let mut s = DMatrix::<f64>::zeros(3, 6);
                for c in 0..3 {
                    s[(0, c)] = e1[c];
                    s[(1, c)] = e2[c];
                    s[(2, 3 + c)] = p[c] * inv_l;
                }
                s
            }
        };
        EquilibriumMap { select }
    }

    /// Number of equilibrium rows (3 planar, 6 in 3-D).
    pub fn rows(&self) -> usize {
        self.select.nrows()
    }

    /// The scaled equilibrium coordinates of a wrench.
    pub fn apply(&self, w: &Wrench) -> Vec<f64> {
        (&self.select * DMatrix::from_column_slice(6, 1, w.as_slice()))
            .column(0)
            .iter()
            .copied()
            .collect()
    }
}

/// Row-space reduction of the equilibrium rows: an orthonormal basis `U` (`rows x r`) of the
/// range of `E` (`rows x n`), and the directions `N` (`rows x (rows - r)`) no finger can
/// resist. Equality rows `U' E x = U' b` replace `E x = b`; `b` must have no component along
/// `N`, else the object has no equilibrium whatever the contact forces.
#[derive(Debug, Clone, PartialEq)]
pub struct RowReduction {
    /// Basis of the resisted directions (columns), in scaled equilibrium coordinates.
    pub basis: DMatrix<f64>,
    /// Directions no contact force can produce (columns).
    pub null: DMatrix<f64>,
}

/// `E E'` of a wide `E` (`rows x n`), with `E'` read in place through its strides rather than
/// copied (a fine patch's `E` is a million columns): the same product, term for term, as
/// `e * e.transpose()`.
fn gram(e: &DMatrix<f64>) -> DMatrix<f64> {
    let (rows, n) = e.shape();
    let transposed = nalgebra::DMatrixView::from_slice_with_strides(e.as_slice(), n, rows, rows, 1);
    e * transposed
}

impl RowReduction {
    /// Computes the reduction from `E E'` (at most 6 x 6) by a symmetric eigendecomposition;
    /// directions with eigenvalue below `1e-12` of the largest are unresisted.
    pub fn new(e: &DMatrix<f64>) -> Self {
        let rows = e.nrows();
        let eig = nalgebra::SymmetricEigen::new(gram(e));
        let lmax = eig.eigenvalues.iter().cloned().fold(0.0_f64, f64::max);
        let mut keep = Vec::new();
        let mut drop = Vec::new();
        for c in 0..rows {
            let col: Vec<f64> = eig.eigenvectors.column(c).iter().copied().collect();
            if lmax > 0.0 && eig.eigenvalues[c] > RANK_CUTOFF * lmax {
                keep.push((eig.eigenvalues[c], col));
            } else {
                drop.push(col);
            }
        }
        // Deterministic order: largest eigenvalue first.
        keep.sort_by(|a, b| b.0.total_cmp(&a.0));
        let basis = DMatrix::from_fn(rows, keep.len(), |r, c| keep[c].1[r]);
        let null = DMatrix::from_fn(rows, drop.len(), |r, c| drop[c][r]);
        RowReduction { basis, null }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Gram product read through the strides has the bits of the product with a copied
    /// transpose, for a narrow and a wide matrix (the wide one in many blocks of the product).
    #[test]
    fn gram_equals_the_copied_product() {
        let mut seed = 0x9e3779b97f4a7c15_u64;
        for (rows, n) in [(3, 10), (6, 70_001)] {
            let e = DMatrix::from_fn(rows, n, |_, _| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            });
            let want = &e * e.transpose();
            let got = gram(&e);
            assert!(got
                .iter()
                .zip(want.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }
}
