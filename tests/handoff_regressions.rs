//! Regressions found in review: a hand-off step must equal the one-shot solve of the same grasp
//! whatever the size of the loads (the program is scaled by the step's loads), and phase
//! boundaries hold at large schedule times.

use std::path::Path;

use grasp_model::solve;
use grasp_model::{GraspModel, LoadedScene};
use grasp_transfer::{Command, Schedule, Stepper, TransferOptions};
use serde_json::json;

fn squeeze(load: f64, weight: f64) -> serde_json::Value {
    let pad = |name: &str, x: f64, n: f64| {
        json!({"name": name, "contact_point": [x, 0.0, 0.0], "normal": [n, 0.0, 0.0],
               "material": {"youngs_modulus": 2e6, "poisson_ratio": 0.45},
               "patch": {"size": [0.01, 0.01], "grid": [3, 3]}, "friction": {"mu": 0.5},
               "control": {"normal_load": load}})
    };
    json!({"object": {"weight": weight, "center_of_mass": [0.0, 0.0, 0.0], "material": {"youngs_modulus": 7e10, "poisson_ratio": 0.33}},
           "fingers": [pad("l", -0.05, 1.0), pad("r", 0.05, -1.0)]})
}

#[test]
fn hand_off_steps_equal_one_shot_solves_at_any_load_size() {
    for (load, weight) in [(1e-6, 1e-7), (1.0, 0.1), (1e5, 1e4)] {
        let v = squeeze(load, weight);
        let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
        let one_shot = solve(&GraspModel::from_loaded(&scene).unwrap()).unwrap();
        let names = vec!["l".to_string(), "r".to_string()];
        let sched = json!({"time": {"times": [0, 1]}, "fingers": {
            "l": [{"ramp": {"keyframes": [[0, load], [1, load]]}}],
            "r": [{"ramp": {"keyframes": [[0, load], [1, load]]}}]}});
        let schedule = Schedule::from_json_str(&sched.to_string(), &names, Path::new(".")).unwrap();
        for r in Stepper::new(&scene, &schedule, TransferOptions::default()) {
            let r = r.unwrap();
            for (a, b) in r.solution.fingers.iter().zip(&one_shot.fingers) {
                assert_eq!(
                    (a.stick_count, a.slip_count, a.separated_count),
                    (b.stick_count, b.slip_count, b.separated_count),
                    "load {load}"
                );
                assert!((a.tangential_magnitude_n - b.tangential_magnitude_n).abs() <= 1e-7 * load);
            }
        }
    }
}

#[test]
fn phase_boundaries_hold_at_large_times() {
    let names = vec!["l".to_string(), "r".to_string()];
    // 0 + 163841 * 0.1 = 16384.100000000002 in floating point: just above the phase end
    // 16384.1 written in the file; it must still count as the end of the held phase.
    let sched = json!({"time": {"start": 0, "end": 16384.5, "step": 0.1}, "fingers": {
        "l": [{"held": {"until": 16384.1}}, {"ramp": {"keyframes": [[16384.1, 2.0], [16390, 1.0]]}}]}});
    let s = Schedule::from_json_str(&sched.to_string(), &names, Path::new(".")).unwrap();
    let k = 163841;
    assert!(
        s.times[k] > 16384.1,
        "the test needs a time rounded above the boundary"
    );
    assert_eq!(
        s.command(0, s.times[k], 0.0, Command::Held),
        Command::Held,
        "t = {} is still in the held phase",
        s.times[k]
    );
    assert!(matches!(
        s.command(0, s.times[k + 1], 0.0, Command::Held),
        Command::Load(_)
    ));
}

/// Regression (found by the mutation test): a held finger listed before a force-controlled one
/// took that finger's load when a step's grasp was built, so the disc hand-off with f3 left to
/// the scene (held) failed with "expected 2 prescribed loads, got 3". Every force-controlled
/// finger must carry exactly its commanded load.
#[test]
fn a_held_finger_before_a_force_controlled_one_keeps_the_loads_in_order() {
    let text = std::fs::read_to_string(format!(
        "{}/../examples/disc_transfer.schedule.json",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let mut sched: serde_json::Value = serde_json::from_str(&text).unwrap();
    sched["fingers"].as_object_mut().unwrap().remove("f3");
    let scene_text = std::fs::read_to_string(format!(
        "{}/../examples/disc_transfer.json",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let scene = LoadedScene::from_json_str(&scene_text).unwrap();
    let names = scene.finger_names();
    let schedule = Schedule::from_json_str(&sched.to_string(), &names, Path::new(".")).unwrap();
    let mut loaded_after_held = 0;
    for r in Stepper::new(&scene, &schedule, TransferOptions::default()) {
        let r = r.unwrap();
        assert!(
            r.solution.status.has_forces(),
            "t = {}: {:?}",
            r.time_s,
            r.solution.reason
        );
        for c in &r.commands {
            if let Command::Load(p) = c.command {
                let carried = r.normal_force_n(&c.name);
                assert!(
                    (carried - p).abs() <= 1e-9 * p.max(1.0),
                    "{} carries {carried} N, commanded {p} N",
                    c.name
                );
                loaded_after_held += usize::from(c.name == "f4");
            }
        }
    }
    assert!(
        loaded_after_held > 0,
        "f4 is never force-controlled: the test needs it"
    );
}
