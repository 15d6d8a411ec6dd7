//! The spring behind a finger's rigid core (`fingers[i].mount`), as the model uses it: its
//! compliance `S = K^-1` over the directions the core moves, and the map `B` from the patch's
//! element forces to the wrench they put on the core.
//!
//! The element forces `x` of a patch sum, in the contact frame (`t1, t2, n`, about the contact
//! point, element `k` at `(x_k, y_k)`), to the wrench `w = B x`: force `(sum G1, sum G2, sum F)`
//! and moment `(sum y F, -sum x F, sum (x G2 - y G1))`. A spring of stiffness `K` carrying
//! `w` and preloaded with `w0` (along the normal) moves the core back by `S (w - w0)`; a motion
//! `(d, phi)` of the core moves element `k`'s surface by `d + phi x p_k`, which is `B'(d, phi)`
//! on the element's components (virtual work). The core's retreat so adds `B' S B` to the
//! patch compliance and `-B' S w0` to the displacement offsets: the complementary energy of
//! the spring, `1/2 (w - w0)' S (w - w0)`, added to the program's (model.md, "The grasp
//! program"; the springs in series of Johnson, *Contact Mechanics*, 4.2).
//!
//! `B` is never stored (a 1024 x 1024 patch would need 150 MB): it is applied from the
//! element centres.

use nalgebra::{DMatrix, Matrix6, Vector6};

use crate::scene::mount_spec::MountSpec;

/// Components of a mount's wrench and motion: translations along `t1, t2, n`, rotations about
/// them.
pub const MOUNT_COMPONENTS: usize = 6;

/// How many times the contact's largest compliance a mount's may be before a model warns:
/// the two are added in one matrix, so the contact's part keeps about `f64::EPSILON` times
/// this of its relative precision (1e8: about 2e-8).
pub const MOUNT_SOFTNESS_WARNING: f64 = 1e8;

/// One finger's mount as the model uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerMount {
    /// `S = K^-1` over the compliant directions, 0 on the rigid ones: m/N, rad/N and
    /// rad/(N m), contact frame `[t1, t2, n, rot t1, rot t2, rot n]`.
    compliance: Matrix6<f64>,
    /// The preload wrench `w0` (N along `n`; the spring's push at the commanded pose).
    preload: Vector6<f64>,
    /// Element centres `(x along t1, y along t2)`, m.
    centres_m: Vec<[f64; 2]>,
    /// Tangential unknowns per element: 0, 1 (planar) or 2.
    n_tangential: usize,
    /// What a sensitivity may differentiate: each direction given by its stiffness, or the
    /// scale of a full matrix.
    parameters: Vec<StiffnessParameter>,
}

/// A stiffness of a mount that a sensitivity differentiates with respect to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StiffnessParameter {
    /// `normal_n_per_m` (N/m).
    Normal,
    /// `tangential_n_per_m` (N/m, `t1` and `t2` alike).
    Tangential,
    /// `rotational_nm_per_rad` (N m/rad, about each axis alike).
    Rotational,
    /// A common factor on a full `matrix` (dimensionless, 1 as given).
    Scale,
}

impl StiffnessParameter {
    /// Short name: `k_n`, `k_t`, `k_r`, `k_scale`.
    pub fn name(self) -> &'static str {
        match self {
            StiffnessParameter::Normal => "k_n",
            StiffnessParameter::Tangential => "k_t",
            StiffnessParameter::Rotational => "k_r",
            StiffnessParameter::Scale => "k_scale",
        }
    }

    /// The components `[t1, t2, n, rot t1, rot t2, rot n]` whose stiffness it sets.
    fn components(self) -> [bool; 6] {
        match self {
            StiffnessParameter::Normal => [false, false, true, false, false, false],
            StiffnessParameter::Tangential => [true, true, false, false, false, false],
            StiffnessParameter::Rotational => [false, false, false, true, true, true],
            StiffnessParameter::Scale => [true; 6],
        }
    }
}

/// The components a planar scene's finger moves in: along `t1` and `n`, and about `t2` (the
/// plane's normal).
const PLANAR_COMPONENTS: [bool; 6] = [true, false, true, false, true, false];

