//! The reduced Newton matrix of one finger and its Cholesky factor (faer), kept apart from
//! the assembly of the residuals ([`super::linearisation`]).
//!
//! Over the free directions `d_a` (element `k_a`) the matrix is
//!
//! ```text
//!   M[a, b] = d_a' P_i[k_a, k_b] d_b + delta_ab beta_a,      beta = (1 - theta)/(gamma theta)
//! ```
//!
//! (`P_i[k, l]` the `dim x dim` block of elements `k`, `l`), symmetric positive definite since
//! `P_i` is. With `M = L L'` the factor also keeps `W = L^-1 Et'`, `Et = E_i D_F` the equality
//! rows in the free directions, from which the Schur complement `W'W` on the equality rows
//! follows. A factor depends only on the free directions and their weights: it is cached and
//! reused while they stay the same (a hand-off step whose stick, slip and separation sets do
//! not change, or a quiescent iterate, costs no factorisation).

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatMut, Par};

use crate::solver::native::dense_cholesky::cholesky;
use crate::solver::native::finger_block::FingerBlockData;

use super::linearisation::Direction;

/// A factorised reduced matrix.
#[derive(Debug, Clone)]
pub(crate) struct ReducedFactor {
    /// The free directions it was built for (`element`, `dir`, `theta` bits).
    key: Vec<u64>,
    /// Lower Cholesky factor `L` of `M`.
    l: Mat<f64>,
    /// `W = L^-1 Et'` (`n_free x m`).
    pub w: Mat<f64>,
    /// The linearisation's free directions it was built for, for chord steps.
    pub free: Vec<Direction>,
    /// The linearisation's fixed directions it was built with, for chord steps.
    pub fixed: Vec<Direction>,
}

/// The cache key of a list of free directions.
pub(crate) fn key_of(free: &[Direction]) -> Vec<u64> {
    let mut key = Vec::with_capacity(5 * free.len());
    for d in free {
        key.push(d.element as u64);
        key.extend(d.dir.iter().map(|v| v.to_bits()));
        key.push(d.theta.to_bits());
    }
    key
}

impl ReducedFactor {
    /// True when the factor was built for exactly these free directions.
    pub fn matches(&self, key: &[u64]) -> bool {
        self.key == key
    }

    /// Assembles `M` and `Et'` for the free directions and factorises `M`, in the storage of
    /// `spare` (an evicted factor's, so that a run does not keep faulting in fresh pages) when
    /// given. A pivot that is not positive (round-off on a nearly singular block) is retried
    /// once with a diagonal shift of `1e-12` of the largest diagonal entry; `None` if that
    /// fails too.
    pub fn new(
        block: &FingerBlockData,
        free: &[Direction],
        fixed: &[Direction],
        key: Vec<u64>,
        spare: Option<Self>,
    ) -> Option<Self> {
        let mut l = reduced_matrix(block, free, spare.map(|f| f.l));
        if !cholesky(l.as_mut()) {
            // Rebuilt rather than kept: a copy for this rare retry would cost as much as the
            // assembly on every factorisation.
            l = reduced_matrix(block, free, Some(l));
            let n = l.nrows();
            let shift = 1e-12 * (0..n).map(|a| l[(a, a)]).fold(0.0_f64, f64::max);
            for a in 0..n {
                l[(a, a)] += shift;
            }
            if !cholesky(l.as_mut()) {
                return None;
            }
        }
        let work = l;
        let mut w = reduced_equality_transpose(block, free);
        solve_lower_triangular_in_place(work.as_ref(), w.as_mut(), Par::Seq);
        Some(ReducedFactor {
            key,
            l: work,
            w,
            free: free.to_vec(),
            fixed: fixed.to_vec(),
        })
    }

    /// `v <- L^-1 v`.
    pub fn forward(&self, v: &mut [f64]) {
        let n = v.len();
        solve_lower_triangular_in_place(
            self.l.as_ref(),
            MatMut::from_column_major_slice_mut(v, n, 1),
            Par::Seq,
        );
    }

    /// `v <- L^-T v`.
    pub fn backward(&self, v: &mut [f64]) {
        let n = v.len();
        solve_upper_triangular_in_place(
            self.l.as_ref().transpose(),
            MatMut::from_column_major_slice_mut(v, n, 1),
            Par::Seq,
        );
    }
}

/// The nonzero components `(local index, coefficient)` of a direction.
fn components(block: &FingerBlockData, d: &Direction) -> ([(usize, f64); 3], usize) {
    let mut out = [(0, 0.0); 3];
    let mut n = 0;
    for c in 0..block.dim {
        if d.dir[c] != 0.0 {
            out[n] = (block.index(d.element, c), d.dir[c]);
            n += 1;
        }
    }
    (out, n)
}

/// `M = D_F' P_i D_F + diag(beta)` (lower triangle written; the factorisation and the
/// triangular solves read only it), in `storage` when given (its upper triangle keeps stale
/// values). Column `b` of `M` is `D_F'` applied to `P_i d_b`, a combination of at most three
/// columns of `P_i` read as slices.
fn reduced_matrix(
    block: &FingerBlockData,
    free: &[Direction],
    storage: Option<Mat<f64>>,
) -> Mat<f64> {
    let n = free.len();
    let comps: Vec<_> = free.iter().map(|d| components(block, d)).collect();
    let mut m = match storage {
        Some(mut m) => {
            m.resize_with(n, n, |_, _| 0.0);
            m
        }
        None => Mat::<f64>::zeros(n, n),
    };
    let mut pd = vec![0.0; block.len()];
    for b in 0..n {
        let (cb, nb) = comps[b];
        // Column b of C D (m/N), scaled to P below.
        let single;
        let col: &[f64] = if nb == 1 && cb[0].1 == 1.0 {
            single = block.compliance_column(cb[0].0);
            &single
        } else {
            pd.fill(0.0);
            for &(ib, vb) in &cb[..nb] {
                for (o, p) in pd.iter_mut().zip(block.compliance_column(ib).iter()) {
                    *o += vb * p;
                }
            }
            &pd
        };
        let out = m
            .col_mut(b)
            .try_as_col_major_mut()
            .map(|c| c.as_slice_mut());
        let Some(out) = out else { continue };
        let scale = block.scale;
        for a in b..n {
            let (ca, na) = comps[a];
            out[a] = scale * ca[..na].iter().map(|&(ia, va)| va * col[ia]).sum::<f64>();
        }
        let t = free[b].theta;
        out[b] += (1.0 - t) / (block.gamma * t);
    }
    m
}

/// `Et' = D_F' E_i'` (`n_free x m`).
fn reduced_equality_transpose(block: &FingerBlockData, free: &[Direction]) -> Mat<f64> {
    let m = block.equality_rows();
    let mut out = Mat::<f64>::zeros(free.len(), m);
    for (a, d) in free.iter().enumerate() {
        let (ca, na) = components(block, d);
        for r in 0..m {
            out[(a, r)] = ca[..na]
                .iter()
                .map(|&(i, v)| v * block.equality(r, i))
                .sum();
        }
    }
    out
}
