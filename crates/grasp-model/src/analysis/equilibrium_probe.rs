//! Whether the coulomb law admits another equilibrium at the failing end of a margin's
//! bracket, where the search's choice decides the margin.
//!
//! The coulomb law's incremental problem need not have one solution (Klarbring 1990: large
//! friction with strong normal-tangential coupling). A margin search follows the equilibrium
//! its warm-started solves reach from the state that held; at the failing end it probes for
//! another: the step from the margin's state to the failing magnitude is solved again three
//! ways, each on a solver of its own: by the chosen solver (the path; when it holds there, the
//! search reached its failing end from another state and the probe stops), by the same
//! solver's fixed point started cold (no previous forces, no warm start: the same slip memory),
//! and by the other solver. When one answer holds and the path's does not (or the reverse), and both carry
//! forces that differ at some finger by more than [`DISTINCT_FRACTION`] of the load scale (or
//! the path found no equilibrium), the law admits two equilibria there that disagree on
//! whether the grasp survives, and the margin says so
//! ([`crate::DirectionMargin::other_equilibrium`]). Answers whose forces agree are one
//! equilibrium, whatever the verdicts (at the bracket's end a finger is at the edge of sliding
//! as a whole, and two solvers' round-off can judge it either way). Two equilibria that both
//! fail leave the margin as it is, and are not reported: past a margin a finger slides as a
//! whole, the object's motion is then path dependent, and the solvers land on different sliding
//! states (the cylinder hand-off twisted about z: a1 sliding by the native solver, a2 by
//! Clarabel, 0.019 N apart). The energy model's program is convex: no probe.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::analysis::margin_report::{holds, Failure};
use crate::analysis::margin_trial::{Fails, Held, Search};
use crate::error::ModelError;
use crate::number_text::Readable;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::{Solution, SolveStatus};

/// Two answers whose forces on some finger (normal and tangential, as one vector) differ by
/// more than this fraction of the load scale are two equilibria: the solves balance the load to
/// about 1e-10 of it (Clarabel's reduced-accuracy answers to about 1e-5), and a difference below
/// the margins' own tolerance (1e-3 by default) could not move a margin beyond it.
pub const DISTINCT_FRACTION: f64 = 1e-3;

/// One way the probe solves the failing step.
#[derive(Clone, Copy)]
enum Way {
    /// The chosen solver, warm, as the search solves it.
    Path,
    /// The chosen solver's fixed point started cold.
    Cold,
    /// The other solver.
    Other,
}

