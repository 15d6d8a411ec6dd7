//! The strategy for a program without sequential structure (energy model, constant `mu`): one
//! convex solve, read into a [`Solution`].

use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::solve::readout::{build_solution, escape_reason, failed};
use crate::solve::residuals::{FrictionRule, SolvedWith};
use crate::solve::solution::{Solution, SolveStatus, SolverStats};
use crate::solver::options::SolveOptions;
use crate::solver::outcome::{ConvexOutcome, ConvexRun, Start};
use crate::solver::program_solver::ProgramSolver;

/// Adds a convex run's cost to `stats` and records who answered and why (the last run wins).
pub(crate) fn add_run(stats: &mut SolverStats, run: &ConvexRun) {
    stats.iterations += run.iterations;
    stats.factorizations += run.factorisations;
    stats.inner_iterations += run.inner_iterations;
    stats.solver_time_s += run.solver_time_s;
    stats.solver = run.answered_by;
    if run.fallback.is_some() {
        stats.fallback.clone_from(&run.fallback);
    }
}

/// Where a convex solve of this program starts under `options`.
pub(crate) fn start_of(options: &SolveOptions) -> Start<'static> {
    if options.warm_start {
        Start::Last
    } else {
        Start::Cold
    }
}

/// Solves the program of `ps` once (loads already set).
pub(crate) fn solve_once(
    ps: &mut ProgramSolver,
    model: &GraspModel,
    options: &SolveOptions,
    mut stats: SolverStats,
    clock: Instant,
) -> Result<Solution, ModelError> {
    let run = ps.solve(model, options, start_of(options))?;
    add_run(&mut stats, &run);
    let mu = ps.program.mu();
    Ok(match run.outcome {
        ConvexOutcome::Solved {
            reduced_accuracy,
            x,
            multipliers,
        } => {
            let solved_with = SolvedWith {
                rule: FrictionRule::Associated,
                mu: &mu,
                radii_n: None,
            };
            let mut out = build_solution(model, &ps.program, &x, &multipliers, stats, &solved_with);
            if reduced_accuracy {
                out.mark_reduced_accuracy();
            }
            out
        }
        ConvexOutcome::Infeasible(cert) => failed(
            model,
            SolveStatus::NoEquilibrium,
            escape_reason(model, &ps.program, &cert),
            clock,
            stats,
        ),
        ConvexOutcome::Failed { reason } => {
            failed(model, SolveStatus::NoConvergence, reason, clock, stats)
        }
    })
}
