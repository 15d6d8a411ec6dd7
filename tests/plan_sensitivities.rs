//! The planner's linearisation: the derivative of every step's slip margin with respect to a
//! keyframe load, by the chain rule through the step's KKT sensitivities
//! (`grasp_transfer::plan_linearisation::slip_rows`), equals the central difference of the
//! margins of two runs of the whole schedule with that keyframe moved, along the plate hand-off
//! under the energy model (each pair of jaws moved together, through five keyframes), and along
//! the gripper hand-off, whose jaws are planned by their approaches (the servo's jaws opened,
//! the receiving jaws closed), through the `approach:<finger>` columns.

mod support;

use std::collections::BTreeMap;

use grasp_transfer::plan_linearisation::{load_directions, slip_rows};
use grasp_transfer::{
    Commanded, KeyframePath, PlannedGroup, Schedule, StepRecord, Stepper, TransferOptions,
};
use support::example_scene;

/// Keyframe load step of the difference, N: small against the 8 N loads (the quotient's
/// truncation error is of order h^2 times the margin's curvature), large against the
/// margins' round-off (1e-12 of the load).
const H_N: f64 = 1e-4;

fn run(scene: &grasp_model::LoadedScene, path: &KeyframePath) -> Vec<StepRecord> {
    let spec = path.to_spec("test".into(), &BTreeMap::new());
    let schedule = Schedule::from_spec(&spec, &scene.finger_names(), std::path::Path::new("."))
        .expect("a valid schedule");
    let options = TransferOptions {
        sensitivities: true,
        keep_going: true,
        ..TransferOptions::default()
    };
    Stepper::new(scene, &schedule, options)
        .with_load_directions(load_directions(path))
        .map(|r| r.expect("a step"))
        .collect()
}

/// The margin of `finger` at step `s`, and its elements' states (stick counts).
fn margin(records: &[StepRecord], s: usize, finger: &str) -> Option<(f64, usize, usize)> {
    let f = records[s].solution.finger(finger)?;
    Some((1.0 - f.friction_utilization, f.stick_count, f.slip_count))
}

#[test]
fn slip_margin_derivatives_along_a_schedule_equal_central_differences_of_its_runs() {
    let mut scene = example_scene("plate_handoff_coulomb.json");
    scene.model = grasp_model::ModelKind::Energy;
    let pair = |name: &str, a: &str, b: &str| PlannedGroup {
        name: name.into(),
        members: vec![(a.into(), 1.0), (b.into(), 1.0)],
        commanded: Commanded::Load,
    };
    let path = KeyframePath {
        groups: vec![pair("releasing", "f1", "f2"), pair("receiving", "f3", "f4")],
        fractions: vec![0.0, 0.25, 0.5, 0.75, 1.0],
        values: vec![vec![8.0, 7.0, 5.0, 3.0, 0.0], vec![0.0, 3.0, 6.0, 8.0, 8.0]],
        duration_s: 12.0,
        steps: 24,
    };
    let (compared, nonzero) = compare_with_differences(&scene, &path);
    println!("{compared} derivatives compared, {nonzero} of them above 1e-3 per N");
    assert!(compared > 40, "{compared} derivatives compared");
    // Derivatives that are not all zero (a zero chain rule would match flat margins).
    assert!(nonzero > 10, "{nonzero} derivatives above 1e-3 per N");
}

/// The gripper hand-off planned by approaches: the variable of each pair is its jaws'
/// approach times `c` = 1000 N/m from the pair's fixed end (the releasing jaws' -1 mm, the
/// receiving jaws' 0.1 mm), so the step `H_N` moves the jaws by 0.1 um. Same tolerance.
#[test]
fn slip_margin_derivatives_in_the_jaws_approaches_equal_central_differences() {
    let mut scene = example_scene("plate_transfer_gripper.json");
    scene.model = grasp_model::ModelKind::Energy;
    let c = 1000.0;
    let pair = |name: &str, a: &str, b: &str, reference_m: f64| PlannedGroup {
        name: name.into(),
        members: vec![(a.into(), 1.0), (b.into(), 1.0)],
        commanded: Commanded::Approach {
            newtons_per_metre: c,
            reference_m: vec![reference_m; 2],
            range_m: (-0.001, 0.004),
        },
    };
    // Releasing: 4 mm to -1 mm; receiving: 0.1 mm to 1 mm, closing first.
    let path = KeyframePath {
        groups: vec![
            pair("releasing", "f1", "f2", -0.001),
            pair("receiving", "f3", "f4", 0.0001),
        ],
        fractions: vec![0.0, 0.25, 0.5, 0.75, 1.0],
        values: vec![vec![5.0, 4.8, 3.0, 1.0, 0.0], vec![0.0, 0.6, 0.9, 0.9, 0.9]],
        duration_s: 10.0,
        steps: 24,
    };
    let spec = serde_json::to_value(path.to_spec("test".into(), &BTreeMap::new())).unwrap();
    let keys = &spec["fingers"]["f1"][0]["approach"]["keyframes"];
    assert_eq!(
        keys[0][1], 0.004,
        "the jaws are planned by approach phases: {spec}"
    );
    assert_eq!(keys[4][1], -0.001);
    let (compared, nonzero) = compare_with_differences(&scene, &path);
    println!("{compared} derivatives compared, {nonzero} of them above 1e-3 per unit");
    assert!(compared > 40, "{compared} derivatives compared");
    assert!(nonzero > 10, "{nonzero} derivatives above 1e-3 per unit");
}

/// Compares every slip row's derivative in the interior keyframes of both groups with the
/// central difference of two runs; the counts compared, and of those above 1e-3.
fn compare_with_differences(
    scene: &grasp_model::LoadedScene,
    path: &KeyframePath,
) -> (usize, usize) {
    let base = run(scene, path);
    let mut notes = Vec::new();
    let rows = slip_rows(path, &base, &mut notes);
    assert!(notes.is_empty(), "{notes:?}");
    let nk = path.fractions.len();
    let (mut compared, mut nonzero) = (0, 0);
    // The interior keyframes of the releasing and the receiving pair.
    for (i, k) in [(0, 1), (0, 2), (1, 1), (1, 3)] {
        let moved = |sign: f64| {
            let mut p = path.clone();
            p.values[i][k] += sign * H_N;
            run(scene, &p)
        };
        let (up, down) = (moved(1.0), moved(-1.0));
        for row in &rows {
            let (Some(a), Some(b)) = (
                margin(&up, row.step, &row.finger),
                margin(&down, row.step, &row.finger),
            ) else {
                continue;
            };
            // A state change between the two runs makes the margin kinked: no derivative.
            if (a.1, a.2) != (b.1, b.2) {
                continue;
            }
            let fd = (a.0 - b.0) / (2.0 * H_N);
            let g = row.gradient[i * nk + k];
            // Central difference: error ~ h^2 |m'''| (m is a ratio of forces linear in the
            // loads within a state, so smooth) plus round-off 1e-12 / h = 1e-8 per N.
            assert!(
                (fd - g).abs() <= 1e-6 + 1e-4 * g.abs(),
                "{} at step {} (t = {} s), keyframe {k} of {}: chain rule {g}, difference {fd}",
                row.finger,
                row.step,
                row.time_s,
                path.groups[i].name
            );
            compared += 1;
            nonzero += usize::from(g.abs() > 1e-3);
        }
    }
    (compared, nonzero)
}