impl Search<'_> {
    /// What the probe at the failing end `fails` of the bracket above `held` found: `None`
    /// when every answer agrees (or no probe applies: the energy model, a failure proved by the
    /// load capacity, `probe` false), else the two equilibria in words.
    pub(crate) fn other_equilibrium(
        &mut self,
        held: &Held,
        fails: &Fails,
        probe: bool,
    ) -> Result<Option<String>, ModelError> {
        if !probe || self.model.kind() != ModelKind::Coulomb || fails.s >= self.capacity_n {
            return Ok(None);
        }
        // A solve the solver cannot take (Clarabel and an FFT operator too large to write
        // out) leaves its probe out; the margin stands whatever the probe.
        let Ok(path) = self.solve_by(Way::Path, held, fails.s) else {
            return Ok(None);
        };
        // The search reached its failing end from another state (a bisection's earlier one, a
        // prediction's start): from the margin's state the step holds, and the probe has no
        // failing answer to set the others against.
        if path
            .as_ref()
            .is_some_and(|p| holds(self.model, p, self.exempt).is_ok())
        {
            return Ok(None);
        }
        for way in [Way::Cold, Way::Other] {
            let Ok(probe) = self.solve_by(way, held, fails.s) else {
                continue;
            };
            if let Some(words) = self.distinct(&path, &probe, way, fails.s) {
                return Ok(Some(words));
            }
        }
        Ok(None)
    }

    /// The step from `held`'s state ramped to `s` N, solved `way`: the last solve's answer
    /// (at `s`, or the first step of the ramp without forces).
    /// Every way solves on a solver of its own: the search's solver (kept from step to step
    /// along a hand-off) keeps its warm start as the search left it.
    fn solve_by(&mut self, way: Way, held: &Held, s: f64) -> Result<Option<Solution>, ModelError> {
        let mut options = *self.solver.options();
        match way {
            Way::Path => {}
            Way::Cold => options.warm_start = false,
            Way::Other => options.solver = options.solver.other(),
        }
        let mut solver = GraspSolver::new(Arc::clone(self.solver.shared_model()), options);
        let mut state = held.state.clone();
        let mut last = None;
        for p in self.ramp(held.s, s) {
            if matches!(way, Way::Cold) {
                forget_forces(&mut state);
            }
            let inputs = self.inputs_at(p);
            let sol = solver.solve_step(&inputs, &mut state)?;
            self.solves += 1;
            let stop = !sol.status.has_forces();
            last = Some(sol);
            if stop {
                break;
            }
        }
        Ok(last)
    }

    /// The two equilibria in words, when `probe` (solved `way`) is one and differs from
    /// `path` at `s` N (or `path` found none).
    fn distinct(
        &self,
        path: &Option<Solution>,
        probe: &Option<Solution>,
        way: Way,
        s: f64,
    ) -> Option<String> {
        let probe = probe.as_ref().filter(|p| p.status.has_forces())?;
        let path = path.as_ref()?;
        let chosen = self.solver.options().solver;
        let by = match way {
            Way::Cold => format!("{chosen} started cold"),
            _ => format!("the other solver ({})", chosen.other()),
        };
        if path.status == SolveStatus::NoConvergence {
            // A stall says nothing of the path's equilibrium: nothing to compare.
            return None;
        }
        // Beyond the margin the grasp fails on either branch when the probe's fails too: the
        // margin stands, whichever the law picks.
        let probe_holds = holds(self.model, probe, self.exempt).is_ok();
        let path_holds = holds(self.model, path, self.exempt).is_ok();
        if probe_holds == path_holds {
            return None;
        }
        if path.status == SolveStatus::NoEquilibrium {
            return Some(format!(
                "at {} N {by} finds an equilibrium ({}) where {chosen} from the margin's state \
                 finds none",
                Readable(s),
                self.verdict(probe)
            ));
        }
        let (finger, gap) = largest_difference(path, probe)?;
        (gap > DISTINCT_FRACTION * self.load_n).then(|| {
            format!(
                "two equilibria at {} N from the margin's state: {chosen} ({}) and {by} ({}) \
                 differ by {} N at {finger}; the margin follows the first",
                Readable(s),
                self.verdict(path),
                self.verdict(probe),
                Readable(gap)
            )
        })
    }

    /// `holds` or how the grasp fails in `sol`.
    fn verdict(&self, sol: &Solution) -> String {
        match holds(self.model, sol, self.exempt) {
            Ok(()) => "holds".into(),
            Err(Failure::Slides { finger }) => format!("{finger} slides"),
            Err(Failure::NoEquilibrium { .. }) => "no equilibrium".into(),
            Err(Failure::NoConvergence { .. }) => "no convergence".into(),
        }
    }
}

/// Drops the previous forces of `state` (the sequential solve's warm start), keeping its slip
/// memory and history: the next solve starts cold on the same path.
fn forget_forces(state: &mut ContactState) {
    for f in &mut state.fingers {
        f.normal_forces_n = None;
        f.earlier.clear();
    }
}

