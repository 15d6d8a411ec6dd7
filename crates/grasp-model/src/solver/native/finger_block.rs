//! The fixed data of one finger in the native solver: its scaled compliance block `P_i`
//! (dense, symmetric positive definite, `n_i x n_i`) and its columns `E_i` of the equality
//! matrix (`m x n_i`). Both stay constant for the life of a program; only the cones, `q` and
//! the right-hand side change between solves.
//!
//! The block is the one place that stores `P_i`: the Newton system reads it through
//! [`FingerBlockData::entry`], [`FingerBlockData::apply`] and
//! [`FingerBlockData::apply_columns`], so a matrix-free operator (FFT products on the uniform
//! grid) can replace the stored matrix here without touching the solver's strategy.

use std::borrow::Cow;
use std::sync::Arc;

use faer::Mat;
use nalgebra::DMatrix;

use crate::model::patch_compliance::{PatchCompliance, MATERIALISED_UNKNOWNS};

use crate::program::cone_program::FingerBlock;

use super::parallel_vectors::{each_chunk, map_indices_coarse, VectorPool, CHUNK, PARALLEL_LEN};

/// One finger's constant data.
#[derive(Debug, Clone)]
pub(crate) struct FingerBlockData {
    /// Index of the finger's first unknown in the program's `x`.
    pub offset: usize,
    /// Elements of the patch.
    pub elements: usize,
    /// Unknowns per element, `1 + n_tangential`.
    pub dim: usize,
    /// `C_i`, m/N (dense, column-major `n_i x n_i`, or the FFT operator): shared with the
    /// model, not copied.
    c: PatchCompliance,
    /// `1 / Cu`: `P_i = scale C_i`.
    pub scale: f64,
    /// The program's equality matrix (shared, not copied), whose columns `offset..offset +
    /// n_i` are `E_i`.
    e: Arc<DMatrix<f64>>,
    /// Step of the natural residual `x - Proj(x - gamma y)` ([`step_of_residual`]): `gamma
    /// y` is a force like `x`.
    pub gamma: f64,
    /// Per element: in contact at a cold start ([`crate::solver::native::newton::cold_start`]).
    pub cold_contact: Vec<bool>,
    /// Local work vectors kept from one product, and one Newton step, to the next (a fresh
    /// allocation of a long vector faults its pages in again).
    pub work: VectorPool,
}

/// The step `gamma` of a finger's natural residual, whose sign pattern `x - gamma y` is the
/// Newton step's prediction of the contact set (an element stays in contact while its force
/// exceeds `gamma` times its gap):
///
/// - a dense block: `1 / ||P_i||_inf` (the largest absolute row sum, Gershgorin's bound on the
///   largest eigenvalue `L` of `P_i`), so `gamma <= 1 / L`, which makes the forward-backward
///   envelope of the finger's problem convex and smooth;
/// - an FFT block: `1 / max_k P_i[k, k]`, the force that closes an element's own gap. The row
///   sum of a fine patch is hundreds of diagonals (the compliance's `1/|k|` symbol summed over
///   the grid), so `1 / ||P_i||_inf` keeps nearly every element with a force in contact
///   whatever its gap: from a rough contact's bearing area each Newton step then pulls many
///   elements that should separate into tension, the line search cuts the step to 1/8 and the
///   contact set shrinks a little at a time. With the diagonal the steps are full ones. Measured
///   cold on the rough pad of `examples/rough_sphere_on_flat.json` at 256 x 256: 17 Newton
///   steps and 147 conjugate-gradient iterations with the row sum, 14 and 121 with the
///   diagonal; from a coarser grid's answer (`crate::solver::grid_continuation`) the row sum
///   stalls (steps of 1/128) and the diagonal converges in 5 steps. The dense path keeps the
///   row sum: with the diagonal the coulomb hand-off of `grasp bench` (216 unknowns) fell back
///   to Clarabel and took 10 Newton steps a step instead of 1.06.
fn step_of_residual(compliance: &PatchCompliance, scale: f64) -> f64 {
    let bound = match compliance.is_fft() {
        true => scale * compliance.max_diagonal(),
        false => scale * compliance.row_sum_bound(),
    };
    if bound > 0.0 {
        1.0 / bound
    } else {
        1.0
    }
}

