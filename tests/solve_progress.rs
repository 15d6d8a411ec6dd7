//! Progress of a solve: what a solve given a `SolveProgress` reports while it runs.

mod support;
use support::*;

use grasp_model::{GraspModel, GraspSolver, SolveOptions, SolveStatus, StepInputs};

/// A solve given a [`SolveProgress`] reports its work as it goes: read from another thread
/// while the solve runs, the Newton steps and conjugate-gradient iterations never decrease,
/// and at the end they are the counts the solution's statistics give (an independent tally,
/// kept by the solver for the solution), on a patch on the FFT path (96 x 96 frictionless,
/// 9,216 unknowns: conjugate gradients run) and on a dense one (no CG iterations).
#[test]
fn a_solve_reports_monotone_progress_that_ends_at_its_statistics() {
    use grasp_model::SolveProgress;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    for side in [96, 21] {
        let mut v = example_json("hertz_sphere_on_flat.json");
        v["fingers"][0]["patch"]["grid"] = serde_json::json!([side, side]);
        let model = GraspModel::from_loaded(&scene(&v)).unwrap();
        let progress = Arc::new(SolveProgress::new());
        let mut solver = GraspSolver::new(model, SolveOptions::default());
        solver.set_progress(Arc::clone(&progress));
        let done = AtomicBool::new(false);
        let (solution, seen) = std::thread::scope(|s| {
            let reader = s.spawn(|| {
                let mut seen = vec![(0, 0)];
                while !done.load(Ordering::Relaxed) {
                    let now = (progress.newton_steps(), progress.cg_iterations());
                    let last = *seen.last().unwrap();
                    assert!(now.0 >= last.0 && now.1 >= last.1, "{last:?} then {now:?}");
                    seen.push(now);
                    std::thread::yield_now();
                }
                seen
            });
            let solution = solver.solve(&StepInputs::of_scene(solver.model())).unwrap();
            done.store(true, Ordering::Relaxed);
            (solution, reader.join().unwrap())
        });
        assert_eq!(solution.status, SolveStatus::Solved);
        let stats = &solution.solver;
        assert!(stats.iterations > 0);
        assert_eq!(
            progress.newton_steps(),
            stats.iterations,
            "{side}: {seen:?}"
        );
        assert_eq!(progress.cg_iterations(), stats.inner_iterations, "{side}");
        assert_eq!(stats.inner_iterations > 0, side == 96, "{side}: {stats:?}");
    }
}
