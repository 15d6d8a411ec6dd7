//! The native solver: a semismooth Newton method for the grasp program that exploits its
//! structure (model.md; issue 9). Each finger's compliance block is dense but fixed, fingers
//! couple only through the `m <= 6 + fingers` equality rows, and every element has one small
//! cone; so each Newton step factorises one reduced matrix per finger (faer's dense Cholesky,
//! cached while the stick / slip / separation pattern stays the same) and solves an `m x m`
//! Schur complement. It accepts a starting point (the previous step's or iterate's forces and
//! multipliers), so a hand-off step whose contact sets do not change costs one step and no
//! factorisation.
//!
//! Files: [`element_cone`] with one file per cone ([`cone_nonnegative`], [`cone_friction`],
//! [`cone_tresca`]); [`finger_block`] (the fixed data); [`linearisation`] (residual and Newton
//! directions); [`reduced_factor`] (reduced matrix and factorisation); [`newton_step`];
//! [`semismooth_newton`] (the iteration).

pub(crate) mod cold_start;
pub(crate) mod cone_friction;
pub(crate) mod cone_nonnegative;
pub(crate) mod cone_tresca;
pub(crate) mod conic_rows;
pub(crate) mod element_cone;
pub(crate) mod finger_block;
pub(crate) mod free_operator;
pub(crate) mod interior_cones;
pub(crate) mod interior_point;
pub(crate) mod kkt_derivative;
pub(crate) mod linearisation;
pub(crate) mod newton_step;
pub(crate) mod projected_step;
pub(crate) mod projection;
pub(crate) mod reduced_factor;
pub(crate) mod reduced_iterative;
pub(crate) mod reduced_system;
pub(crate) mod semismooth_newton;

#[cfg(test)]
mod newton_tests;

use crate::model::grasp_model::GraspModel;
use crate::program::cone_program::ConeProgram;

use finger_block::FingerBlockData;
use newton_step::FactorCache;
use semismooth_newton::Limits;

/// A point of the iteration, scaled: forces `x` and equality multipliers `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub struct Iterate {
    /// Scaled forces (program layout).
    pub x: Vec<f64>,
    /// Scaled equality multipliers (equilibrium rows, then load rows).
    pub lambda: Vec<f64>,
}

/// How a native solve ended.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum NativeStatus {
    /// The KKT conditions hold to the tolerance.
    Converged,
    /// No convergence: why.
    Stalled(String),
}

/// The result of a native solve.
#[derive(Debug, Clone)]
pub(crate) struct NativeResult {
    pub status: NativeStatus,
    /// The last iterate (the solution when converged).
    pub iterate: Iterate,
    /// Newton steps taken.
    pub iterations: u32,
    /// Reduced matrices factorised (or, for the FFT operator, reduced systems prepared).
    pub factorisations: u32,
    /// Conjugate-gradient iterations of the reduced systems (the FFT operator's path).
    pub inner_iterations: u32,
}

impl NativeResult {
    /// The result `status` at `(x, lambda)` after the work `counts`.
    pub(crate) fn after(
        status: NativeStatus,
        x: Vec<f64>,
        lambda: Vec<f64>,
        counts: Counts,
    ) -> Self {
        NativeResult {
            status,
            iterate: Iterate { x, lambda },
            iterations: counts.newton_steps,
            factorisations: counts.factorisations,
            inner_iterations: counts.inner_iterations,
        }
    }
}

/// The work of a solve so far, carried from the Newton iteration to the interior-point method
/// and back.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Counts {
    /// Newton steps taken (interior-point iterations included).
    pub newton_steps: u32,
    /// Reduced matrices factorised (or, for the FFT operator, reduced systems prepared).
    pub factorisations: u32,
    /// Conjugate-gradient iterations of the reduced systems (the FFT operator's path).
    pub inner_iterations: u32,
}

/// The native solver's workspace for one program: the fingers' fixed blocks and their cached
/// factors.
pub(crate) struct NativeSolver {
    blocks: Vec<FingerBlockData>,
    caches: Vec<FactorCache>,
}

impl NativeSolver {
    /// Copies the fixed data of `program`'s blocks from `model`.
    pub(crate) fn new(model: &GraspModel, program: &ConeProgram) -> Self {
        let blocks: Vec<FingerBlockData> = program
            .blocks
            .iter()
            .zip(&model.fingers)
            .map(|(b, f)| {
                FingerBlockData::new(
                    b,
                    &f.compliance_m_per_n,
                    program.compliance_scale,
                    &program.equality,
                    cold_start::initial_contact(model, f),
                )
            })
            .collect();
        NativeSolver {
            caches: vec![Vec::new(); blocks.len()],
            blocks,
        }
    }

    /// True when some finger's compliance is an FFT operator too large to write out (no
    /// matrix for Clarabel).
    pub(crate) fn is_matrix_free(&self) -> bool {
        self.blocks.iter().any(FingerBlockData::is_matrix_free)
    }

    /// The fingers' fixed blocks.
    pub(crate) fn blocks(&self) -> &[FingerBlockData] {
        &self.blocks
    }

    /// Solves `program` from the candidate start with the smallest residual (none: cold).
    pub(crate) fn solve(
        &mut self,
        program: &ConeProgram,
        starts: &[&Iterate],
        limits: Limits,
    ) -> NativeResult {
        semismooth_newton::run(&self.blocks, &mut self.caches, program, starts, limits)
    }
}
