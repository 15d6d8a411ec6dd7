//! A scene pays only for what it needs: unknowns, rows and nonzeros follow the scene.

mod support;
use support::*;

use grasp_model::{GraspModel, GraspSolver, SolveOptions};
use serde_json::json;

fn program(v: &serde_json::Value) -> (GraspModel, GraspSolver) {
    let m = GraspModel::from_loaded(&scene(v)).unwrap();
    let s = GraspSolver::new(m.clone(), SolveOptions::default());
    (m, s)
}

#[test]
fn planar_scene_has_three_equilibrium_rows_and_one_tangential_unknown_per_element() {
    let v = example_json("plate_four_fingers.json");
    let (m, s) = program(&v);
    let elements: usize = m.fingers().iter().map(|f| f.patch().len()).sum();
    assert_eq!(m.n_unknowns(), 2 * elements);
    assert_eq!(m.equilibrium_rows(), 3);
    assert_eq!(s.program().equilibrium_rows(), 3);
}

#[test]
fn three_d_scene_has_six_rows_and_two_tangential_unknowns() {
    let (m, s) = program(&example_json("cube_a.json"));
    let elements: usize = m.fingers().iter().map(|f| f.patch().len()).sum();
    assert_eq!(m.n_unknowns(), 3 * elements);
    assert_eq!(s.program().equilibrium_rows(), 6);
}

#[test]
fn frictionless_finger_has_no_tangential_unknowns() {
    let mut v = example_json("cube_a.json");
    v["fingers"][2]["friction"]["mu"] = json!(0.0);
    let (m, _) = program(&v);
    assert_eq!(m.fingers()[2].n_tangential(), 0);
    assert_eq!(m.fingers()[2].n_unknowns(), 25);
    assert_eq!(m.n_unknowns(), 75 + 75 + 25);
}

#[test]
fn equal_materials_add_no_coupling_entries() {
    let v = example_json("cube_a.json");
    let mut w = v.clone();
    // Same material for fingers and object: the coupling blocks vanish exactly.
    let obj = w["object"]["material"].clone();
    for f in w["fingers"].as_array_mut().unwrap() {
        f["material"] = obj.clone();
    }
    let (_ma, a) = program(&v);
    let (_mb, b) = program(&w);
    let (na, nb) = (
        a.clarabel_form().p.nzval.len(),
        b.clarabel_form().p.nzval.len(),
    );
    // Per finger of N = 25 elements, the two coupling blocks hold 2 N^2 entries minus the
    // ones on the N x N antisymmetric structure's zero diagonal (X = 0 for each self term).
    assert!(nb < na, "{nb} >= {na}");
    let n = 25usize;
    let per_finger_coupling = na / 3 - nb / 3;
    assert!(
        per_finger_coupling >= n * n,
        "only {per_finger_coupling} coupling entries dropped"
    );
}