impl FingerBlockData {
    /// The finger's block: `compliance` (m/N, shared) with its `scale`, and the columns
    /// `offset..offset + n_i` of the program's `equality` (`m x n`, shared).
    pub fn new(
        block: &FingerBlock,
        compliance: &PatchCompliance,
        scale: f64,
        equality: &Arc<DMatrix<f64>>,
        cold_contact: Vec<bool>,
    ) -> Self {
        debug_assert!(
            equality.ncols() >= block.offset + block.len(),
            "equality columns"
        );
        FingerBlockData {
            offset: block.offset,
            elements: block.elements,
            dim: 1 + block.n_tangential,
            c: compliance.clone(),
            scale,
            e: Arc::clone(equality),
            gamma: step_of_residual(compliance, scale),
            cold_contact,
            work: VectorPool::default(),
        }
    }

    /// Frees the work vectors kept between Newton steps and products (its own and its
    /// compliance operator's).
    pub fn release_work(&self) {
        self.work.clear();
        self.c.release_work();
    }

    /// Unknowns of the block.
    pub fn len(&self) -> usize {
        self.elements * self.dim
    }

    /// Local index of component `c` of element `k`.
    pub fn index(&self, k: usize, c: usize) -> usize {
        c * self.elements + k
    }

    /// Rows `m` of the equality matrix.
    pub fn equality_rows(&self) -> usize {
        self.e.nrows()
    }

    /// Column `c` of `E_i` (`m` entries).
    fn equality_column(&self, c: usize) -> &[f64] {
        let m = self.e.nrows();
        &self.e.as_slice()[(self.offset + c) * m..(self.offset + c + 1) * m]
    }

    /// True when `C_i` is the FFT operator (reduced systems are solved by conjugate
    /// gradients, [`crate::solver::native::newton::reduced_iterative`]).
    pub fn is_fft(&self) -> bool {
        self.c.is_fft()
    }

    /// A copy of `P_i` (see [`PatchCompliance::matrix`]; `None` for an FFT patch too large to
    /// write out).
    pub fn matrix(&self) -> Option<Mat<f64>> {
        let c = self.c.matrix()?;
        let n = self.len();
        Some(Mat::from_fn(n, n, |r, col| self.scale * c[(r, col)]))
    }

    /// True when [`FingerBlockData::matrix`] has no matrix to give.
    pub fn is_matrix_free(&self) -> bool {
        self.c.is_fft() && self.len() > MATERIALISED_UNKNOWNS
    }

