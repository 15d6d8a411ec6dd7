//! The sequential (coulomb) solve does not give up early. On the fixture
//! grasp the plain fixed-point iteration `F <- T(F)` from the energy model's forces (the
//! solver with `min_relaxation = 1`) reaches an iterate whose Tresca program has no solution,
//! which the earlier code reported as "cannot hold"; the damped iteration backs off towards
//! the last feasible iterate and converges. The
//! fixed point is then checked independently: one Clarabel solve of the Tresca program at
//! its radii `mu F` reproduces its forces, or shows it to be that program's minimiser
//! (`support::fixed_point_confirmed`).

mod support;

use grasp_model::{GraspModel, LoadedScene, SolveOptions, SolveStatus, SolverChoice};

fn fixture() -> LoadedScene {
    let path = format!(
        "{}/fixtures/coulomb_damped_fixed_point.json",
        env!("CARGO_MANIFEST_DIR")
    );
    LoadedScene::from_json_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn the_undamped_iteration_fails_where_the_damped_one_finds_the_fixed_point() {
    let scene = fixture();
    let model = GraspModel::from_loaded(&scene).unwrap();
    // The undamped iteration (no back-off: the smallest relaxation is 1) stops at an iterate
    // whose program has no solution.
    let undamped = support::solve_with_options(
        &serde_json::to_value(&scene.scene).unwrap(),
        SolveOptions {
            solver: SolverChoice::Native,
            min_relaxation: 1.0,
            ..SolveOptions::default()
        },
    );
    assert_eq!(
        undamped.status,
        SolveStatus::NoEquilibrium,
        "{:?}",
        undamped.reason
    );
    let k = undamped.sequential.unwrap().iterations;
    assert!(
        k >= 2,
        "the first iterate is always feasible from the energy model's forces"
    );
    // The damped sequential solve converges, having backed off at least once.
    // A fixed point is known to its sequential tolerance; it is tightened to the reference
    // of the equivalence test so that the check below compares the fixed point, not where
    // the iteration stopped.
    let sol = support::solve_with_options(
        &serde_json::to_value(&scene.scene).unwrap(),
        SolveOptions {
            solver: SolverChoice::Native,
            sequential_tolerance: support::SEQUENTIAL_REFERENCE,
            max_sequential_iterations: 200,
            ..SolveOptions::default()
        },
    );
    assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
    let report = sol.sequential.unwrap();
    assert!(
        report.converged && report.damped_iterations > 0,
        "{report:?}"
    );
    // Independent check of the fixed point by Clarabel at its radii.
    let d = support::fixed_point_confirmed(&model, &sol)
        .expect("Clarabel at the fixed point's radii confirms it");
    println!(
        "sequential damping: the undamped iteration fails at iterate {k}; the damped one \
         converges in {} iterates ({} damped); Clarabel at the fixed point's radii confirms it (forces within {d:.1e} of the load; \
         confirmed when within 1e-8 or when the fixed point is feasible with the lower energy)",
        report.iterations, report.damped_iterations
    );
}