impl FingerMount {
    /// The mount of `spec` on a patch with element centres `centres_m` (m) and `n_tangential`
    /// tangential unknowns; in a planar scene (`planar`) the core moves only in the plane. The
    /// compliance is the inverse of the stiffness over the directions that move (a rigid
    /// direction holds the core: the free directions' stiffness is `K`'s block over them).
    pub fn new(
        spec: &MountSpec,
        centres_m: Vec<[f64; 2]>,
        n_tangential: usize,
        planar: bool,
    ) -> Self {
        let in_plane = |c: usize| !planar || PLANAR_COMPONENTS[c];
        let compliance = match spec.compliance {
            // Given as written, its out-of-plane rows and columns dropped in a planar scene.
            Some(s) => Matrix6::from_fn(|r, c| match in_plane(r) && in_plane(c) {
                true => s[r][c],
                false => 0.0,
            }),
            None => inverse_over_free(spec, &in_plane),
        };
        let mut preload = Vector6::zeros();
        preload[2] = spec.preload_n;
        FingerMount {
            parameters: stiffness_parameters(spec, &compliance),
            compliance,
            preload,
            centres_m,
            n_tangential,
        }
    }

    /// The stiffnesses a sensitivity may differentiate: each direction the spec gives that
    /// moves the core, or a matrix's scale.
    pub fn stiffness_parameters(&self) -> &[StiffnessParameter] {
        &self.parameters
    }

    /// The change of the core's retreat `S (B v - w0)` under the element forces `v` (N) per
    /// unit of `parameter` (m and rad per N/m, per N m/rad, or per unit factor): `dS = -S dK S`
    /// with `dK` the identity on the parameter's components, or `K` itself for a matrix's
    /// scale (`dS = -S`): the derivative of an inverse.
    pub fn retreat_per_stiffness(&self, v: &[f64], parameter: StiffnessParameter) -> Vector6<f64> {
        let load = self.wrench(v) - self.preload;
        if parameter == StiffnessParameter::Scale {
            return -(self.compliance * load);
        }
        let mut retreat = self.compliance * load;
        for (c, on) in parameter.components().iter().enumerate() {
            if !on {
                retreat[c] = 0.0;
            }
        }
        -(self.compliance * retreat)
    }

    /// `S`, the compliance over `[t1, t2, n, rot t1, rot t2, rot n]` (0 where rigid).
    pub fn compliance(&self) -> &Matrix6<f64> {
        &self.compliance
    }

    fn elements(&self) -> usize {
        self.centres_m.len()
    }

