//! The native solver: a semismooth Newton method for the grasp program that exploits its
//! structure (model.md). Each finger's compliance block is dense but fixed, fingers
//! couple only through the `m <= 6 + fingers` equality rows, and every element has one small
//! cone; so each Newton step factorises one reduced matrix per finger (faer's dense Cholesky,
//! cached while the stick / slip / separation pattern stays the same) and solves an `m x m`
//! Schur complement. It accepts a starting point (the previous step's or iterate's forces and
//! multipliers), so a hand-off step whose contact sets do not change costs one step and no
//! factorisation. Where the Newton iteration stalls, a primal-dual interior-point method takes
//! over and the Newton method polishes its answer.
//!
//! Files, layered: the shared files here at the bottom, then `interior/`, then `newton/` (whose
//! iteration hands over to the interior point), then this entry. The element sets, with their
//! projections and conic rows, are the program's (`crate::program::cones`).
//!
//! - this file: [`NativeSolver`], the entry (the fingers' fixed blocks and their factor caches);
//! - [`native_result`]: how a native solve ended (status, last iterate, work counted);
//! - [`finger_block`]: one finger's fixed data (compliance block, equality columns, cones);
//! - [`dense_cholesky`]: the in-place Cholesky shared by both methods;
//! - [`parallel_vectors`]: vector arithmetic of the FFT path on all cores, with sums that do
//!   not depend on the number of threads;
//! - [`newton`]: the semismooth Newton method: [`newton::cold_start`] (which elements start in
//!   contact), [`newton::linearisation`] (residual and Newton directions),
//!   [`newton::reduced_system`] over [`newton::reduced_factor`] (dense, factorised) and
//!   [`newton::reduced_iterative`] (FFT operator, conjugate gradients, with
//!   [`newton::free_operator`]), [`newton::newton_step`] and [`newton::projected_step`] (one
//!   step), [`newton::semismooth_newton`] (the iteration), [`newton::kkt_derivative`] (the
//!   solution's derivative at its active set), and the unit tests `newton_tests`;
//! - [`interior`]: the interior-point fallback, [`interior::interior_point`].

pub(crate) mod dense_cholesky;
pub(crate) mod finger_block;
pub(crate) mod interior;
pub(crate) mod native_result;
pub(crate) mod newton;
pub(crate) mod parallel_vectors;

use std::sync::Arc;

use crate::model::grasp_model::GraspModel;
use crate::model::patch_compliance::PatchCompliance;
use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;

use finger_block::FingerBlockData;
use native_result::NativeResult;
use newton::cold_start;
use newton::newton_step::FactorCache;
use newton::semismooth_newton::{self, Limits};

/// The native solver's workspace for one program: the fingers' fixed blocks and their cached
/// factors.
pub(crate) struct NativeSolver {
    blocks: Vec<FingerBlockData>,
    caches: Vec<FactorCache>,
}

impl NativeSolver {
    /// Copies the fixed data of `program`'s blocks from `model`.
    pub(crate) fn new(model: &GraspModel, program: &ConeProgram) -> Self {
        let mut blocks: Vec<FingerBlockData> = program
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
        // The shared springs' coordinates: dense blocks, free of cones.
        let springs = &program.blocks[model.fingers.len()..];
        for (b, s) in springs.iter().zip(&program.springs) {
            let compliance = PatchCompliance::Dense(Arc::clone(&s.compliance_m_per_n));
            let scale = program.compliance_scale;
            let free = vec![true; b.elements];
            blocks.push(FingerBlockData::new(
                b,
                &compliance,
                scale,
                &program.equality,
                free,
            ));
        }
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
        let result =
            semismooth_newton::run(&self.blocks, &mut self.caches, program, starts, limits);
        // The work vectors are kept from one Newton step to the next, not while the answer is
        // read out.
        self.blocks.iter().for_each(FingerBlockData::release_work);
        result
    }

    /// At most `limits.max_iterations` Newton steps on `program` from `start`, kept where they
    /// end whether or not they converge (no interior-point method after a stall); `None` when
    /// `start` is not an iterate of `program`.
    pub(crate) fn steps(
        &mut self,
        program: &ConeProgram,
        start: &Iterate,
        limits: Limits,
    ) -> Option<NativeResult> {
        let result =
            semismooth_newton::steps(&self.blocks, &mut self.caches, program, start, limits);
        self.blocks.iter().for_each(FingerBlockData::release_work);
        result
    }
}
