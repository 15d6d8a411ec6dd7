//! Options of a solve: which solver, tolerances, limits, warm starts.

use serde::{Deserialize, Serialize};

/// Which solver answers the convex programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverChoice {
    /// The native solver, falling back to Clarabel when it does not converge (the solution
    /// says so and why).
    #[default]
    Auto,
    /// The native semismooth Newton solver only (Clarabel is asked only to certify a program
    /// without solution).
    Native,
    /// Clarabel's interior-point method, the reference.
    Clarabel,
}

impl std::str::FromStr for SolverChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(SolverChoice::Auto),
            "native" => Ok(SolverChoice::Native),
            "clarabel" => Ok(SolverChoice::Clarabel),
            other => Err(format!(
                "unknown solver `{other}`; choose auto, native or clarabel"
            )),
        }
    }
}

impl std::fmt::Display for SolverChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SolverChoice::Auto => "auto",
            SolverChoice::Native => "native",
            SolverChoice::Clarabel => "clarabel",
        })
    }
}

/// Default smallest relaxation factor `omega` of the damped fixed-point iteration
/// ([`crate::solve::sequential`]) before an infeasible iterate is reported as the outcome
/// ([`SolveOptions::min_relaxation`]).
pub const MIN_RELAXATION: f64 = 1.0 / 64.0;

/// Options of a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Which solver answers.
    pub solver: SolverChoice,
    /// Tolerance of the scaled program: Clarabel's `tol_feas`, `tol_gap_abs`, `tol_gap_rel`;
    /// the native solver's bound on the natural residual relative to `max(1, max |x|)` and on
    /// the equality residual relative to `max(1, max |e|)` (dimensionless).
    pub tolerance: f64,
    /// Iteration limit of each convex solve: Clarabel's interior-point iterations; the native
    /// solver's Newton steps (at most [`crate::solver::outcome::MAX_NEWTON_ITERATIONS`]).
    pub max_iterations: u32,
    /// Time limit of each Clarabel solve, s.
    pub time_limit_s: f64,
    /// Sequential solve: converged when no element normal force changes by more than this
    /// many element force units `Fu` between iterates (dimensionless).
    pub sequential_tolerance: f64,
    /// Sequential solve: largest number of convex solves per step.
    pub max_sequential_iterations: u32,
    /// Sequential solve: smallest relaxation `omega` of the damped fixed-point iteration
    /// before an iterate without solution is reported as the outcome (dimensionless, in
    /// `(0, 1]`; `1` gives the plain, undamped iteration).
    pub min_relaxation: f64,
    /// Start each solve from the previous solution of the same program (the previous step or
    /// iterate), and a coulomb step from the previous step's forces; `false` starts every
    /// convex solve cold (for comparison).
    pub warm_start: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            solver: SolverChoice::Auto,
            tolerance: 1e-10,
            max_iterations: 200,
            time_limit_s: f64::INFINITY,
            sequential_tolerance: 1e-7,
            max_sequential_iterations: 50,
            min_relaxation: MIN_RELAXATION,
            warm_start: true,
        }
    }
}
