//! Fingertips as shapes: `tip: {sphere | cylinder | flat}`. Crossed
//! cylinders of equal radius are a sphere near a plane (Johnson, *Contact Mechanics*, 4.2: the
//! gap is `x^2/2R + y^2/2R` either way), a cylindrical tip turned a quarter turn gives the
//! transposed pressure map, a sphere written as `tip` equals `tip_radius`, and every misuse is
//! an error naming the field.

mod support;

use grasp_model::LoadedScene;
use serde_json::{json, Value};
use support::*;

/// The Hertz example (steel sphere R = 10 mm under a flat steel object, 21 x 21 grid).
fn hertz() -> Value {
    example_json("hertz_sphere_on_flat.json")
}

fn without_tip_radius(mut v: Value, tip: Value) -> Value {
    let f = v["fingers"][0].as_object_mut().unwrap();
    f.remove("tip_radius");
    f.insert("tip".into(), tip);
    v
}

fn problem_paths(v: &Value) -> Vec<String> {
    let e = LoadedScene::from_json_str(&v.to_string()).expect_err("refused");
    e.problems().into_iter().map(|p| p.path).collect()
}

#[test]
fn crossed_cylinders_of_equal_radius_press_like_a_sphere_on_a_flat() {
    let sphere = solved(&hertz());
    // The tip's axis along t2 (curved along t1), the object curved along t2 (its axis along t1).
    let frame_t2 = [0.0, 1.0, 0.0]; // t1 = x for a normal along z (the least aligned axis)
    let mut crossed = without_tip_radius(
        hertz(),
        json!({"cylinder": {"radius": 0.01, "axis": frame_t2}}),
    );
    crossed["fingers"][0]["object_radius"] = json!([null, 0.01]);
    let c = solved(&crossed);
    let d = element_force_difference_n(&sphere, &c);
    // The same gap and compliance: equal to round-off.
    assert!(d <= 1e-12 * sphere.load_scale_n, "{d:e}");
}

#[test]
fn a_sphere_written_as_tip_equals_tip_radius() {
    let a = solved(&hertz());
    let b = solved(&without_tip_radius(
        hertz(),
        json!({"sphere": {"radius": 0.01}}),
    ));
    assert_eq!(element_force_difference_n(&a, &b), 0.0);
}

#[test]
fn a_cylindrical_tip_turned_a_quarter_turn_transposes_the_pressure_map() {
    let along_t1 = solved(&without_tip_radius(
        hertz(),
        json!({"cylinder": {"radius": 0.01, "axis": [1, 0, 0]}}),
    ));
    let along_t2 = solved(&without_tip_radius(
        hertz(),
        json!({"cylinder": {"radius": 0.01, "axis": [0, 1, 0]}}),
    ));
    let (a, b) = (&along_t1.fingers[0].elements, &along_t2.fingers[0].elements);
    let n = 21;
    let scale = along_t1.load_scale_n;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (a[i * n + j].normal_force_n, b[j * n + i].normal_force_n);
            // Mirror images on a square grid: equal to the solver's tolerance (1e-10 of the load).
            assert!((x - y).abs() <= 1e-9 * scale, "({i}, {j}): {x} vs {y}");
        }
    }
    // Straight along its axis, the tip touches along the whole centre line of the patch
    // (zero initial gap there), where the sphere's contact circle leaves the ends unloaded.
    let sphere = solved(&hertz());
    let loaded = |e: &[grasp_model::ElementSolution], k: usize| e[k].normal_force_n > 0.0;
    let centre = n / 2;
    assert!(
        (0..n).all(|i| loaded(a, i * n + centre)),
        "the axis line along t1 is in contact"
    );
    assert!(
        !loaded(&sphere.fingers[0].elements, centre),
        "the sphere leaves the patch's edge free"
    );
}

#[test]
fn tip_misuse_names_the_field() {
    let mut both = hertz();
    both["fingers"][0]["tip"] = json!({"sphere": {"radius": 0.01}});
    assert_eq!(problem_paths(&both), ["fingers[0].tip"]);
    let two = without_tip_radius(
        hertz(),
        json!({"sphere": {"radius": 0.01}, "flat": {"size": [1, 1]}}),
    );
    assert_eq!(problem_paths(&two), ["fingers[0].tip"]);
    let skew = without_tip_radius(
        hertz(),
        json!({"cylinder": {"radius": 0.01, "axis": [1, 1, 0]}}),
    );
    assert_eq!(problem_paths(&skew), ["fingers[0].tip.cylinder.axis"]);
    let normal = without_tip_radius(
        hertz(),
        json!({"cylinder": {"radius": 0.01, "axis": [0, 0, 1]}}),
    );
    assert_eq!(problem_paths(&normal), ["fingers[0].tip.cylinder.axis"]);
    let small = without_tip_radius(hertz(), json!({"flat": {"size": [0.0001, 0.001]}}));
    assert_eq!(problem_paths(&small), ["fingers[0].patch.size[0]"]);
    let pad = without_tip_radius(hertz(), json!({"flat": {"size": [0.001, 0.001]}}));
    assert!(LoadedScene::from_json_str(&pad.to_string()).is_ok());
}

