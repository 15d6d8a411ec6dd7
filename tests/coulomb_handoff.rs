//! The coulomb plate hand-off (`examples/plate_handoff_coulomb.*`): the plate (weight W, mu
//! 0.4) passes from the force-controlled pair f1, f2 to the pair f3, f4. Checks: every step is
//! in equilibrium and converged; the slip memory is bookkept (each step's accumulated slip is
//! the previous one plus this step's slip); the answer depends on the loading path; warm and
//! cold stepping agree; the minimum squeeze matches the rigid-body bound W / (2 mu).

mod support;
use support::*;

use grasp_model::{ContactState, GraspModel, GraspSolver, SolveOptions, SolveStatus};
use grasp_transfer::{minimum_squeeze, SqueezeOutcome, StepRecord, TransferOptions};

const W: f64 = 4.448;
const MU: f64 = 0.4;

fn run(options: TransferOptions) -> Vec<StepRecord> {
    step_transfer_example("plate_handoff_coulomb", options)
}

#[test]
fn every_step_converges_in_equilibrium_with_consistent_slip_memory() {
    let recs = run(TransferOptions::default());
    assert_eq!(recs.len(), 121);
    for (k, r) in recs.iter().enumerate() {
        let s = &r.solution;
        assert_eq!(s.status, SolveStatus::Solved, "step {k}: {:?}", s.reason);
        assert!(s.sequential.unwrap().converged);
        let res = s.residuals.unwrap();
        assert!(res.equilibrium_relative < 1e-9, "step {k}: {res:?}");
        assert!(res.cone_violation_relative < 1e-6, "step {k}: {res:?}");
        if k == 0 {
            continue;
        }
        // Memory: accumulated slip now = accumulated slip before + this step's slip, for
        // every element of a finger in contact at both steps (1e-15 m: a subtraction).
        for f in &s.fingers {
            let Some(prev) = recs[k - 1].solution.finger(&f.name) else {
                continue;
            };
            for (e, ep) in f.elements.iter().zip(&prev.elements) {
                for c in 0..2 {
                    let d = e.slip_m[c] - e.step_slip_m[c] - ep.slip_m[c];
                    assert!(d.abs() < 1e-15, "step {k} {} {:?}: {d}", f.name, e.index);
                }
            }
        }
    }
    // The releasing pair slides as a whole before it lets go (its load falls below what the
    // weight it still carries needs): slip fraction 1 at t = 8 s, friction = mu P.
    let r = recs.iter().find(|r| (r.time_s - 8.0).abs() < 1e-9).unwrap();
    let f1 = r.solution.finger("f1").unwrap();
    assert_eq!(f1.stick_count, 0);
    assert!((f1.tangential_magnitude_n - MU * f1.normal_force_n).abs() < 1e-6 * W);
}

/// Path dependence: at t = 6 s both pairs press with 6.75 N. Reached along the schedule, the
/// releasing pair still carries nearly all the weight (the receiving pads touched down on a
/// plate already held, and sticking pads keep their memory); solved afresh, the weight is
/// shared equally (W/4 per pad: equal pads under equal loads). Both are
/// valid Coulomb states.
#[test]
fn loading_path_changes_the_answer() {
    let recs = run(TransferOptions::default());
    let r = recs.iter().find(|r| (r.time_s - 6.0).abs() < 1e-9).unwrap();
    let along = |n: &str| r.solution.finger(n).unwrap().tangential_magnitude_n;
    let (scene, _) = transfer_example("plate_handoff_coulomb");
    let mut fresh_scene = scene.clone();
    for f in &mut fresh_scene.fingers {
        f.control = grasp_model::ControlSpec::Load(grasp_model::NormalLoadSpec {
            normal_load: r.normal_force_n(&f.name),
        });
    }
    let model = GraspModel::from_loaded(&fresh_scene).unwrap();
    let mut state = ContactState::new(&model);
    let fresh = GraspSolver::new(model.clone(), SolveOptions::default())
        .solve_step(&grasp_model::StepInputs::of_scene(&model), &mut state)
        .unwrap();
    assert_eq!(fresh.status, SolveStatus::Solved);
    let fresh_q = |n: &str| fresh.finger(n).unwrap().tangential_magnitude_n;
    eprintln!(
        "t = 6 s friction along the path f1 {:.4} f3 {:.4} N; fresh f1 {:.4} f3 {:.4} N",
        along("f1"),
        along("f3"),
        fresh_q("f1"),
        fresh_q("f3")
    );
    assert!(along("f1") > 0.45 * W, "releasing pair carries the weight");
    for n in ["f1", "f2", "f3", "f4"] {
        assert!(
            (fresh_q(n) - W / 4.0).abs() < 1e-3 * W,
            "fresh: equal shares"
        );
    }
    assert!(fresh.residuals.unwrap().equilibrium_relative < 1e-9);
}

