//! What varies per step travels in `StepInputs` beside the model: an approach or an extra
//! wrench given there solves the same grasp as the scene that writes it into the model, and
//! inputs that do not fit the model are refused naming what is wrong.

mod support;
use support::*;

use grasp_model::{GraspModel, GraspSolver, LoadedScene, ModelError, SolveOptions, StepInputs};
use serde_json::json;

/// The half-space pad pinch (left jaw held, right jaw 2 N, mu 0.8) on a 15 x 15 grid: small
/// enough for the dense path.
fn pinch() -> serde_json::Value {
    let mut v = example_json("pad_pinch_halfspace.json");
    for f in v["fingers"].as_array_mut().unwrap() {
        f["patch"]["grid"] = json!([15, 15]);
    }
    v
}

fn solve(model: &GraspModel, inputs: &StepInputs) -> grasp_model::Solution {
    let s = GraspSolver::new(model.clone(), SolveOptions::default())
        .solve(inputs)
        .unwrap();
    assert!(s.status.has_forces(), "{:?}", s.reason);
    s
}

/// A held finger pressed in by `StepInputs::with_approach` gives the very numbers (bit for
/// bit: the same program data) of the scene whose finger is position-controlled by that
/// approach, and reports the approach.
#[test]
fn an_approach_in_the_inputs_is_the_scenes_approach() {
    let d = 2e-5;
    let held = GraspModel::from_loaded(&scene(&pinch())).unwrap();
    let mut v = pinch();
    v["fingers"][0]["control"] = json!({ "approach_m": d });
    let pressed = GraspModel::from_loaded(&scene(&v)).unwrap();
    let a = solve(&pressed, &StepInputs::of_scene(&pressed));
    let b = solve(&held, &StepInputs::of_scene(&held).with_approach(0, d));
    assert_eq!(element_force_components(&a), element_force_components(&b));
    assert_eq!(b.fingers[0].approach_m, d);
    assert_eq!(a.fingers[0].approach_m, b.fingers[0].approach_m);
}

/// An extra force at the centre of mass in the inputs balances as the same force written into
/// the scene as an external force there: equal forces to 1e-9 of the load (the two wrenches
/// are summed in different orders, and the solver's tolerance is 1e-10 of the scaled program).
#[test]
fn an_extra_wrench_in_the_inputs_is_an_external_force_of_the_scene() {
    let push = [0.0, 0.0, -0.4];
    let plain = scene(&pinch());
    let com = plain.object.center_of_mass;
    let mut v = pinch();
    v["object"]["external_forces"] = json!([{ "force": push, "at": com }]);
    let written: LoadedScene = scene(&v);
    let a_model = GraspModel::from_loaded(&written).unwrap();
    let a = solve(&a_model, &StepInputs::of_scene(&a_model));
    let model = GraspModel::from_loaded(&plain).unwrap();
    let inputs = StepInputs::of_scene(&model).with_load_at_center_of_mass(
        &model,
        &nalgebra::Vector3::from(push),
        &nalgebra::Vector3::zeros(),
    );
    let b = solve(&model, &inputs);
    let diff = element_force_difference_n(&a, &b);
    let load = a.load_scale_n;
    assert!(diff <= 1e-9 * load, "{diff:e} N of {load} N");
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        assert!((fa.normal_force_n - fb.normal_force_n).abs() <= 1e-9 * load);
    }
}

/// An approach of a force-controlled finger, of a finger the model lacks, or loads of the
/// wrong count are refused before any solve, naming what is wrong.
#[test]
fn inputs_that_do_not_fit_the_model_are_refused() {
    let model = GraspModel::from_loaded(&scene(&pinch())).unwrap();
    let mut solver = GraspSolver::new(model.clone(), SolveOptions::default());
    let e = solver
        .solve(&StepInputs::of_scene(&model).with_approach(1, 1e-5))
        .unwrap_err();
    assert!(
        matches!(&e, ModelError::BadInput(m) if m.contains("`right` is force-controlled")),
        "{e}"
    );
    let e = solver
        .solve(&StepInputs::of_scene(&model).with_approach(5, 1e-5))
        .unwrap_err();
    assert!(
        matches!(&e, ModelError::BadInput(m) if m.contains("finger 5")),
        "{e}"
    );
    let e = solver.solve(&StepInputs::loads(vec![])).unwrap_err();
    assert!(
        matches!(
            e,
            ModelError::LoadCount {
                expected: 1,
                got: 0
            }
        ),
        "{e}"
    );
}
