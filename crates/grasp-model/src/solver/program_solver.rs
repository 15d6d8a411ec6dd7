//! The backend layer: one assembled [`ConeProgram`] and the workspaces of the solvers that can
//! answer it (the native semismooth Newton solver, Clarabel as the reference), created on first
//! use. Each workspace notices by itself what changed in the program since its last solve.
//!
//! [`ProgramSolver::solve`] runs one convex solve with the chosen backend:
//! - `clarabel`: Clarabel's interior-point method;
//! - `native`: the native solver from the given start; if it does not converge, Clarabel is
//!   asked only to certify: an infeasible program is reported as such (certified by
//!   Clarabel), anything else as no convergence;
//! - `auto`: the native solver, falling back to Clarabel's answer when it does not converge
//!   (the run says why).

use std::sync::Arc;
use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::option_names;
use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;
use crate::solver::native::native_result::{NativeResult, NativeStatus};
use crate::solver::native::newton::semismooth_newton::Limits;
use crate::solver::native::NativeSolver;
use crate::solver::options::{SolveOptions, SolverChoice};
use crate::solver::solve_progress::SolveProgress;

use crate::solver::clarabel::{self, ClarabelWorkspace};
use crate::solver::outcome::{ConvexOutcome, ConvexRun, SolverKind, Start, MAX_NEWTON_ITERATIONS};
use crate::solver::predictor::{data_of, Trail};

/// A program and its solver workspaces.
pub(crate) struct ProgramSolver {
    /// The program; change it through its `set_*` methods between solves.
    pub program: ConeProgram,
    native: Option<NativeSolver>,
    clarabel: Option<ClarabelWorkspace>,
    /// The last solution, whichever backend gave it (the default warm start).
    last: Option<Iterate>,
    /// The last few solutions with their data, for the prediction.
    trail: Trail,
    /// Told the native solver's counts as it goes, when given.
    pub progress: Option<Arc<SolveProgress>>,
}

impl ProgramSolver {
    pub(crate) fn new(program: ConeProgram) -> Self {
        ProgramSolver {
            program,
            native: None,
            clarabel: None,
            last: None,
            trail: Trail::default(),
            progress: None,
        }
    }

    /// The last solution, whichever backend gave it.
    pub(crate) fn last(&self) -> Option<&Iterate> {
        self.last.as_ref()
    }

    /// The native solver's workspace (created if no native solve ran yet), with the program.
    pub(crate) fn native_workspace(&mut self, model: &GraspModel) -> (&NativeSolver, &ConeProgram) {
        let program = &self.program;
        let native = self
            .native
            .get_or_insert_with(|| NativeSolver::new(model, program));
        (native, program)
    }

    /// Solves the program as it stands with the backend of `options.solver`; options outside
    /// their ranges are an error ([`SolveOptions::validate`]); data that are not finite (a
    /// load or wrench that overflowed) are no convergence, reported without a solve.
    pub(crate) fn solve(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
        start: Start<'_>,
    ) -> Result<ConvexRun, ModelError> {
        options.validate()?;
        // The program's data: the prediction's input, and recorded with the solution.
        let data = data_of(&self.program);
        if let Some(run) = unsolvable(&data, options) {
            return Ok(run);
        }
        let run = match options.solver {
            SolverChoice::Clarabel => self.solve_clarabel(model, options),
            SolverChoice::Native | SolverChoice::Auto => {
                self.solve_native(model, options, start, &data)
            }
        }?;
        if let ConvexOutcome::Solved { x, multipliers, .. } = &run.outcome {
            let solution = Iterate {
                x: x.clone(),
                lambda: multipliers.clone(),
            };
            self.trail.push(data, solution.clone());
            self.last = Some(solution);
        }
        Ok(run)
    }

    fn solve_clarabel(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
    ) -> Result<ConvexRun, ModelError> {
        let settings = clarabel::settings(
            options.tolerance,
            options.max_iterations,
            options.time_limit_s,
        )?;
        let program = &self.program;
        let ws = self
            .clarabel
            .get_or_insert_with(|| ClarabelWorkspace::new(model, program));
        let run = ws.solve(program, options.tolerance, &settings)?;
        Ok(ConvexRun {
            outcome: run.outcome,
            iterations: run.iterations,
            factorisations: 0,
            inner_iterations: 0,
            solver_time_s: run.solve_time_s,
            answered_by: SolverKind::Clarabel,
            fallback: None,
        })
    }

