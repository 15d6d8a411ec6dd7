//! Margins in hand-offs and scheduled external loads:
//!
//! - a scheduled downward pull on a coulomb pinch makes the grasp fail (no equilibrium, or a
//!   finger sliding as a whole) at the step where the pull crosses the margin that
//!   `disturbance_margins` computed, within one step;
//! - the stepper's per-step margins: the summary's least safe step is the step with the smallest
//!   margin, and the MCAP step messages carry it;
//! - more squeeze gives more margin on the coulomb plate (both pads raised by `d` add `2 mu d`
//!   to the downward margin, the friction capacity), and the sensitivities say so: the
//!   derivative of a pad's friction utilisation with respect to the squeeze (all commanded
//!   loads scaled together) is negative and matches central differences (1e-4 relative: the
//!   differences of 1e-3 carry about 1e-6 of truncation).

mod support;

use grasp_model::{disturbance_margins, holds, MarginOptions, WrenchDirection};
use grasp_model::{ContactState, GraspModel, GraspSolver, LoadedScene, SolveOptions};
use grasp_transfer::{Schedule, Stepper, TransferOptions, TransferSummary};
use serde_json::json;
use support::{example_json, scene};

const MU: f64 = 0.5;
const P: f64 = 10.0;
const W: f64 = 4.0;

