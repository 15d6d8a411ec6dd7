//! The reduced Newton system of one finger solved by preconditioned conjugate gradients, for a
//! finger whose compliance is the FFT operator (no matrix to factorise), in the
//! Schur-complement form the dense fingers use: this is the path of a finger beside dense ones
//! (when every finger is an FFT one, [`super::projected_step`] solves all of them with the
//! equality rows at once).
//!
//! Where the dense path keeps `L` and `W = L^-1 Et'`, this keeps `U = M^-1 Et'` (one solve
//! per equality row the free directions reach; `M` and its preconditioner are
//! [`super::free_operator`]) and the finger's Schur complement `S_i = Et U`; each Newton step
//! then costs one more solve, `M^-1 r`. With `g = M^-1 r`:
//!
//! ```text
//!   S dlambda = sum_i Et_i g_i + ...,        xi_F,i = g_i - U_i dlambda
//! ```
//!
//! which is the dense path's `xi = L^-T (L^-1 r - W dlambda)` written with `M^-1`.

use nalgebra::DMatrix;

use crate::solver::native::finger_block::FingerBlockData;

use super::free_operator::FreeOperator;
use super::linearisation::Direction;

/// A conjugate-gradient solve ends when its residual is below this fraction of the right-hand
/// side's norm: two orders above the round-off of an FFT product (about `1e-15 log2 N`), so it
/// is reachable, and far below the Newton iteration's tolerance, so the inexact directions do
/// not slow it down.
pub(crate) const CG_TOLERANCE: f64 = 1e-12;

/// A solve that has not reached [`CG_TOLERANCE`] after this many iterations per square root
/// of the unknowns (the condition number of a boundary-element compliance grows like the
/// square root of the elements, and CG needs about the square root of that) is accepted when
/// it reached [`CG_ACCEPTABLE`], and refused otherwise.
pub(crate) const CG_ITERATIONS_PER_ROOT: usize = 50;

/// The accuracy a solve that ran out of iterations must have reached to be used.
pub(crate) const CG_ACCEPTABLE: f64 = 1e-8;

/// The reduced system of one finger over its free directions, ready for conjugate gradients.
#[derive(Debug, Clone)]
pub(crate) struct ReducedIterative {
    /// The free directions it was built for (`element`, `dir`, `theta` bits).
    key: Vec<u64>,
    /// The free directions it was built for.
    pub free: Vec<Direction>,
    /// `M` over them, with its preconditioner.
    pub op: FreeOperator,
    /// The linearisation's fixed directions it was built with, for chord steps.
    pub fixed: Vec<Direction>,
    /// `Et'` as columns (one per equality row, `n_free` long).
    et: Vec<Vec<f64>>,
    /// `U = M^-1 Et'`, column per equality row (empty where `Et'` has a zero column).
    u: Vec<Vec<f64>>,
    /// `S_i = Et U` (`m x m`, symmetric).
    pub schur: DMatrix<f64>,
    /// Conjugate-gradient iterations spent building `U`.
    pub iterations: u32,
}

impl ReducedIterative {
    /// The system of `free` (`None` when a solve for a column of `Et'` fails).
    pub fn new(
        block: &FingerBlockData,
        free: &[Direction],
        fixed: &[Direction],
        key: Vec<u64>,
    ) -> Option<Self> {
        let mut system = ReducedIterative {
            key,
            free: free.to_vec(),
            op: FreeOperator::new(block, free),
            fixed: fixed.to_vec(),
            et: Vec::new(),
            u: Vec::new(),
            schur: DMatrix::zeros(0, 0),
            iterations: 0,
        };
        let et = FreeOperator::equality_columns(block, free);
        for col in &et {
            let u = match col.iter().any(|v| *v != 0.0) {
                true => {
                    let (u, its) = system.solve(block, col)?;
                    system.iterations += its;
                    u
                }
                false => Vec::new(),
            };
            system.u.push(u);
        }
        system.schur = schur_of(&et, &system.u);
        system.et = et;
        Some(system)
    }

    /// True when the system was built for exactly these free directions.
    pub fn matches(&self, key: &[u64]) -> bool {
        self.key == key
    }

    /// `M^-1 r` and the iterations it took (`None` when it cannot be solved to
    /// [`CG_ACCEPTABLE`]).
    pub fn solve(&self, block: &FingerBlockData, r: &[f64]) -> Option<(Vec<f64>, u32)> {
        conjugate_gradients(
            |p, out| self.op.apply(block, p, out),
            |r, z| self.op.precondition(block, r, z),
            r,
        )
    }

