//! Shared helpers of the integration tests: load the bundled examples, edit them as JSON.
#![allow(dead_code)]

use grasp_model::{solve, GraspModel, Scene, Solution, SolveStatus};
use serde_json::Value;

/// Path of a file in the workspace's `examples/` folder.
pub fn example_path(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// An example scene as JSON, for editing.
pub fn example_json(name: &str) -> Value {
    let text = std::fs::read_to_string(example_path(name)).expect("example exists");
    serde_json::from_str(&text).expect("example is JSON")
}

/// Parses and validates a JSON scene.
pub fn scene(v: &Value) -> Scene {
    Scene::from_json_str(&v.to_string()).expect("valid scene")
}

/// Builds and solves a JSON scene.
pub fn solve_json(v: &Value) -> Solution {
    let model = GraspModel::from_scene(&scene(v)).expect("model");
    solve(&model).expect("solve runs")
}

/// Solves and insists on a solution.
pub fn solved(v: &Value) -> Solution {
    let s = solve_json(v);
    assert_eq!(s.status, SolveStatus::Solved, "{:?}", s.reason);
    s
}

/// Multiplies every Young's modulus in the scene by `k`.
pub fn scale_moduli(v: &mut Value, k: f64) {
    let scale = |m: &mut Value| {
        if let Some(e) = m.get_mut("youngs_modulus") {
            *e = Value::from(e.as_f64().unwrap() * k);
        }
    };
    scale(&mut v["object"]["material"]);
    for f in v["fingers"].as_array_mut().unwrap() {
        scale(&mut f["material"]);
    }
}

/// The five thesis examples.
pub const EXAMPLES: [&str; 5] = [
    "plate_four_fingers.json",
    "disc_three_fingers.json",
    "pipe_three_fingers.json",
    "cube_a.json",
    "cube_b.json",
];

/// A bundled hand-off: its scene and its schedule (`<name>.json`, `<name>.schedule.json`).
pub fn transfer_example(name: &str) -> (Scene, grasp_transfer::Schedule) {
    let dir = std::path::PathBuf::from(example_path(""));
    let scene =
        Scene::from_json_str(&std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap())
            .unwrap();
    let names: Vec<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
    let text = std::fs::read_to_string(dir.join(format!("{name}.schedule.json"))).unwrap();
    let schedule = grasp_transfer::Schedule::from_json_str(&text, &names, &dir).unwrap();
    (scene, schedule)
}

/// Steps a bundled hand-off with `options`, insisting that every step runs.
pub fn step_transfer_example(
    name: &str,
    options: grasp_transfer::TransferOptions,
) -> Vec<grasp_transfer::StepRecord> {
    let (scene, schedule) = transfer_example(name);
    grasp_transfer::Stepper::new(&scene, &schedule, options)
        .map(|r| r.unwrap())
        .collect()
}