/// A coulomb pinch of a block by two flat pads with commanded loads (Poisson's ratio 0, see
/// tests/disturbance_margin.rs).
fn pinch() -> LoadedScene {
    let finger = |name: &str, x: f64, nx: f64| {
        json!({
            "name": name, "contact_point": [x, 0.0, 0.0], "normal": [nx, 0.0, 0.0],
            "tangent": [0.0, 1.0, 0.0],
            "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.0},
            "patch": {"size": [0.01, 0.01], "grid": [5, 5]},
            "friction": {"mu": MU}, "control": {"normal_load": P}
        })
    };
    scene(&json!({
        "object": {"weight": W, "center_of_mass": [0.0, 0.0, 0.0],
                   "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.0}},
        "fingers": [finger("left", -0.02, 1.0), finger("right", 0.02, -1.0)],
        "model": "coulomb"
    }))
}

fn down() -> WrenchDirection {
    WrenchDirection {
        force: [0.0, 0.0, -1.0],
        torque: [0.0; 3],
    }
}

fn margin_down(scene: &LoadedScene) -> f64 {
    let model = std::sync::Arc::new(GraspModel::from_loaded(scene).unwrap());
    disturbance_margins(
        &model,
        &grasp_model::StepInputs::of_scene(&model),
        &ContactState::new(&model),
        SolveOptions::default(),
        &[down()],
        &MarginOptions::default(),
    )
    .unwrap()
    .directions[0]
        .margin_n
        .expect("the pinch's downward margin is bounded")
}

#[test]
fn a_scheduled_pull_fails_the_grasp_where_it_crosses_the_margin() {
    let scene = pinch();
    let margin = margin_down(&scene);
    // Pull from 0 to 1.5 margins in 30 steps of 0.05 margins.
    let names = scene.finger_names();
    let text = json!({
        "time": {"start": 0.0, "end": 3.0, "step": 0.1},
        "fingers": {},
        "external": {"ramp": {"keyframes": [[0.0, {"force": [0, 0, 0]}],
                                             [3.0, {"force": [0, 0, -1.5 * margin]}]]}}
    })
    .to_string();
    let schedule = Schedule::from_json_str(&text, &names, std::path::Path::new(".")).unwrap();
    let options = TransferOptions {
        keep_going: true,
        ..TransferOptions::default()
    };
    let model = GraspModel::from_loaded(&scene).unwrap();
    let records: Vec<_> = Stepper::new(&scene, &schedule, options)
        .map(|r| r.unwrap())
        .collect();
    let crossing = records
        .iter()
        .position(|r| -r.external_force_n[2] > margin)
        .expect("the pull crosses the margin");
    let failed = records
        .iter()
        .position(|r| holds(&model, &r.solution, &[]).is_err())
        .expect("the grasp fails");
    assert!(
        failed.abs_diff(crossing) <= 1,
        "failed at step {failed}, the pull crosses the margin {margin} N at step {crossing}"
    );
    // And every step before it held.
    assert!(records[..failed]
        .iter()
        .all(|r| holds(&model, &r.solution, &[]).is_ok()));
}

/// The hand-off stepped with margins at every 12th step of the schedule's (the margins cost
/// about 50 solves a step).
fn every_12th_step_with_margins(
    scene: &grasp_model::LoadedScene,
    schedule: &mut grasp_transfer::Schedule,
) -> Vec<grasp_transfer::StepRecord> {
    schedule.times = schedule.times.iter().copied().step_by(12).collect();
    let options = TransferOptions {
        margins: true,
        ..TransferOptions::default()
    };
    Stepper::new(scene, schedule, options)
        .map(|r| r.unwrap())
        .collect()
}

#[test]
fn the_least_safe_step_is_the_smallest_margin_and_the_log_carries_it() {
    let (scene, mut schedule) = support::transfer_example("plate_handoff_coulomb");
    let records = every_12th_step_with_margins(&scene, &mut schedule);
    let names = scene.finger_names();
    let summary = TransferSummary::from_records(&records, &names);
    let least = summary.least_safe_step.expect("margins were computed");
    let smallest = records
        .iter()
        .filter_map(|r| Some((r.index, r.margin.as_ref()?.smallest_n?)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert_eq!((least.step, least.margin_n), (smallest.0, Some(smallest.1)));
    assert!(records.iter().all(|r| r.margin.is_some()));
    // The MCAP step message carries the margin.
    let msg = grasp_transfer::FingersMessage::from_record(&records[least.step]);
    assert_eq!(msg.smallest_margin_n, least.margin_n);
}

/// A step's margin is the margin of that step's grasp under that step's own loads: on the
/// plate hand-off solved with the energy model (no path dependence: a fresh contact state
/// gives the same grasp), every 12th step's smallest margin equals `disturbance_margins` of
/// the scene's model restricted to the step's active fingers, each driven as commanded, to
/// 2e-3 of the load scale (twice the bisection's relative tolerance: both searches stop within
/// 1e-3 of the same bracket). Reusing a step's program at later steps once made the margins
/// read the loads the program was built with: the ramped pads kept their first squeeze.
#[test]
fn a_steps_margin_is_its_grasps_margin_under_its_own_loads() {
    let (mut scene, mut schedule) = support::transfer_example("plate_handoff_coulomb");
    scene.model = grasp_model::ModelKind::Energy;
    let records = every_12th_step_with_margins(&scene, &mut schedule);
    let base = GraspModel::from_loaded(&scene).unwrap();
    let mut checked = 0;
    for r in records.iter().filter(|r| r.solution.status.has_forces()) {
        let active: Vec<(usize, grasp_model::Control)> = r
            .commands
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.command.control().map(|control| (i, control)))
            .collect();
        let model = std::sync::Arc::new(base.restricted(&active).unwrap());
        let dirs = grasp_model::axis_directions(&model);
        let fresh = disturbance_margins(
            &model,
            &grasp_model::StepInputs::of_scene(&model),
            &ContactState::new(&model),
            SolveOptions::default(),
            &dirs,
            // In the scene's units (its reach and load scale), as the hand-off measures.
            &MarginOptions::default().in_units_of(&base),
        )
        .unwrap();
        let expected = fresh.directions[fresh.smallest].held_to_n;
        let got = r.margin.as_ref().unwrap().known_to_hold_n();
        let scale = fresh.load_scale_n;
        assert!(
            (got - expected).abs() <= 2e-3 * scale,
            "step {} (t = {} s): margin {got} N, its grasp's {expected} N",
            r.index,
            r.time_s
        );
        checked += 1;
    }
    assert!(checked >= 8, "{checked} steps checked");
}

/// The plate of the coulomb hand-off with all four pads loaded (mid-transfer).
fn plate(loads: [f64; 4]) -> serde_json::Value {
    let mut v = example_json("plate_handoff_coulomb.json");
    for (f, p) in v["fingers"].as_array_mut().unwrap().iter_mut().zip(loads) {
        f["control"] = json!({ "normal_load": p });
    }
    v
}

#[test]
fn more_squeeze_gives_more_margin_and_the_sensitivity_says_so() {
    let mu = 0.4;
    // Before the hand-off only the upper pads are loaded: the downward margin is the pinch's
    // 2 mu P - W, and squeezing both by d adds 2 mu d (each margin bracketed to 1e-3).
    let d = 0.5;
    let m0 = margin_down(&scene(&plate([8.0, 8.0, 0.0, 0.0])));
    let m1 = margin_down(&scene(&plate([8.0 + d, 8.0 + d, 0.0, 0.0])));
    assert!(
        ((m1 - m0) - 2.0 * mu * d).abs() <= 2e-3 * m1,
        "margin grew by {} N, expected 2 mu d = {} N",
        m1 - m0,
        2.0 * mu * d
    );
    // Mid-transfer, all four pads loaded: more squeeze on every pad, more margin.
    let base = [8.0, 8.0, 4.0, 4.0];
    let m2 = margin_down(&scene(&plate(base)));
    let m3 = margin_down(&scene(&plate(base.map(|p| 1.1 * p))));
    assert!(m3 > m2, "10 % more squeeze: margin {m3} N, before {m2} N");
    // The sensitivity of the grip to the squeeze, on the coulomb plate mid-transfer: every
    // commanded load scaled by lambda ("squeeze"; raising one pad alone leaves no equilibrium),
    // d(utilisation of f1)/d lambda from the KKT system against central differences.
    let utilisation = |lambda: f64| -> (f64, grasp_model::Solution, GraspSolver, GraspModel) {
        let loads = base.map(|p| p * lambda);
        let model = GraspModel::from_loaded(&scene(&plate(loads))).unwrap();
        let mut solver = GraspSolver::new(model.clone(), SolveOptions::default());
        let sol = solver
            .solve(&grasp_model::StepInputs::loads(loads.to_vec()))
            .unwrap();
        assert!(sol.status.has_forces(), "{loads:?}: {:?}", sol.reason);
        (sol.fingers[0].friction_utilization, sol, solver, model)
    };
    let (u0, sol, mut solver, _model) = utilisation(1.0);
    let sens = solver.sensitivities(&sol).unwrap();
    let col = sens
        .parameters
        .iter()
        .position(|p| p.name == "squeeze")
        .unwrap();
    assert!(
        sens.parameters[col].defined,
        "{:?}",
        sens.parameters[col].reason
    );
    let f1 = &sol.fingers[0];
    let q = nalgebra::Vector3::from(f1.tangential_force_n);
    let dq = nalgebra::Vector3::from(sens.fingers[0].tangential_force[col]);
    let dp = sens.fingers[0].normal_force[col];
    let du = (q.dot(&dq) / q.norm()) / (mu * f1.normal_force_n)
        - f1.tangential_magnitude_n * dp / (mu * f1.normal_force_n.powi(2));
    let h = 1e-3;
    let (up, down) = (utilisation(1.0 + h).0, utilisation(1.0 - h).0);
    let fd = (up - down) / (2.0 * h);
    assert!(
        du < 0.0,
        "more squeeze should lower f1's utilisation {u0}: {du}"
    );
    assert!(
        (du - fd).abs() <= 1e-4 * fd.abs(),
        "d utilisation / d load: KKT {du:e}, differences {fd:e}"
    );
}

#[test]
fn the_bundled_task_load_schedules_run_and_log_their_wrench() {
    for (name, t, force_z, torque_y) in [
        ("plate_pull", 8.0, -1.5, 0.0),
        ("plate_bump", 6.1, 2.0, 0.05),
    ] {
        let dir = std::path::PathBuf::from(support::example_path(""));
        let scene = LoadedScene::from_json_str(
            &std::fs::read_to_string(dir.join("plate_handoff_coulomb.json")).unwrap(),
        )
        .unwrap();
        let names = scene.finger_names();
        let text = std::fs::read_to_string(dir.join(format!("{name}.schedule.json"))).unwrap();
        let schedule = Schedule::from_json_str(&text, &names, &dir).unwrap();
        let records: Vec<_> = Stepper::new(&scene, &schedule, TransferOptions::default())
            .map(|r| r.unwrap())
            .collect();
        assert!(
            records.iter().all(|r| r.solution.status.has_forces()),
            "{name}"
        );
        let at = records
            .iter()
            .find(|r| (r.time_s - t).abs() < 1e-9)
            .unwrap();
        assert!((at.external_force_n[2] - force_z).abs() < 1e-12, "{name}");
        assert!(
            (at.external_torque_nm[1] - torque_y).abs() < 1e-12,
            "{name}"
        );
        // The logged wrench is the one the step balanced: the equilibrium residual stays tiny.
        let r = at.solution.residuals.unwrap();
        assert!(r.equilibrium_relative < 1e-9, "{name}: {r:?}");
        let msg = grasp_transfer::FingersMessage::from_record(at);
        assert_eq!(msg.external_force_n, at.external_force_n);
    }
}

#[test]
fn bad_external_loads_are_named() {
    let names = vec!["left".to_string(), "right".to_string()];
    let dir = std::path::PathBuf::from(support::example_path(""));
    for (external, path) in [
        (
            json!({"ramp": {"keyframes": [[1.0, {"force": [0, 0, 1]}], [0.5, {}]]}}),
            "external.ramp.keyframes[1]",
        ),
        (
            json!({"ramp": {"keyframes": [[0.0, {"force": [0, 0, 1e9]}]]}}),
            "external.ramp.keyframes[0]",
        ),
        (
            json!({"csv": {"path": "plate_bump.csv", "time_column": "t_s",
                           "force_columns": ["nope", null, null]}}),
            "external.csv.columns",
        ),
        (
            json!({"csv": {"path": "plate_bump.csv", "time_column": "t_s"}}),
            "external.csv",
        ),
    ] {
        let text = json!({"time": {"times": [0.0]}, "fingers": {}, "external": external});
        let err = Schedule::from_json_str(&text.to_string(), &names, &dir).unwrap_err();
        assert!(err.to_string().contains(path), "{path}: {err}");
    }
}
