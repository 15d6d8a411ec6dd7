//! The probe for a second coulomb equilibrium at each margin's failing end
//! (`grasp_model::analysis::equilibrium_probe`): it runs, it never moves the margin it probes,
//! and on the bundled coulomb grasps it raises no false alarm.
//!
//! At a bracket's failing end a finger is at the edge of sliding as a whole: the three answers
//! (the search's solver warm, the same solver started cold, the other solver) may judge it
//! differently by round-off, but their forces agree to the solves' accuracy (about 1e-10 of
//! the load scale; Clarabel's reduced-accuracy answers 1e-5), far below the probe's threshold
//! `DISTINCT_FRACTION` (1e-3 of the load scale). A probe that compared verdicts instead, or
//! took the path's answer from another state, would flag these grasps.

mod support;

use std::sync::Arc;

use grasp_model::{
    axis_directions, disturbance_margins, ContactState, GraspModel, MarginOptions, MarginReport,
    SolveOptions, SolverChoice, StepInputs,
};
use serde_json::Value;
use support::{example_json, scene};

fn margins(v: &Value, solver: SolverChoice, probe: bool) -> MarginReport {
    let model = Arc::new(GraspModel::from_loaded(&scene(v)).unwrap());
    let solve = SolveOptions {
        solver,
        ..SolveOptions::default()
    };
    let options = MarginOptions {
        probe_equilibria: probe,
        ..MarginOptions::default()
    };
    disturbance_margins(
        &model,
        &StepInputs::of_scene(&model),
        &ContactState::new(&model),
        solve,
        &axis_directions(&model),
        &options,
    )
    .unwrap()
}

/// The coulomb grasps at their scenes' own loads: the plate hand-off's and the servo plate's
/// (every finger loaded). `tests/margin_agreement.rs` probes every bundled hand-off's steps.
fn coulomb_grasps() -> Vec<(&'static str, Value)> {
    vec![
        (
            "plate_handoff_coulomb",
            example_json("plate_handoff_coulomb.json"),
        ),
        (
            "plate_transfer_servo",
            example_json("plate_transfer_servo.json"),
        ),
    ]
}

/// With and without the probe the margins are the same numbers (it runs after the search,
/// on its own solvers but for the path's re-solve), every bounded direction spent more solves
/// with it (it ran), and no direction reports a second equilibrium.
#[test]
fn the_probe_runs_moves_no_margin_and_finds_no_second_equilibrium_on_the_bundled_grasps() {
    for (what, v) in coulomb_grasps() {
        for solver in [SolverChoice::Native, SolverChoice::Clarabel] {
            let with = margins(&v, solver, true);
            let without = margins(&v, solver, false);
            let mut probed = 0;
            for (i, (a, b)) in with.directions.iter().zip(&without.directions).enumerate() {
                let at = format!("{what}, {solver}, #{i}");
                assert_eq!(
                    (a.margin_n, a.fails_at_n, a.held_to_n),
                    (b.margin_n, b.fails_at_n, b.held_to_n),
                    "{at}"
                );
                assert_eq!(a.other_equilibrium, None, "{at}: {a:?}");
                let probe_applies = a.fails_at_n.is_some()
                    && !matches!(a.failure, Some(grasp_model::Failure::NoEquilibrium { .. }));
                if probe_applies {
                    assert!(a.solves > b.solves, "{at}: the probe did not run: {a:?}");
                    probed += 1;
                } else {
                    assert!(a.solves >= b.solves, "{at}");
                }
            }
            assert!(probed > 0, "{what}, {solver}: no direction was probed");
        }
    }
}

/// The energy model's program is convex: no probe, not one solve more.
#[test]
fn the_energy_model_is_not_probed() {
    let v = example_json("disc_transfer.json");
    assert_eq!(v["model"], "energy", "the example's law changed");
    let with = margins(&v, SolverChoice::Native, true);
    let without = margins(&v, SolverChoice::Native, false);
    for (a, b) in with.directions.iter().zip(&without.directions) {
        assert_eq!((a.solves, &a.other_equilibrium), (b.solves, &None));
    }
}

/// Along a coulomb hand-off the margins continue from step to step on solvers kept between
/// steps: the probe solves on solvers of its own, so every step's smallest margin is the same
/// number with and without it (`--probe-equilibria`), and no step finds a second equilibrium.
/// The plate hand-off thinned to 7 steps (every 20th of its 121).
#[test]
fn a_hand_offs_continued_margins_are_the_same_with_and_without_the_probe() {
    use grasp_transfer::{StepRecord, Stepper, TransferOptions};
    let (scene, mut schedule) = support::transfer_example("plate_handoff_coulomb");
    schedule.times = schedule.times.iter().copied().step_by(20).collect();
    let run = |probe: bool| -> Vec<StepRecord> {
        let mut options = TransferOptions {
            margins: true,
            ..TransferOptions::default()
        };
        options.margin_options.probe_equilibria = probe;
        Stepper::new(&scene, &schedule, options)
            .map(|r| r.unwrap())
            .collect()
    };
    let (with, without) = (run(true), run(false));
    assert_eq!(with.len(), 7);
    for (a, b) in with.iter().zip(&without) {
        let (ma, mb) = (a.margin.as_ref().unwrap(), b.margin.as_ref().unwrap());
        assert_eq!(
            (ma.smallest_n, ma.held_to_n),
            (mb.smallest_n, mb.held_to_n),
            "step {}",
            a.index
        );
        assert!(
            ma.solves > mb.solves || ma.smallest_n.is_none(),
            "step {}: not probed",
            a.index
        );
        assert_eq!(ma.other_equilibrium, None, "step {}", a.index);
    }
}
