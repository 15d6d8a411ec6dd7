//! How far a solve has got, for a progress display: the Newton steps and conjugate-gradient
//! iterations so far, stored by the native solver once per Newton step as plain atomics (no
//! lock, no I/O) and read from any thread (a progress bar's).

use std::sync::atomic::{AtomicU32, Ordering};

/// The work of a solve so far, shared between the solver (writing) and a display (reading):
/// give it to [`crate::GraspSolver::set_progress`]. The counts never decrease: a solve of
/// several programs (a fallback, the sequential fixed point) adds each one's to the last.
#[derive(Debug, Default)]
pub struct SolveProgress {
    newton_steps: AtomicU32,
    cg_iterations: AtomicU32,
    /// The counts when the current program's solve began.
    base: [AtomicU32; 2],
}

impl SolveProgress {
    /// Nothing done yet.
    pub fn new() -> Self {
        SolveProgress::default()
    }

    /// Newton steps so far (the cold start's all-stick step included).
    pub fn newton_steps(&self) -> u32 {
        self.newton_steps.load(Ordering::Relaxed)
    }

    /// Conjugate-gradient iterations of the reduced systems so far (the FFT operator's path;
    /// 0 for dense patches).
    pub fn cg_iterations(&self) -> u32 {
        self.cg_iterations.load(Ordering::Relaxed)
    }

    /// A program's solve begins: its counts start from the totals so far.
    pub(crate) fn begin_program(&self) {
        self.base[0].store(self.newton_steps(), Ordering::Relaxed);
        self.base[1].store(self.cg_iterations(), Ordering::Relaxed);
    }

    /// The current program's solve has taken `newton_steps` steps and `cg_iterations`
    /// iterations.
    pub(crate) fn note(&self, newton_steps: u32, cg_iterations: u32) {
        let base = |i: usize| self.base[i].load(Ordering::Relaxed);
        let steps = base(0).saturating_add(newton_steps);
        let cg = base(1).saturating_add(cg_iterations);
        self.newton_steps.fetch_max(steps, Ordering::Relaxed);
        self.cg_iterations.fetch_max(cg, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two programs' counts add up; a count never goes back.
    #[test]
    fn counts_add_up_over_programs_and_never_decrease() {
        let p = SolveProgress::new();
        p.begin_program();
        p.note(3, 40);
        p.note(5, 70);
        assert_eq!((p.newton_steps(), p.cg_iterations()), (5, 70));
        p.begin_program();
        p.note(1, 9);
        assert_eq!((p.newton_steps(), p.cg_iterations()), (6, 79));
        p.note(0, 0);
        assert_eq!((p.newton_steps(), p.cg_iterations()), (6, 79));
    }
}
