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
//! quarter as much per step, and the fine grid then only moves the islands' edges.
//!
//! The levels are a nested iteration (full multigrid's order of work): the coarsest level (and
//! any level whose level below gave no answer) is solved cold, to [`COARSE_TOLERANCE`]; each
//! level above it takes [`NESTED_STEPS`] Newton step from the prolonged answer below and passes
//! on where that step ends, converged or not; only the fine grid is solved to the solve's
//! tolerance. A coarse level's answer differs from the fine one by its discretisation error (an
//! island edge, half a coarse element), so solving it more closely buys the fine start nothing.
//! While their contact sets settle, coarse Newton systems are solved to at most
//! [`COARSE_FORCING`] of their right-hand sides, and the fine grid's, started from the levels,
//! to at most [`CONTINUED_FORCING`]. The work of every level is counted in the solve's totals.

use crate::model::grasp_model::GraspModel;
use crate::program::coarse_program::CoarseProgram;
use crate::program::cone_program::ConeProgram;
use crate::solver::iterate::Iterate;
use crate::solver::native::native_result::{Counts, NativeStatus};
use crate::solver::native::newton::semismooth_newton::Limits;
use crate::solver::native::NativeSolver;

/// The tolerance the coarsest level is solved to (at most; a looser fine tolerance is kept):
/// its answer is only the next level's start.
const COARSE_TOLERANCE: f64 = 1e-2;

/// The loosest relative accuracy of a coarse level's Newton systems (the forcing term of
/// `crate::solver::native::newton::semismooth_newton`; the fine grid's is [`CONTINUED_FORCING`]
/// from the levels' start, 1e-4 from any other).
const COARSE_FORCING: f64 = 1e-2;

/// The loosest relative accuracy of the fine grid's Newton systems when its solve starts from
/// the coarse levels' answer (1e-4 from any other start): while its contact set settles only
/// the islands' edges move. Measured (29 November 2026, `grasp solve --solver native`, the
/// same answers), conjugate-gradient iterations in all against 1e-4, the Newton steps the
/// same: the rough pad at 1024 x 1024 76 against 80, at 256 x 256 63 against 70; the ridged
/// pad 41 against 43; the ridged pad pinch at 256 x 256 91 against 98; the frictional rough
/// pad 240 against 248. 1e-2 saved a few more (73 at 1024 x 1024) but took a Newton step more
/// there and on the frictional pad and the pinch.
pub(crate) const CONTINUED_FORCING: f64 = 1e-3;

/// Newton steps a level above the coarsest takes from the answer below it.
///
/// Measured (29 November 2026, `grasp solve --solver native`, one run each, the answers the
/// same to the solve's tolerance), conjugate-gradient iterations in all against the levels
/// each solved to 1e-5 with the fine grid's forcing (the rule before): the rough pad of
/// `examples/rough_sphere_on_flat.json` at 1024 x 1024 80 instead of 198 (the fine grid's
/// own 48 either way); at 256 x 256 70 instead of 130; the ridged pad at 256 x 256 43 instead
/// of 84; the frictional rough pad's energy-model start 100 instead of 213. Two steps a level
/// took 98 at 1024 x 1024, every level solved to 1e-2 101, the coarse forcing 1e-1 (with one
/// step) 78 but 58 on the fine grid instead of 48.
const NESTED_STEPS: u32 = 1;

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
/// Newton steps cold and 11 in all with the coarse levels (each then solved to 1e-5).
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
    /// answer prolonged, the nested step from the level below's answer where there is one
    /// ([`NESTED_STEPS`]), else a cold solve to [`COARSE_TOLERANCE`]; `None` when this level
    /// gives no answer (its cold solve does not converge, or its step ends at numbers that are
    /// not finite: the level above is then solved cold). The work of every level is added to
    /// `counts`.
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
        let limits = Limits {
            progress: None,
            forcing: COARSE_FORCING,
            ..limits
        };
        let answer = match below {
            Some(start) => nested_step(&mut self.solver, program, &start, limits, counts)?,
            None => solved(&mut self.solver, program, limits, counts)?,
        };
        Some(Iterate {
            x: self.coarse.prolong(&answer.x, fine.n_unknowns),
            lambda: answer.lambda,
        })
    }
}

/// [`NESTED_STEPS`] Newton steps of `solver` on `program` from `start`, where they end
/// (finite).
fn nested_step(
    solver: &mut NativeSolver,
    program: &ConeProgram,
    start: &Iterate,
    limits: Limits,
    counts: &mut Counts,
) -> Option<Iterate> {
    let limits = Limits {
        max_iterations: limits.max_iterations.min(NESTED_STEPS),
        ..limits
    };
    let result = solver.steps(program, start, limits)?;
    counts.add(result.counts());
    let it = result.iterate;
    let finite = it.x.iter().chain(&it.lambda).all(|v| v.is_finite());
    finite.then_some(it)
}