#[test]
fn a_placed_finger_takes_its_cylindrical_tips_axis_as_t1() {
    // A cylinder object (axis z) and a tip whose axis is horizontal: t1 follows the tip's
    // axis (the principal direction around the object), t2 the object's axis.
    let v = json!({
        "object": {"weight": 1.0, "center_of_mass": [0, 0, 0], "material": {"youngs_modulus": 7e10, "poisson_ratio": 0.3},
                   "shape": {"cylinder": {"radius": 0.02, "length": 0.2}}},
        "fingers": [{
            "name": "f", "place": {"ray": {"origin": [1, 0, 0], "direction": [-1, 0, 0]}},
            "tip": {"cylinder": {"radius": 0.01, "axis": [0, 1, 0]}},
            "material": {"youngs_modulus": 2e6, "poisson_ratio": 0.45},
            "patch": {"size": [0.004, 0.004], "grid": [5, 5]}, "friction": {"mu": 0.5}
        }]
    });
    let s = LoadedScene::from_json_str(&v.to_string()).unwrap_or_else(|e| panic!("{e}"));
    let d = &s.shape_report().unwrap().fingers[0];
    let t1 = d.tangent.unwrap();
    assert!((t1[1].abs() - 1.0).abs() < 1e-12, "{t1:?}");
    assert!((d.object_radius_m[0].unwrap() - 0.02).abs() < 1e-12 && d.object_radius_m[1].is_none());
}

#[test]
fn the_hertz_suggestion_is_hertz_and_its_patch_holds_the_contact() {
    use grasp_model::closed_form::HertzSphere;
    use grasp_model::hertz_suggestion;
    let v = hertz();
    let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
    let model = grasp_model::GraspModel::from_loaded(&scene).unwrap();
    let h = hertz_suggestion(&scene.fingers[0], &model.fingers()[0], 10.0).unwrap();
    // Steel on steel: E* = E / (2 (1 - nu^2)).
    let exact = HertzSphere::new(10.0, 0.01, 2.1e11 / (2.0 * (1.0 - 0.09)));
    for a in h.semi_axes_m {
        assert!((a.unwrap() - exact.contact_radius_m).abs() <= 1e-12 * exact.contact_radius_m);
    }
    // Solved on the suggested patch, the contact leaves the patch's boundary ring unloaded
    // (thesis 2.2.1): the patch holds the contact.
    let mut w = v.clone();
    w["fingers"][0]["patch"]["size"] = json!(h.suggested_size_m);
    let s = solved(&w);
    assert!(
        s.fingers[0].boundary_load_fraction < 1e-9,
        "{}",
        s.fingers[0].boundary_load_fraction
    );
}

/// The tip drawn by the Rerun and Foxglove sinks, for `v`'s only finger.
fn tip_drawing(v: &Value) -> (grasp_transfer::TipDrawing, grasp_model::FingerModel) {
    let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
    let model = grasp_model::GraspModel::from_loaded(&scene).unwrap();
    let run = grasp_transfer::RunInfo {
        scene: &scene,
        model: &model,
        margins: false,
    };
    let mut tips = grasp_transfer::tip_drawings(&run, 0.05);
    assert_eq!(tips.len(), 1);
    (tips.remove(0).1, model.fingers()[0].clone())
}

/// Each tip shape is drawn touching the contact point from the finger's side (outside the
/// object, against the inward normal), with the tip's own size: the sphere and the cylinder
/// of radius R have their centre at `origin - R n` (and the cylinder's axis along the
/// tangent it is straight along), the flat pad's face lies in the contact plane; a curved tip
/// far larger than the scene is drawn as a pad. Tolerance: round-off of unit frames (1e-12 m).
#[test]
fn every_tip_shape_is_drawn_touching_its_contact_from_outside() {
    use grasp_transfer::TipDrawing;
    let (sphere, f) = tip_drawing(&hertz());
    let (o, n) = (f.frame().origin_m, f.frame().normal);
    match sphere {
        TipDrawing::Sphere { centre, radius_m } => {
            assert!((radius_m - 0.01).abs() < 1e-15);
            assert!((centre - (o - n * 0.01)).norm() < 1e-12);
        }
        other => panic!("a sphere tip drawn as {other:?}"),
    }
    let cyl = json!({"cylinder": {"radius": 0.004, "axis": [0, -1, 0]}});
    match tip_drawing(&without_tip_radius(hertz(), cyl)).0 {
        TipDrawing::Cylinder {
            centre,
            axis,
            radius_m,
            length_m,
        } => {
            assert!((radius_m - 0.004).abs() < 1e-15);
            assert!((centre - (o - n * 0.004)).norm() < 1e-12);
            assert!(
                axis.cross(&f.frame().t2).norm() < 1e-12,
                "along t2: {axis:?}"
            );
            assert!(length_m >= 2.0 * radius_m);
        }
        other => panic!("a cylinder tip drawn as {other:?}"),
    }
    let pad = json!({"flat": {"size": [0.003, 0.002]}});
    match tip_drawing(&without_tip_radius(hertz(), pad)).0 {
        TipDrawing::Pad {
            centre,
            rotation,
            half_sizes_m,
        } => {
            assert!(
                (half_sizes_m.x - 0.0015).abs() < 1e-15 && (half_sizes_m.y - 0.001).abs() < 1e-15
            );
            assert!((rotation * nalgebra::Vector3::z() - n).norm() < 1e-12);
            assert!((rotation * nalgebra::Vector3::x() - f.frame().t1).norm() < 1e-12);
            // The face towards the object lies in the contact plane, through the contact.
            assert!((centre + n * half_sizes_m.z - o).norm() < 1e-12);
        }
        other => panic!("a flat tip drawn as {other:?}"),
    }
    let huge = json!({"sphere": {"radius": 100.0}});
    let (drawn, _) = tip_drawing(&without_tip_radius(hertz(), huge));
    assert!(matches!(drawn, TipDrawing::Pad { .. }), "{drawn:?}");
}