    /// Column of `B` for local unknown `j` (component-major: `c N + k`): the wrench of a unit
    /// force of component `c` (0 normal, 1 along `t1`, 2 along `t2`) at element `k`.
    fn column(&self, j: usize) -> Vector6<f64> {
        let n = self.elements();
        let [x, y] = self.centres_m[j % n];
        match j / n {
            0 => Vector6::new(0.0, 0.0, 1.0, y, -x, 0.0),
            1 => Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, -y),
            _ => Vector6::new(0.0, 1.0, 0.0, 0.0, 0.0, x),
        }
    }

    /// Local unknowns, `(1 + n_tangential) N`.
    fn len(&self) -> usize {
        self.elements() * (1 + self.n_tangential)
    }

    /// The wrench `B v` of local element forces `v` (N): N and N m about the contact point.
    pub fn wrench(&self, v: &[f64]) -> Vector6<f64> {
        (0..self.len())
            .filter(|&j| v[j] != 0.0)
            .fold(Vector6::zeros(), |w, j| w + self.column(j) * v[j])
    }

    /// `out += scale B' m` for a core motion `m` (m, rad): each element's surface moved with
    /// the core.
    pub fn add_motion(&self, motion: &Vector6<f64>, scale: f64, out: &mut [f64]) {
        for (j, o) in out.iter_mut().enumerate().take(self.len()) {
            *o += scale * self.column(j).dot(motion);
        }
    }

    /// `out += scale B' S B v`: the core's retreat under the forces `v`, on every element
    /// (m per N of `v` times `scale`).
    pub fn add_product(&self, v: &[f64], scale: f64, out: &mut [f64]) {
        let motion = self.compliance * self.wrench(v);
        self.add_motion(&motion, scale, out);
    }

    /// Adds `B' S B` to the dense compliance `c` (m/N, `len x len`).
    pub fn add_to_matrix(&self, c: &mut DMatrix<f64>) {
        let columns: Vec<Vector6<f64>> = (0..self.len()).map(|j| self.column(j)).collect();
        let retreats: Vec<Vector6<f64>> = columns.iter().map(|b| self.compliance * b).collect();
        for (col, s) in retreats.iter().enumerate() {
            for (row, b) in columns.iter().enumerate() {
                c[(row, col)] += b.dot(s);
            }
        }
    }

    /// The diagonal entry of `B' S B` at local unknown `j`, m/N.
    pub fn diagonal(&self, j: usize) -> f64 {
        let b = self.column(j);
        b.dot(&(self.compliance * b))
    }

    /// The largest diagonal entry of `B' S B`, m/N.
    pub fn largest_diagonal(&self) -> f64 {
        (0..self.len())
            .map(|j| self.diagonal(j))
            .fold(0.0, f64::max)
    }

    /// An upper bound of the largest absolute row sum of `B' S B`, m/N: `max_j sum_ab |B_aj|
    /// |S_ab| ||B_b||_1` (every row of `B` summed in absolute value).
    pub fn row_sum_bound(&self) -> f64 {
        let mut row_norms = Vector6::zeros();
        for j in 0..self.len() {
            row_norms += self.column(j).abs();
        }
        let weights = self.compliance.abs() * row_norms;
        (0..self.len())
            .map(|j| self.column(j).abs().dot(&weights))
            .fold(0.0, f64::max)
    }

    /// `out += -B' S w0`: the preload's displacement of every element (m), the spring
    /// pushing the core toward the object by `S w0` at its commanded pose.
    pub fn add_preload_offset(&self, out: &mut [f64]) {
        if self.preload != Vector6::zeros() {
            let motion = self.compliance * self.preload;
            self.add_motion(&motion, -1.0, out);
        }
    }

    /// The core's displacement from its commanded pose under the element forces `v` (N): `-S
    /// (B v - w0)`, translations (m) along `t1, t2, n` (positive along `n`: toward the
    /// object) and rotations (rad) about them.
    pub fn core_displacement(&self, v: &[f64]) -> Vector6<f64> {
        -(self.compliance * (self.wrench(v) - self.preload))
    }
}

/// The compliance `S` of `spec`'s stiffness: the inverse of its block over the directions that
/// move (`moves`; a rigid direction holds the core), 0 elsewhere.
fn inverse_over_free(spec: &MountSpec, moves: &dyn Fn(usize) -> bool) -> Matrix6<f64> {
    let k = spec.stiffness();
    let free: Vec<usize> = (0..MOUNT_COMPONENTS)
        .filter(|&c| k.compliant[c] && moves(c))
        .collect();
    let block = DMatrix::from_fn(free.len(), free.len(), |r, c| k.matrix[free[r]][free[c]]);
    let mut compliance = Matrix6::zeros();
    // Validation checked the matrix positive definite, so every principal block is too.
    if let Some(inverse) = block.cholesky().map(|c| c.inverse()) {
        for (r, &fr) in free.iter().enumerate() {
            for (c, &fc) in free.iter().enumerate() {
                compliance[(fr, fc)] = inverse[(r, c)];
            }
        }
    }
    compliance
}