    /// Column `c` of `C_i` (m/N): `scale` times it is column `c` of `P_i`. Borrowed from the
    /// dense matrix; the operator's is its product with a unit vector.
    pub fn compliance_column(&self, c: usize) -> Cow<'_, [f64]> {
        let n = self.len();
        match &self.c {
            PatchCompliance::Dense(m) => Cow::Borrowed(&m.as_slice()[c * n..(c + 1) * n]),
            PatchCompliance::Fft { .. } => {
                let mut unit = vec![0.0; n];
                unit[c] = 1.0;
                let mut out = vec![0.0; n];
                self.c.apply(&unit, &mut out);
                Cow::Owned(out)
            }
        }
    }

    /// The diagonal entry of `C_i` (m/N) at local index `i`.
    pub fn compliance_diagonal(&self, i: usize) -> f64 {
        match &self.c {
            PatchCompliance::Dense(m) => m[(i, i)],
            PatchCompliance::Fft { op, mount } => {
                op.diagonal(i / self.elements.max(1))
                    + mount.as_ref().map_or(0.0, |m| m.diagonal(i))
            }
        }
    }

    /// `E_i` (`m x n_i`).
    pub fn equality_matrix(&self) -> faer::MatRef<'_, f64> {
        let m = self.e.nrows();
        let columns = &self.e.as_slice()[self.offset * m..(self.offset + self.len()) * m];
        faer::MatRef::from_column_major_slice(columns, m, self.len())
    }

    /// `E_i[r, c]`.
    pub fn equality(&self, r: usize, c: usize) -> f64 {
        self.e[(r, self.offset + c)]
    }

    /// `out = P_i v` (local vectors): a sum of columns, which vectorises at every size (the
    /// operator's product, scaled, for an FFT patch).
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        if let PatchCompliance::Fft { op, mount } = &self.c {
            op.apply_scaled(v, out, self.scale);
            if let Some(m) = mount {
                m.add_product(v, self.scale, out);
            }
            return;
        }
        out.fill(0.0);
        let support: Vec<usize> = (0..v.len()).collect();
        self.apply_columns(v, &support, out);
    }

    /// `out += P_i v` for a `v` that is zero outside the local indices `support` (the
    /// dense matrix sums those columns; the operator applies itself to `v` whole).
    pub fn apply_columns(&self, v: &[f64], support: &[usize], out: &mut [f64]) {
        match &self.c {
            PatchCompliance::Dense(m) => {
                let n = self.len();
                for &c in support {
                    let vc = v[c] * self.scale;
                    if vc != 0.0 {
                        for (o, r) in out.iter_mut().zip(&m.as_slice()[c * n..(c + 1) * n]) {
                            *o += r * vc;
                        }
                    }
                }
            }
            PatchCompliance::Fft { op, mount } => {
                if support.iter().all(|&c| v[c] == 0.0) {
                    return;
                }
                if let Some(m) = mount {
                    m.add_product(v, self.scale, out);
                }
                let mut cv = self.work.take(v.len());
                op.apply(v, &mut cv);
                each_chunk(out, |s, chunk| {
                    for (o, x) in chunk.iter_mut().zip(&cv[s..]) {
                        *o += self.scale * x;
                    }
                });
                self.work.give(cv);
            }
        }
    }

    /// `out = Pc_i^-1 v` (local vectors) with `Pc_i` the circulant approximation of `P_i`
    /// ([`crate::model::circulant_inverse`]) for an FFT patch, `P_i`'s diagonal for a dense
    /// one: a preconditioner for systems in `P_i`. A mount's low-rank retreat `B' S B` is
    /// left out of the circulant one (conjugate gradients take at most six more iterations for
    /// it in exact arithmetic).
    pub fn precondition(&self, v: &[f64], out: &mut [f64]) {
        match &self.c {
            PatchCompliance::Dense(m) => {
                for (i, (o, x)) in out.iter_mut().zip(v).enumerate() {
                    *o = x / (self.scale * m[(i, i)]);
                }
            }
            PatchCompliance::Fft { op, .. } => {
                op.apply_approximate_inverse_scaled(v, out, 1.0 / self.scale)
            }
        }
    }

    /// `out += E_i' lambda` (local vector), on all cores for a long one.
    pub fn add_equality_transpose(&self, lambda: &[f64], out: &mut [f64]) {
        each_chunk(out, |s, chunk| {
            for (c, o) in (s..).zip(chunk.iter_mut()) {
                let col = self.equality_column(c);
                *o += col.iter().zip(lambda).map(|(a, b)| a * b).sum::<f64>();
            }
        });
    }

    /// `out += E_i v` (`out` of length `m`). A long `v` is summed on all cores, a partial sum
    /// per [`CHUNK`] of its entries added to `out` in order (the same bits on any number of
    /// threads).
    pub fn add_equality(&self, v: &[f64], out: &mut [f64]) {
        let add = |range: std::ops::Range<usize>, out: &mut [f64]| {
            for c in range.filter(|&c| v[c] != 0.0) {
                for (o, a) in out.iter_mut().zip(self.equality_column(c)) {
                    *o += a * v[c];
                }
            }
        };
        if v.len() < PARALLEL_LEN {
            return add(0..v.len(), out);
        }
        let parts = map_indices_coarse(v.len().div_ceil(CHUNK), v.len(), |k| {
            let mut part = vec![0.0; out.len()];
            add(k * CHUNK..((k + 1) * CHUNK).min(v.len()), &mut part);
            part
        });
        for part in parts {
            out.iter_mut().zip(part).for_each(|(o, p)| *o += p);
        }
    }

    /// Element `k`'s components of a local vector.
    pub fn gather(&self, v: &[f64], k: usize) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate().take(self.dim) {
            *o = v[self.index(k, c)];
        }
        out
    }
}