/// `program` solved cold by `solver` to [`COARSE_TOLERANCE`] (`None`: no convergence).
fn solved(
    solver: &mut NativeSolver,
    program: &ConeProgram,
    limits: Limits,
    counts: &mut Counts,
) -> Option<Iterate> {
    let limits = Limits {
        tolerance: limits.tolerance.max(COARSE_TOLERANCE),
        ..limits
    };
    let result = solver.solve(program, &[], limits);
    counts.add(result.counts());
    (result.status == NativeStatus::Converged).then_some(result.iterate)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::scene_format::Scene;
    use crate::solver::native::newton::semismooth_newton::FORCING_MAX;

    /// `examples/<name>` with its grid set to `side x side` elements (FFT compliance).
    fn model_of(text: &str, side: usize) -> GraspModel {
        let text = text.replace("[64, 64]", &format!("[{side}, {side}]"));
        let scene = Scene::from_json_str(&text).expect("a valid scene");
        GraspModel::from_scene(&scene).expect("a usable model")
    }

    const LIMITS: Limits = Limits {
        tolerance: 1e-10,
        max_iterations: 100,
        forcing: FORCING_MAX,
        progress: None,
    };

    /// The rough and the ridged pad of `examples/` at 128 x 128 (16,384 frictionless unknowns,
    /// levels of 64 x 64 and 32 x 32): the 32 x 32 level is solved and the 64 x 64 one takes
    /// exactly the nested step (the levels' Newton steps are the 32 x 32 solve's, counted again
    /// on its own, plus [`NESTED_STEPS`]); the fine solve from the levels' start, its systems
    /// at [`CONTINUED_FORCING`] as a cold solve has them, converges to the answer of a plain
    /// cold solve (no coarse grid), every element force within 1e-7 of the largest. The
    /// program's energy is strictly convex (the compliance is positive definite), so its
    /// answer is unique and two solves to a relative 1e-10 agree to within that (measured:
    /// 1.2e-14 and 1.4e-14 of the largest); the start itself (the levels' answer, spread over
    /// the fine elements) is off by 31 % and 27 % of the largest, so the test would see a fine
    /// solve that did not move from it.
    #[test]
    fn the_nested_levels_start_the_same_answer_a_cold_solve_finds() {
        let scenes = [
            include_str!("../../../../examples/rough_sphere_on_flat.json"),
            include_str!("../../../../examples/ridged_sphere_on_flat.json"),
        ];
        for (k, text) in scenes.into_iter().enumerate() {
            let model = model_of(text, 128);
            let program = ConeProgram::with_scene_loads(&model);
            let mut level = CoarseLevel::new(&model, &program).expect("two coarse levels");
            assert!(
                level.below.is_some(),
                "scene {k}: a 64 x 64 and a 32 x 32 level"
            );
            let mut counts = Counts::default();
            let start = level
                .start(&program, LIMITS, &mut counts)
                .expect("a start from the coarse levels");
            let coarsest = level.below.as_mut().expect("the 32 x 32 level");
            let mut alone = Counts::default();
            let coarse_limits = Limits {
                forcing: COARSE_FORCING,
                ..LIMITS
            };
            solved(
                &mut coarsest.solver,
                &coarsest.coarse.program,
                coarse_limits,
                &mut alone,
            )
            .expect("the 32 x 32 level solves");
            assert_eq!(
                counts.newton_steps,
                alone.newton_steps + NESTED_STEPS,
                "scene {k}: the 64 x 64 level takes the nested step"
            );
            let mut native = NativeSolver::new(&model, &program);
            let continued = Limits {
                forcing: CONTINUED_FORCING,
                ..LIMITS
            };
            let from_levels = native.solve(&program, &[&start], continued);
            let cold = native.solve(&program, &[], LIMITS);
            assert_eq!(from_levels.status, NativeStatus::Converged, "scene {k}");
            assert_eq!(cold.status, NativeStatus::Converged, "scene {k}");
            let n = program.finger_unknowns();
            let (a, b) = (&from_levels.iterate.x[..n], &cold.iterate.x[..n]);
            let largest = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let worst = a
                .iter()
                .zip(b)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(
                worst <= 1e-7 * largest,
                "scene {k}: {worst:e} of {largest:e}"
            );
            let unsolved = start.x[..n]
                .iter()
                .zip(b)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(
                unsolved > 1e-7 * largest,
                "scene {k}: the start is the answer"
            );
        }
    }
}
