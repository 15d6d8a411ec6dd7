//! The 200-step plate hand-off (thesis section 4.2.2): equilibrium at every step, symmetric
//! pairs stay symmetric, loads move monotonically from one pair to the other, and warm-started
//! stepping equals a fresh one-shot solve of the same grasp.

mod support;

use grasp_model::solve;
use grasp_model::{GraspModel, LoadedScene, SolveStatus};
use grasp_transfer::{Command, Schedule, StepRecord, TransferOptions};

fn load() -> (LoadedScene, Schedule) {
    support::transfer_example("plate_transfer")
}

fn run(options: TransferOptions) -> Vec<StepRecord> {
    support::step_transfer_example("plate_transfer", options)
}

#[test]
fn two_hundred_steps_in_equilibrium_symmetric_and_monotone() {
    let recs = run(TransferOptions::default());
    assert_eq!(recs.len(), 200);
    let p = |r: &StepRecord, n: &str| r.normal_force_n(n);
    let q = |r: &StepRecord, n: &str| {
        r.solution
            .finger(n)
            .map_or(0.0, |f| f.tangential_magnitude_n)
    };
    for r in &recs {
        assert_eq!(
            r.solution.status,
            SolveStatus::Solved,
            "t = {}: {:?}",
            r.time_s,
            r.solution.reason
        );
        let res = r.solution.residuals.unwrap();
        assert!(
            res.equilibrium_relative < 1e-9,
            "t = {}: {}",
            r.time_s,
            res.equilibrium_relative
        );
        assert!(res.cone_violation_relative < 1e-9);
        // Mirror symmetry x -> -x: P1 = P2, Q1 = Q2, P3 = P4, Q3 = Q4 within 1e-6 relative
        // (of the load scale: two cone solves at tolerance 1e-10 on the scaled program).
        let scale = r.solution.load_scale_n;
        for (a, b) in [("f1", "f2"), ("f3", "f4")] {
            assert!(
                (p(r, a) - p(r, b)).abs() <= 1e-6 * scale,
                "t = {}: P{a} {} vs P{b} {}",
                r.time_s,
                p(r, a),
                p(r, b)
            );
            assert!(
                (q(r, a) - q(r, b)).abs() <= 1e-6 * scale,
                "t = {}: Q{a} vs Q{b}",
                r.time_s
            );
        }
    }
    // Loads move monotonically from pair 1-2 to pair 3-4 (after the receiving pair engages
    // at the second step). Tolerance 1e-9 of the load for solver round-off.
    for w in recs[1..].windows(2) {
        let tol = 1e-9 * w[0].solution.load_scale_n;
        assert!(
            p(&w[1], "f1") <= p(&w[0], "f1") + tol,
            "P1 rose at t = {}",
            w[1].time_s
        );
        assert!(
            p(&w[1], "f3") >= p(&w[0], "f3") - tol,
            "P3 fell at t = {}",
            w[1].time_s
        );
    }
    let (first, last) = (&recs[0], recs.last().unwrap());
    assert!(p(first, "f1") > 0.0 && p(first, "f3") == 0.0);
    assert!(p(last, "f3") > 0.0);
    assert!(
        matches!(last.commands[0].command, Command::Released),
        "f1 is released at the end"
    );
}

/// Every warm step equals a fresh one-shot solve of the same grasp (the active fingers with
/// their commanded loads written into a new scene), to 1e-7 of the load.
#[test]
fn warm_steps_equal_fresh_cold_solves() {
    let (scene, _) = load();
    let recs = run(TransferOptions::default());
    // Step 0 (pair 1-2 held) and step 1 (pair 3-4 engaged) build programs; the last step
    // releases pair 1-2 (a new structure); every step between reuses the program.
    assert!(
        recs[2..recs.len() - 1].iter().all(|r| r.reused_program),
        "steps reuse the program"
    );
    assert!(!recs[recs.len() - 1].reused_program);
    for r in recs.iter().step_by(7) {
        let mut sub = scene.clone();
        sub.fingers = scene
            .fingers
            .iter()
            .zip(&r.commands)
            .filter_map(|(f, c)| {
                let mut f = f.clone();
                match c.command {
                    Command::Released => return None,
                    Command::Held => f.control = serde_json::from_str("\"held\"").unwrap(),
                    Command::Load(p) => {
                        f.control =
                            serde_json::from_value(serde_json::json!({"normal_load": p})).unwrap()
                    }
                    Command::Approach(d) => {
                        f.control =
                            serde_json::from_value(serde_json::json!({"approach_m": d})).unwrap()
                    }
                }
                Some(f)
            })
            .collect();
        let fresh = solve(&GraspModel::from_loaded(&sub).unwrap()).unwrap();
        let tol = 1e-7 * r.solution.load_scale_n;
        for f in &fresh.fingers {
            let w = r.solution.finger(&f.name).unwrap();
            assert!(
                (w.normal_force_n - f.normal_force_n).abs() <= tol,
                "t = {}: {}",
                r.time_s,
                f.name
            );
            for c in 0..3 {
                assert!((w.tangential_force_n[c] - f.tangential_force_n[c]).abs() <= tol);
            }
        }
    }
}

/// Cold stepping (rebuilding everything) gives the same answers as warm stepping.
#[test]
fn cold_stepping_matches_warm_stepping() {
    let warm = run(TransferOptions::default());
    let cold = run(TransferOptions {
        warm_start: false,
        ..TransferOptions::default()
    });
    assert!(cold.iter().all(|r| !r.reused_program));
    for (a, b) in warm.iter().zip(&cold) {
        for f in &a.solution.fingers {
            let g = b.solution.finger(&f.name).unwrap();
            assert!((f.normal_force_n - g.normal_force_n).abs() <= 1e-7 * a.solution.load_scale_n);
        }
    }
}

/// Between the ramps' corners the loads move along a line and the contact pattern holds, so
/// the program's KKT point moves along a line too: the warm start's affine prediction
/// (`backend/predictor.rs`) is then the solution itself and the step takes no Newton step.
/// Counted, not timed: most warm steps need none, while every cold step needs at least one
/// (its forces equal the warm ones: `cold_stepping_matches_warm_stepping`).
#[test]
fn steady_ramp_steps_are_predicted_without_a_newton_step() {
    let warm = run(TransferOptions::default());
    let cold = run(TransferOptions {
        warm_start: false,
        ..TransferOptions::default()
    });
    let free = warm
        .iter()
        .filter(|r| r.solution.solver.iterations == 0)
        .count();
    assert!(
        free * 4 >= warm.len() * 3,
        "{free} of {} steps predicted",
        warm.len()
    );
    assert!(cold.iter().all(|r| r.solution.solver.iterations >= 1));
}