    fn solve_native(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
        start: Start<'_>,
        data: &[f64],
    ) -> Result<ConvexRun, ModelError> {
        let clock = Instant::now();
        let program = &self.program;
        let native = self
            .native
            .get_or_insert_with(|| NativeSolver::new(model, program));
        let limits = Limits {
            tolerance: options.tolerance,
            max_iterations: options.max_iterations.min(MAX_NEWTON_ITERATIONS),
            progress: self.progress.as_deref(),
        };
        let predicted = match start {
            Start::Last => self.trail.predict(data),
            _ => None,
        };
        let starts: Vec<&Iterate> = match start {
            Start::Cold => Vec::new(),
            Start::Last => predicted.iter().chain(self.last.as_ref()).collect(),
            Start::At(it) => vec![it],
        };
        let mut result = native.solve(program, &starts, limits);
        let native_time = clock.elapsed().as_secs_f64();
        let matrix_free = native.is_matrix_free();
        let why = match result.status.clone() {
            NativeStatus::Converged => {
                // The iterate moves into the outcome (no copy on the hot path of a hand-off).
                let solved = ConvexOutcome::Solved {
                    reduced_accuracy: false,
                    x: std::mem::take(&mut result.iterate.x),
                    multipliers: std::mem::take(&mut result.iterate.lambda),
                };
                return Ok(native_run(solved, &result, native_time));
            }
            NativeStatus::Stalled(why) => format!(
                "the native solver did not converge in {} Newton steps ({why})",
                result.iterations
            ),
        };
        if matrix_free {
            // Clarabel needs the matrices: the stall is the outcome.
            let reason = format!(
                "no convergence: {why}; Clarabel cannot take over a model with the FFT \
                 compliance (setting `{}` to dense lets it, for patches of up to about 20,000 \
                 unknowns)",
                option_names::COMPLIANCE
            );
            let failed = ConvexOutcome::Failed { reason };
            return Ok(native_run(failed, &result, native_time));
        }
        let mut run = self.solve_clarabel(model, options)?;
        run.iterations += result.iterations;
        run.factorisations += result.factorisations;
        run.inner_iterations += result.inner_iterations;
        run.solver_time_s += native_time;
        after_native_stall(&mut run, options.solver, &why);
        Ok(run)
    }
}

/// A run the native solver answered (or whose stall is the outcome), with its work.
fn native_run(outcome: ConvexOutcome, result: &NativeResult, time_s: f64) -> ConvexRun {
    ConvexRun {
        outcome,
        iterations: result.iterations,
        factorisations: result.factorisations,
        inner_iterations: result.inner_iterations,
        solver_time_s: time_s,
        answered_by: SolverKind::Native,
        fallback: None,
    }
}

/// Clarabel's run after the native solver stalled (`why`): the fallback's reason, and with
/// `SolverChoice::Native` an answer of Clarabel's is no answer (the native solver was asked).
fn after_native_stall(run: &mut ConvexRun, choice: SolverChoice, why: &str) {
    run.fallback = Some(match (&run.outcome, choice) {
        (ConvexOutcome::Infeasible(_), _) => {
            format!("{why}; Clarabel certified that the program has no solution")
        }
        (_, SolverChoice::Auto) => format!("{why}; Clarabel answered"),
        _ => why.to_string(),
    });
    if choice == SolverChoice::Native {
        if let ConvexOutcome::Solved { .. } = run.outcome {
            run.outcome = ConvexOutcome::Failed {
                reason: format!(
                    "no convergence: {why}; Clarabel solves this program, so set `{}` to \
                     auto (or clarabel)",
                    option_names::SOLVER
                ),
            };
        }
    }
}

/// The outcome of a program whose data are not all finite (`None` when they are): no solver
/// is run on them (the native iteration would carry NaN to its iteration limit, Clarabel
/// might not return).
fn unsolvable(data: &[f64], options: &SolveOptions) -> Option<ConvexRun> {
    let bad = data.iter().filter(|v| !v.is_finite()).count();
    (bad > 0).then(|| ConvexRun {
        outcome: ConvexOutcome::Failed {
            reason: format!(
                "no convergence: {bad} of the program's {} data (gaps, loads, the wrench to \
                 balance, friction coefficients) are not finite, so nothing was solved; an \
                 extra wrench or load too large for double precision does this",
                data.len()
            ),
        },
        iterations: 0,
        factorisations: 0,
        inner_iterations: 0,
        solver_time_s: 0.0,
        answered_by: match options.solver {
            SolverChoice::Clarabel => SolverKind::Clarabel,
            SolverChoice::Native | SolverChoice::Auto => SolverKind::Native,
        },
        fallback: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_that_are_not_finite_are_no_convergence_without_a_solve() {
        assert!(unsolvable(&[1.0, -2.0, 1e300], &SolveOptions::default()).is_none());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let run = unsolvable(&[1.0, bad, bad], &SolveOptions::default()).unwrap();
            match run.outcome {
                ConvexOutcome::Failed { reason } => {
                    assert!(
                        reason.starts_with("no convergence: 2 of the program's 3"),
                        "{reason}"
                    )
                }
                other => panic!("{other:?}"),
            }
            assert_eq!((run.iterations, run.factorisations), (0, 0));
        }
    }
}
