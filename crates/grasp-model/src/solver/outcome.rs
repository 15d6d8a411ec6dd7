//! What one convex solve of the program concluded, solver-neutral: the outcome (solved,
//! infeasible with its certificate, failed), its cost, which solver answered, and where a
//! native solve starts.

use serde::{Deserialize, Serialize};

use crate::solver::iterate::Iterate;

/// Largest number of Newton steps of one native solve.
pub const MAX_NEWTON_ITERATIONS: u32 = 60;

/// A certificate that the program has no solution, solver-neutral: `z` with `E'z` in the dual
/// of the cones and `e'z < 0` (Farkas).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Certificate {
    /// Its equality part (scaled; read as the object's escape motion).
    pub equality: Vec<f64>,
    /// Per finger, the sum over elements of the tangential part's magnitude (which fingers
    /// would have to slide).
    pub finger_slip: Vec<f64>,
}

/// What one convex solve concluded.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum ConvexOutcome {
    /// Solved: scaled forces `x` and equality multipliers.
    Solved {
        /// Clarabel's "almost solved".
        reduced_accuracy: bool,
        /// Scaled forces (program layout).
        x: Vec<f64>,
        /// Scaled equality multipliers (equilibrium rows, then load rows).
        multipliers: Vec<f64>,
    },
    /// No point satisfies the constraints.
    Infeasible(Certificate),
    /// No answer: why.
    Failed {
        /// Reason for the user.
        reason: String,
    },
}

/// One convex solve: outcome and cost.
#[derive(Debug, Clone)]
pub(crate) struct ConvexRun {
    pub outcome: ConvexOutcome,
    /// Iterations: Newton steps (native) plus interior-point iterations (Clarabel).
    pub iterations: u32,
    /// Reduced matrices factorised by the native solver.
    pub factorisations: u32,
    /// Conjugate-gradient iterations of the native solver's reduced systems (FFT path).
    pub inner_iterations: u32,
    /// Time inside the solvers, s.
    pub solver_time_s: f64,
    /// The solver whose answer this is.
    pub answered_by: SolverKind,
    /// Why the native solver's answer was not used, when it was not.
    pub fallback: Option<String>,
}

/// Where a native solve starts.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Start<'a> {
    /// From the all-stick point.
    Cold,
    /// From the workspace's last solution (cold if there is none), or from the affine
    /// combination of its last few solutions ([`predictor`]) when the program's new data lie
    /// in the affine hull of theirs and the prediction has the smaller residual.
    Last,
    /// From this iterate (same program layout).
    At(&'a Iterate),
}

/// The solver that produced an answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// The native semismooth Newton solver.
    Native,
    /// Clarabel's interior-point method (the reference).
    Clarabel,
}

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SolverKind::Native => "native",
            SolverKind::Clarabel => "Clarabel",
        })
    }
}