/// The parameters of [`FingerMount::stiffness_parameters`]: a matrix's (or a compliance's)
/// scale, or each direction
/// given whose compliance is not 0 (a planar scene's out-of-plane directions are).
fn stiffness_parameters(spec: &MountSpec, compliance: &Matrix6<f64>) -> Vec<StiffnessParameter> {
    if spec.matrix.is_some() || spec.compliance.is_some() {
        return vec![StiffnessParameter::Scale];
    }
    let given = [
        (spec.normal_n_per_m, StiffnessParameter::Normal),
        (spec.tangential_n_per_m, StiffnessParameter::Tangential),
        (spec.rotational_nm_per_rad, StiffnessParameter::Rotational),
    ];
    given
        .into_iter()
        .filter(|(k, p)| {
            let moves = p.components();
            k.is_some() && (0..MOUNT_COMPONENTS).any(|c| moves[c] && compliance[(c, c)] != 0.0)
        })
        .map(|(_, p)| p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mount(spec: MountSpec, n_tangential: usize) -> FingerMount {
        let centres = vec![[-1e-3, -2e-3], [-1e-3, 2e-3], [1e-3, -2e-3], [1e-3, 2e-3]];
        FingerMount::new(&spec, centres, n_tangential, false)
    }

    fn spec(matrix: Option<[[f64; 6]; 6]>) -> MountSpec {
        MountSpec {
            normal_n_per_m: matrix.is_none().then_some(2e4),
            tangential_n_per_m: matrix.is_none().then_some(5e3),
            rotational_nm_per_rad: matrix.is_none().then_some(3.0),
            matrix,
            compliance: None,
            preload_n: 0.0,
        }
    }

    /// `B' m` is the transpose of `B`: `v . B'm = (B v) . m` for any forces and motion (the
    /// virtual work of the module docs), to round-off.
    #[test]
    fn motion_is_the_transpose_of_the_wrench() {
        let m = mount(spec(None), 2);
        let v: Vec<f64> = (0..12).map(|j| (j as f64 * 0.7).sin()).collect();
        let motion = Vector6::new(1e-3, -2e-3, 3e-3, 0.1, -0.2, 0.3);
        let mut bm = vec![0.0; 12];
        m.add_motion(&motion, 1.0, &mut bm);
        let lhs: f64 = v.iter().zip(&bm).map(|(a, b)| a * b).sum();
        let rhs = m.wrench(&v).dot(&motion);
        assert!((lhs - rhs).abs() < 1e-15, "{lhs} vs {rhs}");
    }

    /// The moment of a normal force at `(x, y)` about the contact point is `(y F, -x F, 0)`
    /// (`p x F n` with `p = x t1 + y t2`): a hand cross product.
    #[test]
    fn wrench_of_one_normal_force_is_its_cross_product() {
        let m = mount(spec(None), 2);
        let mut v = vec![0.0; 12];
        v[3] = 2.0; // normal force 2 N at (1e-3, 2e-3)
        let w = m.wrench(&v);
        let expected = Vector6::new(0.0, 0.0, 2.0, 4e-3, -2e-3, 0.0);
        assert!((w - expected).norm() < 1e-18, "{w}");
    }

    /// The dense `B'SB`, its products, diagonal and row-sum bound agree with each other; the
    /// per-direction compliance is `diag(1/kt, 1/kt, 1/kn, 1/kr, 1/kr, 1/kr)`.
    #[test]
    fn dense_form_matches_products() {
        let m = mount(spec(None), 2);
        let s = m.compliance();
        assert!((s[(2, 2)] - 1.0 / 2e4).abs() < 1e-20 && (s[(0, 0)] - 1.0 / 5e3).abs() < 1e-18);
        let mut c = DMatrix::zeros(12, 12);
        m.add_to_matrix(&mut c);
        let v: Vec<f64> = (0..12).map(|j| (j as f64 * 1.3).cos()).collect();
        let mut out = vec![0.0; 12];
        m.add_product(&v, 1.0, &mut out);
        let dense = &c * nalgebra::DVector::from_column_slice(&v);
        for j in 0..12 {
            assert!((dense[j] - out[j]).abs() < 1e-12 * out[j].abs().max(1e-9));
            assert!((c[(j, j)] - m.diagonal(j)).abs() <= 1e-15 * c[(j, j)]);
        }
        let exact = (0..12)
            .map(|r| (0..12).map(|col| c[(r, col)].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        assert!(m.row_sum_bound() >= exact * (1.0 - 1e-12));
    }

    /// A rigid direction holds the core: the normal-only mount moves along `n` alone, and a
    /// full matrix's compliance is its inverse.
    #[test]
    fn rigid_directions_hold_and_matrix_inverts() {
        let normal_only = MountSpec {
            normal_n_per_m: Some(1e3),
            tangential_n_per_m: None,
            rotational_nm_per_rad: None,
            matrix: None,
            compliance: None,
            preload_n: 0.0,
        };
        let m = mount(normal_only, 2);
        let s = m.compliance();
        assert_eq!(s.iter().filter(|x| **x != 0.0).count(), 1);
        let mut k = [[0.0; 6]; 6];
        for (c, row) in k.iter_mut().enumerate() {
            row[c] = 10.0 + c as f64;
        }
        k[0][2] = 3.0;
        k[2][0] = 3.0;
        let m = mount(spec(Some(k)), 2);
        let product = Matrix6::from_fn(|r, c| k[r][c]) * m.compliance();
        assert!((product - Matrix6::identity()).norm() < 1e-14, "{product}");
    }
}
