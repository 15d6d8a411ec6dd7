//! Grid continuation: a cold native solve of fine FFT patches starts from the answer of the
//! same program on grids twice as coarse ([`crate::program::coarse_program`] over
//! `crate::model::grid_coarsening`'s model), that one from a coarser, down to
//! `MIN_COARSE_SIDE` elements a side. Each level's forces, spread evenly over the fine
//! elements, and its equality multipliers (the object's motion and the approaches, the same
//! rows in every level) are the next level's start, whose first Newton steps are inexact while
//! the contact set settles.
//!
//! On a rough or ridged patch the contact set is many islands; a cold start on the fine grid
//! spends most of its Newton steps finding them, each step an operator product per
//! conjugate-gradient iteration on the fine grid. On the coarse grid the same search costs a
//! quarter as much per step, and the fine grid then only moves the islands' edges. A coarse
//! level is solved to [`COARSE_TOLERANCE`] only, the fine one to the solve's tolerance. The
//! work of every level is counted in the solve's totals.

use crate::model::grasp_model::GraspModel;
use crate::program::coarse_program::CoarseProgram;
use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;
use crate::solver::native::native_result::{Counts, NativeStatus};
use crate::solver::native::newton::semismooth_newton::Limits;
use crate::solver::native::NativeSolver;

/// The tolerance a coarse level is solved to (at most; a looser fine tolerance is kept): its
/// answer is only the next level's start, whose own solve reaches the fine tolerance. Measured
/// (29 November 2026, `grasp solve --solver native`, one run each) against the fine tolerance
/// (1e-10) on every level, the answers the same to 1e-14 relative: the rough pad of
/// `examples/rough_sphere_on_flat.json` at 1024 x 1024 198 conjugate-gradient iterations in all
/// instead of 256 (2.63 s instead of 2.97 s); at 256 x 256 130 instead of 159; the ridged pad
/// at 256 x 256 84 instead of 109. 1e-4 saves a few more iterations (191 at 1024) but took
/// longer on the frictional pad in the same minute; 1e-6 saves a third less.
const COARSE_TOLERANCE: f64 = 1e-5;

/// One coarse level: its program, its native solver and the level below it (if any).
pub(crate) struct CoarseLevel {
    coarse: CoarseProgram,
    solver: NativeSolver,
    below: Option<Box<CoarseLevel>>,
}

/// True when a cold start of `model` gains from a coarser grid's answer: some patch is
/// textured (its contact is islands the cold start's bearing area only bounds) or carries
/// friction (its stick and slip zones settle over several Newton steps). A smooth frictionless
/// patch starts at its Hertz circle (`crate::solver::native::newton::cold_start`), which is
/// the answer within a step or two: the Hertz sphere of `grasp bench` at 256 x 256 takes 3
/// Newton steps cold and 11 in all with the coarse levels.
fn worth_continuing(model: &GraspModel) -> bool {
    model
        .fingers
        .iter()
        .any(|f| f.patch.textured || f.n_tangential > 0)
}

impl CoarseLevel {
    /// The levels below `model` and its `program` (`None`: the model gains nothing from
    /// them ([`worth_continuing`]) or does not coarsen, or a coarse compliance could not be
    /// allocated, and the solve starts cold as it would).
    pub(crate) fn new(model: &GraspModel, program: &ConeProgram) -> Option<Self> {
        if !worth_continuing(model) {
            return None;
        }
        let twin = model.coarsened().ok()??;
        let coarse = CoarseProgram::new(program, &twin.fine_grids, &twin.coarsened);
        let solver = NativeSolver::new(&twin.model, &coarse.program);
        let below = CoarseLevel::new(&twin.model, &coarse.program).map(Box::new);
        Some(CoarseLevel {
            coarse,
            solver,
            below,
        })
    }

    /// The start of a cold solve of `fine` (its data as set for the solve): this level's
    /// answer (itself started from the level below) prolonged; `None` when a level does not
    /// converge. The work of every level is added to `counts`.
    pub(crate) fn start(
        &mut self,
        fine: &ConeProgram,
        limits: Limits,
        counts: &mut Counts,
    ) -> Option<Iterate> {
        self.coarse.restrict(fine);
        let program = &self.coarse.program;
        let below = match &mut self.below {
            Some(level) => level.start(program, limits, counts),
            None => None,
        };
        let starts: Vec<&Iterate> = below.iter().collect();
        let limits = Limits {
            progress: None,
            tolerance: limits.tolerance.max(COARSE_TOLERANCE),
            ..limits
        };
        let result = self.solver.solve(program, &starts, limits);
        counts.add(result.counts());
        if result.status != NativeStatus::Converged {
            return None;
        }
        Some(Iterate {
            x: self.coarse.prolong(&result.iterate.x, fine.n_unknowns),
            lambda: result.iterate.lambda,
        })
    }
}