/// Warm stepping (previous forces as the first iterate, programs reused) and cold stepping
/// (energy-model start, programs rebuilt) reach the same fixed points: forces agree to
/// 1e-6 W (the fixed-point tolerance is 1e-7 element force units); warm needs fewer convex
/// solves (the counts are deterministic, not timings).
#[test]
fn warm_and_cold_stepping_agree() {
    let warm = run(TransferOptions::default());
    let cold = run(TransferOptions {
        warm_start: false,
        ..TransferOptions::default()
    });
    let mut worst = 0.0_f64;
    for (a, b) in warm.iter().zip(&cold) {
        for f in &a.solution.fingers {
            let g = b.solution.finger(&f.name).unwrap();
            worst = worst.max((f.normal_force_n - g.normal_force_n).abs());
            for c in 0..3 {
                worst = worst.max((f.tangential_force_n[c] - g.tangential_force_n[c]).abs());
            }
        }
    }
    let solves = |v: &[StepRecord]| -> u32 {
        v.iter()
            .map(|r| r.solution.sequential.unwrap().iterations)
            .sum()
    };
    eprintln!(
        "warm vs cold: largest force difference {worst:.2e} N; convex solves warm {} cold {}",
        solves(&warm),
        solves(&cold)
    );
    assert!(worst < 1e-6 * W);
    assert!(solves(&warm) < solves(&cold));
}

/// Minimum squeeze: two opposed flat pads with mu = 0.4 hold a plate of weight W iff each
/// presses with at least W / (2 mu) = 5.56 N (each pad's friction is at most mu P, and
/// symmetry gives each half the weight). The bisection's bracket is 1e-4 wide.
#[test]
fn minimum_squeeze_is_the_rigid_body_bound() {
    let recs = run(TransferOptions::default());
    let (scene, _) = transfer_example("plate_handoff_coulomb");
    let out = minimum_squeeze(&scene, recs.last().unwrap(), SolveOptions::default()).unwrap();
    let SqueezeOutcome::Found(m) = out else {
        panic!("{out:?}")
    };
    eprintln!("{m:?}");
    let bound = W / (2.0 * MU);
    assert_eq!(m.fingers.len(), 2);
    for f in &m.fingers {
        assert!((f.minimum_n / bound - 1.0).abs() < 2e-4, "{f:?} vs {bound}");
        assert_eq!(f.scheduled_n, 8.0);
    }
    assert!((m.margin - 8.0 / bound).abs() < 2e-3);
    assert!(m.limiting.starts_with("cannot hold") || m.limiting.contains("slides as a whole"));
}

/// While the loads ramp and the stick / slip pattern holds, the warm start continues the
/// ramp from the last steps' forces (`sequential.rs`, `extrapolated_forces`): the first
/// convex solve already reproduces its input, so the step ends after one solve. Counted, not
/// timed: warm stepping ends three steps in four after one solve, more than twice as often as
/// cold stepping (whose first solve starts from the energy model's forces: one solve suffices
/// only where those already give the fixed point).
#[test]
fn steady_ramp_steps_end_after_one_convex_solve() {
    let solves = |v: &[StepRecord]| -> Vec<u32> {
        v.iter()
            .map(|r| r.solution.sequential.unwrap().iterations)
            .collect()
    };
    let warm = solves(&run(TransferOptions::default()));
    let cold = solves(&run(TransferOptions {
        warm_start: false,
        ..TransferOptions::default()
    }));
    let one = |v: &[u32]| v.iter().filter(|&&n| n == 1).count();
    eprintln!(
        "steps ending after one solve: warm {} cold {} of {}",
        one(&warm),
        one(&cold),
        warm.len()
    );
    assert!(one(&warm) * 4 >= warm.len() * 3);
    assert!(one(&warm) >= 2 * one(&cold));
}