/// The finger at which the forces of `a` and `b` differ most, and by how much (N): the length
/// of the difference of normal plus tangential force vectors.
pub(crate) fn largest_difference(a: &Solution, b: &Solution) -> Option<(String, f64)> {
    a.fingers
        .iter()
        .zip(&b.fingers)
        .map(|(fa, fb)| {
            // The normals are the finger's, the tangential forces orthogonal to them.
            let dq = Vector3::from(fa.tangential_force_n) - Vector3::from(fb.tangential_force_n);
            let dp = fa.normal_force_n - fb.normal_force_n;
            (fa.name.clone(), dp.hypot(dq.norm()))
        })
        .max_by(|x, y| x.1.total_cmp(&y.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::margin_search::tests::pinch;
    use crate::solve::step_inputs::StepInputs;
    use crate::solver::options::SolveOptions;

    /// Two answers of the pinch (two pads, weight 4 N shared by symmetry, 2 N of friction
    /// each) at commanded loads 10 N and 12 N differ by exactly the 2 N of each pad's normal
    /// force and nothing tangential: the comparison measures force vectors, to the solver
    /// tolerance (1e-9 of the load).
    #[test]
    fn answers_differ_by_their_force_vectors() {
        let model = pinch();
        let mut solver = GraspSolver::new(Arc::clone(&model), SolveOptions::default());
        let at = |solver: &mut GraspSolver, p: f64| {
            let mut inputs = StepInputs::of_scene(&model);
            inputs.loads_n = vec![p, p];
            solver.solve(&inputs).unwrap()
        };
        let (a, b) = (at(&mut solver, 10.0), at(&mut solver, 12.0));
        let (_, gap) = largest_difference(&a, &b).unwrap();
        assert!((gap - 2.0).abs() < 1e-9 * 12.0, "{gap}");
        let (_, none) = largest_difference(&a, &a).unwrap();
        assert_eq!(none, 0.0);
    }

    /// The decision, on the coulomb pinch pushed down (its friction capacity 2 mu P - W = 6
    /// N): a holding answer (3 N) set against a path that found no equilibrium (8 N) is
    /// reported; two holding answers are not; a path whose finger slides against a holding
    /// answer is reported when their forces differ by more than `DISTINCT_FRACTION` of the load
    /// scale (1 N), not when they differ by less (1e-5 N: round-off's order).
    #[test]
    fn only_a_holding_answer_where_the_path_fails_with_distinct_forces_is_reported() {
        use crate::analysis::margin_report::MarginOptions;
        use crate::analysis::margin_search::tests::{pinch_under, Undisturbed, DOWN};
        use crate::solve::solution::{ElementState, SolveStatus};
        let model = pinch_under("coulomb");
        let solve = SolveOptions::default();
        let undisturbed = Undisturbed::of(&model);
        let base_state = &undisturbed.state;
        let options = MarginOptions::default();
        let step = undisturbed.step(&model, &options);
        let mut solver = GraspSolver::new(Arc::clone(&model), solve);
        let search = step.search(&mut solver, DOWN, false);
        let at = |s: f64| {
            let mut state = base_state.clone();
            GraspSolver::new(Arc::clone(&model), solve)
                .solve_step(&search.inputs_at(s), &mut state)
                .unwrap()
        };
        let (holding, beyond) = (at(3.0), at(8.0));
        assert_eq!(
            beyond.status,
            SolveStatus::NoEquilibrium,
            "{:?}",
            beyond.reason
        );
        let words = search.distinct(&Some(beyond), &Some(holding.clone()), Way::Cold, 8.0);
        assert!(words.is_some_and(|w| w.contains("finds none")));
        let same = search.distinct(&Some(holding.clone()), &Some(at(3.0)), Way::Other, 3.0);
        assert_eq!(same, None);
        let sliding = |dp: f64| {
            let mut s = holding.clone();
            let f = &mut s.fingers[0];
            f.normal_force_n += dp;
            for e in &mut f.elements {
                e.state = ElementState::Slip;
            }
            (f.slip_count, f.stick_count) = (f.slip_count + f.stick_count, 0);
            s
        };
        let far = search.distinct(&Some(sliding(1.0)), &Some(holding.clone()), Way::Cold, 3.0);
        assert!(far.is_some_and(|w| w.contains("two equilibria") && w.contains("left slides")));
        let near = search.distinct(&Some(sliding(1e-5)), &Some(holding), Way::Cold, 3.0);
        assert_eq!(near, None);
    }
}
