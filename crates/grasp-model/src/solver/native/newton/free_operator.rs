//! The reduced Newton matrix of one FFT finger over its free directions, as an operator, with
//! its preconditioner: what the conjugate-gradient solves of [`super::reduced_iterative`] and
//! [`super::projected_step`] apply (issue 21).
//!
//! Over the free directions `d_a` the system matrix is the one of [`super::reduced_factor`],
//!
//! ```text
//!   M[a, b] = d_a' P_i[k_a, k_b] d_b + delta_ab beta_a,      beta = (1 - theta)/(gamma theta),
//! ```
//!
//! symmetric positive definite, applied as `D_F' (P_i (D_F p)) + beta p` with one operator
//! product (Polonsky and Keer's conjugate gradients for the contact pressure, Wear 231, 1999,
//! and Vollebregt's NormCG/TangCG do the same over the contact area).
//!
//! The preconditioner is the inverse of the operator's circulant approximation restricted to
//! the free directions, `D_F' Pc^-1 D_F` ([`crate::model::circulant_inverse`]: it cancels the
//! compliance's `1/|k|` symbol, so the iterations stay nearly constant as the grid is refined,
//! where `M`'s diagonal, the same for every element, does nothing), on the directions where
//! `P` dominates `M`'s diagonal; on those where `beta` does (nearly sliding ones), `M`'s
//! diagonal. Both parts are symmetric positive definite, so the preconditioner is.

use crate::solver::native::finger_block::FingerBlockData;

use super::linearisation::Direction;

/// `M` and its preconditioner for one finger's free directions.
#[derive(Debug, Clone)]
pub(crate) struct FreeOperator {
    /// The free directions.
    pub free: Vec<Direction>,
    /// `beta_a` per free direction.
    beta: Vec<f64>,
    /// `1 / M[a, a]`.
    inverse_diagonal: Vec<f64>,
    /// Per free direction: preconditioned by the circulant inverse (`beta_a` below the
    /// compliance's part of `M[a, a]`), else by `1 / M[a, a]`.
    circulant: Vec<bool>,
    /// True when some direction is circulant-preconditioned.
    any_circulant: bool,
    /// `D_F` as `(a, local index, d_a[c])` over its nonzero entries, direction by direction.
    terms: Vec<(usize, usize, f64)>,
}

impl FreeOperator {
    /// The operator of `block` over `free`.
    pub fn new(block: &FingerBlockData, free: &[Direction]) -> Self {
        let beta: Vec<f64> = free
            .iter()
            .map(|d| (1.0 - d.theta) / (block.gamma * d.theta))
            .collect();
        // The compliance's part of `M[a, a]`, `d_a' P_i[k_a, k_a] d_a`.
        let compliance_part: Vec<f64> = free
            .iter()
            .map(|d| {
                let p: f64 = (0..block.dim)
                    .map(|c| d.dir[c] * d.dir[c] * block.compliance_diagonal(c * block.elements))
                    .sum();
                block.scale * p
            })
            .collect();
        let inverse_diagonal = compliance_part
            .iter()
            .zip(&beta)
            .map(|(p, b)| 1.0 / (p + b))
            .collect();
        let circulant: Vec<bool> = compliance_part
            .iter()
            .zip(&beta)
            .map(|(p, b)| b <= p)
            .collect();
        let terms = free
            .iter()
            .enumerate()
            .flat_map(|(a, d)| {
                (0..block.dim)
                    .filter(|&c| d.dir[c] != 0.0)
                    .map(move |c| (a, block.index(d.element, c), d.dir[c]))
            })
            .collect();
        FreeOperator {
            free: free.to_vec(),
            beta,
            inverse_diagonal,
            any_circulant: circulant.iter().any(|c| *c),
            circulant,
            terms,
        }
    }

    /// Free directions, the length of the vectors it applies to.
    pub fn len(&self) -> usize {
        self.free.len()
    }

    /// `D_F p` over the directions `keep` accepts (a local vector of the finger).
    fn scatter(
        &self,
        block: &FingerBlockData,
        p: &[f64],
        keep: impl Fn(usize) -> bool,
    ) -> Vec<f64> {
        let mut full = vec![0.0; block.len()];
        for &(a, i, coef) in &self.terms {
            if keep(a) {
                full[i] += coef * p[a];
            }
        }
        full
    }

    /// `out[a] += d_a' v_full[k_a]` over the directions `keep` accepts.
    fn gather(&self, full: &[f64], keep: impl Fn(usize) -> bool, out: &mut [f64]) {
        for &(a, i, coef) in &self.terms {
            if keep(a) {
                out[a] += coef * full[i];
            }
        }
    }

    /// `out = M p`.
    pub fn apply(&self, block: &FingerBlockData, p: &[f64], out: &mut [f64]) {
        let full = self.scatter(block, p, |_| true);
        let mut pfull = vec![0.0; block.len()];
        block.apply(&full, &mut pfull);
        for ((o, &pa), &b) in out.iter_mut().zip(p).zip(&self.beta) {
            *o = b * pa;
        }
        self.gather(&pfull, |_| true, out);
    }

    /// `z = D_F' Pc^-1 D_F r` on the circulant-preconditioned directions, `r / M[a, a]` on
    /// the others (the module's preconditioner).
    pub fn precondition(&self, block: &FingerBlockData, r: &[f64], z: &mut [f64]) {
        for (a, za) in z.iter_mut().enumerate() {
            *za = match self.circulant[a] {
                true => 0.0,
                false => r[a] * self.inverse_diagonal[a],
            };
        }
        if self.any_circulant {
            let full = self.scatter(block, r, |a| self.circulant[a]);
            let mut back = vec![0.0; block.len()];
            block.precondition(&full, &mut back);
            self.gather(&back, |a| self.circulant[a], z);
        }
    }

    /// `Et' = D_F' E_i'` as columns (one per equality row, each of length `n_free`).
    pub fn equality_columns(&self, block: &FingerBlockData) -> Vec<Vec<f64>> {
        (0..block.equality_rows())
            .map(|r| {
                self.free
                    .iter()
                    .map(|d| {
                        (0..block.dim)
                            .map(|c| d.dir[c] * block.equality(r, block.index(d.element, c)))
                            .sum()
                    })
                    .collect()
            })
            .collect()
    }
}
