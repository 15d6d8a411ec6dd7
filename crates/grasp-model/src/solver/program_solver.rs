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

use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::option_names;
use crate::program::cone_program::ConeProgram;
use crate::solver::native::{Iterate, Limits, NativeSolver, NativeStatus};
use crate::solver::options::{SolveOptions, SolverChoice};

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
}

impl ProgramSolver {
    pub(crate) fn new(program: ConeProgram) -> Self {
        ProgramSolver {
            program,
            native: None,
            clarabel: None,
            last: None,
            trail: Trail::default(),
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

    /// Solves the program as it stands with the backend of `options.solver`.
    pub(crate) fn solve(
        &mut self,
        model: &GraspModel,
        options: &SolveOptions,
        start: Start<'_>,
    ) -> Result<ConvexRun, ModelError> {
        // The program's data: the prediction's input, and recorded with the solution.
        let data = data_of(&self.program);
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
        let result = native.solve(program, &starts, limits);
        let native_time = clock.elapsed().as_secs_f64();
        let why = match result.status {
            NativeStatus::Converged => {
                return Ok(ConvexRun {
                    outcome: ConvexOutcome::Solved {
                        reduced_accuracy: false,
                        x: result.iterate.x,
                        multipliers: result.iterate.lambda,
                    },
                    iterations: result.iterations,
                    factorisations: result.factorisations,
                    solver_time_s: native_time,
                    answered_by: SolverKind::Native,
                    fallback: None,
                })
            }
            NativeStatus::Stalled(why) => format!(
                "the native solver did not converge in {} Newton steps ({why})",
                result.iterations
            ),
        };
        let mut run = self.solve_clarabel(model, options)?;
        run.iterations += result.iterations;
        run.factorisations += result.factorisations;
        run.solver_time_s += native_time;
        run.fallback = Some(match (&run.outcome, options.solver) {
            (ConvexOutcome::Infeasible(_), _) => {
                format!("{why}; Clarabel certified that the program has no solution")
            }
            (_, SolverChoice::Auto) => format!("{why}; Clarabel answered"),
            _ => why.clone(),
        });
        if options.solver == SolverChoice::Native {
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
        Ok(run)
    }
}
