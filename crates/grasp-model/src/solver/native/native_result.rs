//! How a native solve ended: its status, its last iterate and the work it took (Newton steps,
//! factorisations, conjugate-gradient iterations), shared by the Newton iteration, the
//! interior-point method it hands over to, and the solver's entry.

use crate::solver::iterate::Iterate;

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

    /// Adds the work `counts` done before this solve (a grid continuation's coarse levels).
    pub(crate) fn add(&mut self, counts: Counts) {
        self.iterations += counts.newton_steps;
        self.factorisations += counts.factorisations;
        self.inner_iterations += counts.inner_iterations;
    }

    /// This result's work as counts.
    pub(crate) fn counts(&self) -> Counts {
        Counts {
            newton_steps: self.iterations,
            factorisations: self.factorisations,
            inner_iterations: self.inner_iterations,
        }
    }
}

impl Counts {
    /// Adds `other`'s work to this.
    pub(crate) fn add(&mut self, other: Counts) {
        self.newton_steps += other.newton_steps;
        self.factorisations += other.factorisations;
        self.inner_iterations += other.inner_iterations;
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
