//! The reduced Newton system of one finger, whichever way it is solved: factorised
//! ([`super::reduced_factor`], a dense compliance) or by conjugate gradients
//! ([`super::reduced_iterative`], the FFT operator). [`super::newton_step`] sees only the
//! verbs they share: build for a set of free directions, solve the first half (`r -> g`), add
//! the finger's part of the Schur complement, and solve the second half (`g, dlambda -> xi`).

use nalgebra::{DMatrix, DVector};

use crate::solver::native::finger_block::FingerBlockData;

use super::linearisation::Direction;
use super::reduced_factor::ReducedFactor;
use super::reduced_iterative::ReducedIterative;

/// One finger's reduced system, cached while its free directions stay the same.
#[derive(Debug, Clone)]
pub(crate) enum ReducedSystem {
    /// `M = L L'` and `W = L^-1 Et'`: `g = L^-1 r`.
    Factor(ReducedFactor),
    /// `U = M^-1 Et'` and `S_i = Et U`: `g = M^-1 r`.
    Iterative(ReducedIterative),
}

impl ReducedSystem {
    /// The system of `free` for `block` (`None` when it cannot be factorised or solved), in
    /// the storage of `spare` where it can be reused, and the conjugate-gradient iterations
    /// its building took.
    pub fn new(
        block: &FingerBlockData,
        free: &[Direction],
        fixed: &[Direction],
        key: Vec<u64>,
        spare: Option<Self>,
    ) -> Option<(Self, u32)> {
        if block.is_fft() {
            let s = ReducedIterative::new(block, free, fixed, key)?;
            let its = s.iterations;
            return Some((ReducedSystem::Iterative(s), its));
        }
        let spare = match spare {
            Some(ReducedSystem::Factor(f)) => Some(f),
            _ => None,
        };
        let f = ReducedFactor::new(block, free, fixed, key, spare)?;
        Some((ReducedSystem::Factor(f), 0))
    }

    /// True when built for exactly these free directions.
    pub fn matches(&self, key: &[u64]) -> bool {
        match self {
            ReducedSystem::Factor(f) => f.matches(key),
            ReducedSystem::Iterative(s) => s.matches(key),
        }
    }

    /// The free directions it was built for.
    pub fn free(&self) -> &[Direction] {
        match self {
            ReducedSystem::Factor(f) => &f.free,
            ReducedSystem::Iterative(s) => &s.free,
        }
    }

    /// The fixed directions it was built with.
    pub fn fixed(&self) -> &[Direction] {
        match self {
            ReducedSystem::Factor(f) => &f.fixed,
            ReducedSystem::Iterative(s) => &s.fixed,
        }
    }

    /// `r <- L^-1 r` (factor) or `r <- M^-1 r` (iterative); the conjugate-gradient iterations
    /// it took, `None` when the iterative solve fails.
    pub fn first_solve(&self, block: &FingerBlockData, r: &mut Vec<f64>) -> Option<u32> {
        match self {
            ReducedSystem::Factor(f) => {
                f.forward(r);
                Some(0)
            }
            ReducedSystem::Iterative(s) => {
                let (g, its) = s.solve(block, r)?;
                *r = g;
                Some(its)
            }
        }
    }

    /// Adds the finger's part of the Schur complement system: `S += W'W`, `rhs += W'g`
    /// (factor), `S += Et U`, `rhs += Et g` (iterative).
    pub fn add_schur(&self, g: &[f64], s: &mut DMatrix<f64>, rhs: &mut DVector<f64>) {
        match self {
            ReducedSystem::Factor(f) => {
                let w = &f.w;
                for r in 0..rhs.len() {
                    let wr = w.col(r);
                    rhs[r] += wr.iter().zip(g).map(|(a, b)| a * b).sum::<f64>();
                    for c in 0..=r {
                        let v: f64 = wr.iter().zip(w.col(c).iter()).map(|(a, b)| a * b).sum();
                        s[(r, c)] += v;
                        if c != r {
                            s[(c, r)] += v;
                        }
                    }
                }
            }
            ReducedSystem::Iterative(it) => it.add_schur(g, s, rhs.as_mut_slice()),
        }
    }

    /// `xi_F = L^-T (g - W dlambda)` (factor) or `g - U dlambda` (iterative).
    pub fn second_solve(&self, mut g: Vec<f64>, dlambda: &[f64]) -> Vec<f64> {
        match self {
            ReducedSystem::Factor(f) => {
                for (a, v) in g.iter_mut().enumerate() {
                    *v -=
                        f.w.row(a)
                            .iter()
                            .zip(dlambda)
                            .map(|(w, l)| w * l)
                            .sum::<f64>();
                }
                f.backward(&mut g);
                g
            }
            ReducedSystem::Iterative(s) => {
                s.subtract_columns(dlambda, &mut g);
                g
            }
        }
    }
}