    /// `rhs += Et g` and `S += S_i`: the finger's part of the Schur complement system.
    pub fn add_schur(&self, g: &[f64], s: &mut DMatrix<f64>, rhs: &mut [f64]) {
        for (r, col) in self.et.iter().enumerate() {
            rhs[r] += col.iter().zip(g).map(|(a, b)| a * b).sum::<f64>();
        }
        *s += &self.schur;
    }

    /// `v <- v - U dlambda`.
    pub fn subtract_columns(&self, dlambda: &[f64], v: &mut [f64]) {
        for (u, &l) in self.u.iter().zip(dlambda) {
            if l != 0.0 {
                for (x, ui) in v.iter_mut().zip(u) {
                    *x -= ui * l;
                }
            }
        }
    }
}

/// `S = Et U`, symmetrised (exact arithmetic gives a symmetric matrix; the inexact solves do
/// not).
fn schur_of(et: &[Vec<f64>], u: &[Vec<f64>]) -> DMatrix<f64> {
    let m = et.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut s = DMatrix::zeros(m, m);
    for r in 0..m {
        for c in 0..m {
            if !u[c].is_empty() {
                s[(r, c)] = dot(&et[r], &u[c]);
            }
        }
    }
    (&s + s.transpose()) * 0.5
}

/// Preconditioned conjugate gradients for `A x = b` (`A` symmetric positive definite, applied
/// by `apply`; the symmetric positive definite preconditioner applied by `precondition`,
/// `z = B^-1 r`), from `x = 0`. Returns `x` and the
/// iterations, or `None` when the residual did not fall to [`CG_ACCEPTABLE`] of `|b|`.
pub(crate) fn conjugate_gradients(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
) -> Option<(Vec<f64>, u32)> {
    let n = b.len();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot = |a: &[f64], c: &[f64]| a.iter().zip(c).map(|(x, y)| x * y).sum::<f64>();
    let b_norm = norm(b);
    let mut x = vec![0.0; n];
    if b_norm == 0.0 || !b_norm.is_finite() {
        return b_norm.is_finite().then_some((x, 0));
    }
    let mut r = b.to_vec();
    let mut z = vec![0.0; n];
    precondition(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut ap = vec![0.0; n];
    let max = CG_ITERATIONS_PER_ROOT * ((n as f64).sqrt().ceil() as usize).max(1);
    let mut done = 0;
    for it in 1..=max {
        done = it;
        apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if pap.is_nan() || pap <= 0.0 {
            break;
        }
        let alpha = rz / pap;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        let r_norm = norm(&r);
        if r_norm <= CG_TOLERANCE * b_norm {
            return Some((x, it as u32));
        }
        precondition(&r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
    }
    // Out of iterations (or a breakdown): the true residual decides.
    apply(&x, &mut ap);
    let residual: Vec<f64> = b.iter().zip(&ap).map(|(bi, a)| bi - a).collect();
    (norm(&residual) <= CG_ACCEPTABLE * b_norm).then_some((x, done as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CG on a small symmetric positive definite system meets the direct solution.
    #[test]
    fn conjugate_gradients_solve_a_symmetric_positive_definite_system() {
        let n = 30;
        // A 1-D Laplacian plus a diagonal shift: well-posed, not diagonal.
        let a = DMatrix::from_fn(n, n, |i, j| match (i as i64 - j as i64).abs() {
            0 => 2.5 + i as f64 * 0.1,
            1 => -1.0,
            _ => 0.0,
        });
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let inv: Vec<f64> = (0..n).map(|i| 1.0 / a[(i, i)]).collect();
        let (x, its) = conjugate_gradients(
            |p, out| {
                let v = &a * nalgebra::DVector::from_column_slice(p);
                out.copy_from_slice(v.as_slice());
            },
            |r, z| {
                for ((zi, ri), m) in z.iter_mut().zip(r).zip(&inv) {
                    *zi = ri * m;
                }
            },
            &b,
        )
        .expect("converges");
        let direct = a
            .clone()
            .cholesky()
            .unwrap()
            .solve(&nalgebra::DVector::from_column_slice(&b));
        // CG_TOLERANCE on the residual times the condition number (< 10 here).
        for (g, w) in x.iter().zip(direct.iter()) {
            assert!((g - w).abs() <= 1e-10, "{g} vs {w}");
        }
        assert!(its as usize <= n);
    }

    #[test]
    fn a_zero_right_hand_side_needs_no_iteration() {
        let (x, its) =
            conjugate_gradients(|_, _| unreachable!(), |_, _| unreachable!(), &[0.0, 0.0])
                .expect("trivial");
        assert_eq!((x, its), (vec![0.0, 0.0], 0));
    }
}
