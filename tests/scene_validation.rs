//! Bad scene files: each class of mistake gives an error naming the JSON path and the fix.

mod support;
use support::*;

use grasp_model::{LoadedScene, SceneError};
use serde_json::{json, Value};

fn cube() -> Value {
    example_json("cube_a.json")
}

#[test]
fn zero_length_normal() {
    let mut v = cube();
    v["fingers"][2]["normal"] = json!([0, 0, 0]);
    assert_refused(&v, "fingers[2].normal", "zero length");
}

#[test]
fn contact_point_far_from_any_plausible_object() {
    let mut v = cube();
    // Millimetres typed where metres are expected.
    v["fingers"][1]["contact_point"] = json!([50.0, 0.0, 50.0]);
    assert_refused(&v, "fingers[1].contact_point", "no plausible object");
}

#[test]
fn nonpositive_modulus() {
    let mut v = cube();
    v["fingers"][0]["material"]["youngs_modulus"] = json!(0.0);
    assert_refused(&v, "fingers[0].material.youngs_modulus", "is 0 Pa");
    let mut v = cube();
    v["object"]["material"]["youngs_modulus"] = json!(-5e9);
    assert_refused(&v, "object.material.youngs_modulus", "is -5e9 Pa");
}

#[test]
fn poisson_ratio_outside_its_range() {
    for bad in [0.5, -0.1, 0.7] {
        let mut v = cube();
        v["fingers"][1]["material"]["poisson_ratio"] = json!(bad);
        assert_refused(&v, "fingers[1].material.poisson_ratio", "is");
    }
}

#[test]
fn patch_grid_of_zero() {
    let mut v = cube();
    v["fingers"][0]["patch"]["grid"] = json!([0, 5]);
    assert_refused(&v, "fingers[0].patch.grid[0]", "is 0");
}

#[test]
fn duplicate_finger_names() {
    let mut v = cube();
    v["fingers"][2]["name"] = json!("f1");
    assert_refused(&v, "fingers[2].name", "also the name of fingers[0]");
}

#[test]
fn unknown_fields_are_named_with_their_path() {
    let mut v = cube();
    v["fingers"][1]["frictoin"] = v["fingers"][1]["friction"].clone();
    let p = problems(&v);
    assert!(
        p[0].starts_with("fingers[1]") && p[0].contains("frictoin"),
        "{p:?}"
    );
    let mut v = cube();
    v["object"]["mass"] = json!(1.0);
    let p = problems(&v);
    assert!(p[0].starts_with("object") && p[0].contains("mass"), "{p:?}");
}

#[test]
fn wrong_types_are_named_with_their_path() {
    let mut v = cube();
    v["fingers"][0]["normal"] = json!([0, 1]);
    let p = problems(&v);
    assert!(p[0].starts_with("fingers[0].normal"), "{p:?}");
    let mut v = cube();
    v["fingers"][0]["control"] = json!("squeeze");
    let p = problems(&v);
    assert!(
        p[0].starts_with("fingers[0].control") && p[0].contains("held"),
        "{p:?}"
    );
}

#[test]
fn every_problem_is_reported_at_once() {
    let mut v = cube();
    v["fingers"][0]["normal"] = json!([0, 0, 0]);
    v["fingers"][1]["friction"]["mu"] = json!(-1.0);
    v["object"]["weight"] = json!(-2.0);
    let p = problems(&v);
    assert_eq!(p.len(), 3, "{p:#?}");
    let e = LoadedScene::from_json_str(&v.to_string()).unwrap_err();
    assert!(matches!(e, SceneError::Invalid(_)));
    assert!(e.to_string().contains("3 problem(s)"));
}

/// Every missing field at once, each with its own fix (a scene missing
/// `object.weight` and `fingers[1].normal` reported only the first, without a fix): the
/// fields a scene needs unless it derives them (a finger's frame without `place`, the
/// object's weight and centre of mass without a density) as well as the always required.
#[test]
fn every_missing_field_is_reported_with_its_fix() {
    // (JSON pointers removed, [(path, words of its fix)] expected)
    type Case = (
        &'static [&'static str],
        &'static [(&'static str, &'static str)],
    );
    let cases: [Case; 3] = [
        (
            &["/object/weight", "/fingers/1/normal"],
            &[
                ("object.weight", "newtons"),
                ("fingers[1].normal", "into the object"),
            ],
        ),
        (
            &[
                "/object/center_of_mass",
                "/fingers/0/contact_point",
                "/fingers/2/patch",
            ],
            &[
                ("object.center_of_mass", "world frame"),
                ("fingers[0].contact_point", "`place`"),
                ("fingers[2].patch", "add `patch`"),
            ],
        ),
        (
            &[
                "/fingers/0/normal",
                "/fingers/1/normal",
                "/fingers/2/normal",
            ],
            &[
                ("fingers[0].normal", "into the object"),
                ("fingers[1].normal", "into the object"),
                ("fingers[2].normal", "into the object"),
            ],
        ),
    ];
    for (removed, expected) in cases {
        let mut v = cube();
        for ptr in removed {
            let (parent, key) = ptr.rsplit_once('/').unwrap();
            v.pointer_mut(parent)
                .unwrap()
                .as_object_mut()
                .unwrap()
                .remove(key);
        }
        let p = problems(&v);
        assert_eq!(p.len(), expected.len(), "{removed:?}: {p:#?}");
        for (path, words) in expected {
            assert_refused(&v, path, "is missing");
            assert!(
                p.iter().any(|m| m.starts_with(path) && m.contains(words)),
                "{path}: {p:#?}"
            );
        }
    }
}

#[test]
fn both_bodies_rigid() {
    let mut v = cube();
    v["object"]["material"] = json!("rigid");
    v["fingers"][0]["material"] = json!("rigid");
    assert_refused(&v, "fingers[0].material", "rigid and so is the object");
    // One rigid body per contact is fine.
    let mut v = cube();
    v["object"]["material"] = json!("rigid");
    assert!(LoadedScene::from_json_str(&v.to_string()).is_ok());
}

#[test]
fn planar_scene_with_a_point_off_the_plane() {
    let mut v = example_json("plate_four_fingers.json");
    v["fingers"][1]["contact_point"] = json!([0.03, 0.01, -0.05]);
    assert_refused(&v, "fingers[1].contact_point", "off the plane");
    let mut v = example_json("plate_four_fingers.json");
    v["fingers"][0]["normal"] = json!([1, 1, 0]);
    assert_refused(&v, "fingers[0].normal", "leaves the plane");
}

#[test]
fn radius_smaller_than_the_patch() {
    let mut v = cube();
    v["fingers"][0]["tip_radius"] = json!(0.001);
    assert_refused(&v, "fingers[0].tip_radius", "smaller than half the patch");
}

#[test]
fn tangent_parallel_to_the_normal() {
    let mut v = cube();
    v["fingers"][2]["tangent"] = json!([0, 0, 2]);
    assert_refused(&v, "fingers[2].tangent", "parallel to the normal");
}

#[test]
fn friction_tables_must_be_sorted_and_nonnegative() {
    let mut v = cube();
    v["fingers"][1]["friction"] = json!({"table": [[0.0, 0.3], [2.0, 0.5], [1.0, 0.4]]});
    assert_refused(
        &v,
        "fingers[1].friction.table[2][0]",
        "not above the previous load",
    );
    v["fingers"][1]["friction"] = json!({"table": [[0.0, -0.3]]});
    assert_refused(&v, "fingers[1].friction.table[0][1]", "is -0.3");
    v["fingers"][1]["friction"] = json!({"table": []});
    assert_refused(&v, "fingers[1].friction.table", "is empty");
}

#[test]
fn elastic_friction_law_needs_r1_below_r2_and_an_elastic_object() {
    let mut v = cube();
    v["fingers"][0]["friction"] =
        json!({"elastic": {"finger_radius": 0.02, "object_radius": 0.01, "contact_length": 0.01}});
    assert_refused(
        &v,
        "fingers[0].friction.elastic.object_radius",
        "not larger",
    );
    v["fingers"][0]["friction"] =
        json!({"elastic": {"finger_radius": 0.01, "object_radius": 1.0, "contact_length": 0.0}});
    assert_refused(&v, "fingers[0].friction.elastic.contact_length", "is 0 m");
    v["fingers"][0]["friction"] =
        json!({"elastic": {"finger_radius": 0.01, "object_radius": 1.0, "contact_length": 0.01}});
    v["object"]["material"] = json!("rigid");
    assert_refused(&v, "fingers[0].friction.elastic", "needs an elastic object");
}

#[test]
fn unknown_friction_law_says_what_is_expected() {
    let mut v = cube();
    v["fingers"][0]["friction"] = json!({"coefficient": 0.3});
    assert_refused(&v, "fingers[0].friction", "expected a friction law");
    v["model"] = json!("tresca");
    v["fingers"][0]["friction"] = json!({"mu": 0.3});
    assert_refused(&v, "model", "coulomb");
}

#[test]
fn numbers_outside_the_physical_range() {
    let cases = [
        (
            "/object/weight",
            json!(1e200),
            "object.weight",
            "neither 0 nor in [1e-15, 1e7] N",
        ),
        (
            "/fingers/0/control",
            json!({"normal_load": 1e308}),
            "fingers[0].control.normal_load",
            "neither 0 nor",
        ),
        (
            "/fingers/1/contact_point",
            json!([1e308, 0.0, 0.0]),
            "fingers[1].contact_point[0]",
            "outside [-1e3, 1e3] m",
        ),
        (
            "/object/external_forces",
            json!([{"force": [0, 0, -1e200], "at": [0, 0, 0]}]),
            "object.external_forces[0].force[2]",
            "neither 0 nor",
        ),
        (
            "/fingers/2/friction",
            json!({"mu": 1e9}),
            "fingers[2].friction.mu",
            "neither 0 nor",
        ),
        (
            "/fingers/2/friction",
            json!({"mu": 1e-320}),
            "fingers[2].friction.mu",
            "neither 0 nor",
        ),
        (
            "/object/weight",
            json!(1e-320),
            "object.weight",
            "neither 0 nor",
        ),
        (
            "/fingers/0/tip_radius",
            json!(1e9),
            "fingers[0].tip_radius",
            "outside",
        ),
    ];
    for (ptr, value, path, words) in cases {
        let mut v = cube();
        set(&mut v, ptr, value);
        assert_refused(&v, path, words);
    }
}

#[test]
fn huge_and_tiny_directions_normalise_without_overflow() {
    let mut v = cube();
    v["object"]["gravity"] = json!([0.0, 0.0, -1e200]);
    v["fingers"][0]["normal"] = json!([1e-200, 0.0, 0.0]);
    let s = scene(&v);
    assert_eq!(s.object.gravity, [0.0, 0.0, -1.0]);
    assert_eq!(s.fingers[0].normal, [1.0, 0.0, 0.0]);
    // The solve sees the same scene as with unit vectors.
    let mut w = cube();
    w["object"]["gravity"] = json!([0.0, 0.0, -1.0]);
    w["fingers"][0]["normal"] = json!([1.0, 0.0, 0.0]);
    assert_eq!(s, scene(&w));
    // A scene built in code is checked as it is: a square that overflows is refused.
    let mut built = scene(&w);
    built.object.gravity = [0.0, 0.0, -1e200];
    let e = built.validate().unwrap_err().to_string();
    assert!(e.contains("object.gravity: has a length"), "{e}");
}

#[test]
fn trailing_data_after_the_scene() {
    for tail in [" {}", "x", "\n{\"object\": 1}"] {
        let text = format!("{}{tail}", cube());
        let e = LoadedScene::from_json_str(&text).unwrap_err().to_string();
        assert!(e.contains("trailing characters at line"), "{e}");
    }
    assert!(LoadedScene::from_json_str(&format!("{}\n\n", cube())).is_ok());
}

#[test]
fn duplicate_keys_in_the_scene() {
    let text = cube().to_string();
    let twice = text.replacen("\"weight\":", "\"weight\": 1.0, \"weight\":", 1);
    let e = LoadedScene::from_json_str(&twice).unwrap_err().to_string();
    assert!(e.contains("object: duplicate field `weight`"), "{e}");
    let twice = text.replacen("\"mu\":", "\"mu\": 0.1, \"mu\":", 1);
    let e = LoadedScene::from_json_str(&twice).unwrap_err().to_string();
    assert!(
        e.contains("fingers[0].friction: duplicate field `mu`"),
        "{e}"
    );
}

#[test]
fn nested_enum_errors_name_the_inner_field() {
    let cases = [
        (
            "/object/material/poisson_ratio",
            json!("x"),
            "object.material.poisson_ratio: is the string \"x\", expected a number",
        ),
        (
            "/fingers/0/friction",
            json!({"mu": "a"}),
            "fingers[0].friction.mu: is the string \"a\", expected a number",
        ),
        (
            "/fingers/1/friction",
            json!({"table": [[0.0, "x"]]}),
            "fingers[1].friction.table[0][1]: is the string \"x\", expected a number",
        ),
        (
            "/fingers/2/control",
            json!({"normal_load": true}),
            "fingers[2].control.normal_load: is a boolean, expected a number",
        ),
        (
            "/fingers/0/material",
            json!({"youngs_modulus": 1e6}),
            "fingers[0].material.poisson_ratio: is missing; fix: add `poisson_ratio`",
        ),
        (
            "/fingers/0/object_radius",
            json!([0.05, "flat"]),
            "fingers[0].object_radius[1]: is the string \"flat\", expected a number or null",
        ),
        (
            "/fingers/0/friction",
            json!({"elastic": {"finger_radius": 0.01, "object_radius": 1.0}}),
            "fingers[0].friction.elastic.contact_length: is missing; fix: add `contact_length`",
        ),
    ];
    // Each mistake is the one problem listed (the walk against the schema finds no other).
    for (ptr, value, want) in cases {
        let mut v = cube();
        set(&mut v, ptr, value);
        let p = problems(&v);
        assert!(
            p.len() == 1 && p[0].starts_with(want),
            "want `{want}`, got {p:#?}"
        );
    }
}

/// Sets the value at a JSON pointer, adding the last key if missing.
fn set(v: &mut Value, ptr: &str, value: Value) {
    let (parent, key) = ptr.rsplit_once('/').unwrap();
    let p = v.pointer_mut(parent).unwrap();
    match p {
        Value::Array(a) => a[key.parse::<usize>().unwrap()] = value,
        Value::Object(m) => {
            m.insert(key.to_string(), value);
        }
        _ => panic!("{ptr}"),
    }
}

/// A layer thickness that is not a thickness: zero, negative, not finite, or out of
/// the physical range (a micrometre to a metre; millimetres typed as metres land above it).
#[test]
fn layer_thickness_outside_its_range() {
    for (h, words) in [
        (json!(0.0), "outside [1e-6, 1e0] m"),
        (json!(-0.001), "outside"),
        (json!(2.0), "outside"),
        (json!(1e-9), "outside"),
    ] {
        let mut v = cube();
        v["fingers"][1]["material"]["layer_thickness_m"] = h.clone();
        assert_refused(&v, "fingers[1].material.layer_thickness_m", words);
        let mut v = cube();
        v["object"]["material"]["layer_thickness_m"] = h;
        assert_refused(&v, "object.material.layer_thickness_m", words);
    }
    // A rigid body has no layer: the field has nowhere to go.
    let mut v = cube();
    v["object"]["material"] = json!("rigid");
    v["fingers"][0]["material"] = json!({"layer_thickness_m": 0.001});
    assert!(!problems(&v).is_empty());
}

/// A layer the grid cannot resolve (elements larger than its thickness), and one so thick it
/// is a half-space to 1e-6, are solved but warned about, each naming its field and the fix; a
/// resolved layer is not.
#[test]
fn unresolved_and_half_space_like_layers_are_warned_about() {
    use grasp_model::solve;
    use grasp_model::GraspModel;
    let warnings = |finger_h: f64, patch: f64| {
        let mut v = cube();
        for f in v["fingers"].as_array_mut().unwrap() {
            f["material"]["layer_thickness_m"] = json!(finger_h);
            f["patch"]["size"] = json!([patch, patch]);
        }
        let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
        let model = GraspModel::from_loaded(&scene).unwrap();
        solve(&model).unwrap().warnings
    };
    // cube A's 5 x 5 grids on 5 mm patches: elements of 1 mm.
    let thin = warnings(2e-4, 0.005);
    assert!(
        thin.iter()
            .any(|w| w.starts_with("fingers[0].material.layer_thickness_m")
                && w.contains("cannot resolve")
                && w.contains("patch.grid [25, 25]")),
        "{thin:#?}"
    );
    let thick = warnings(1.0, 1e-5);
    assert!(
        thick
            .iter()
            .any(|w| w.starts_with("fingers[2].material.layer_thickness_m")
                && w.contains("half-space")
                && w.contains("omit layer_thickness_m")),
        "{thick:#?}"
    );
    let fine = warnings(2e-3, 0.005);
    assert!(
        !fine.iter().any(|w| w.contains("layer_thickness_m")),
        "{fine:#?}"
    );
}

/// Relaxation laws and approach control: fractions outside `[0, 1)` or summing to
/// 1 or more, times out of range, a long-term modulus above the instantaneous one, and an
/// approach out of range are named with the fix.
#[test]
fn relaxation_laws_and_approaches_out_of_range() {
    let law = |r: Value| {
        let mut v = cube();
        v["fingers"][0]["material"]["relaxation"] = r;
        v
    };
    assert_refused(
        &law(json!([{"fraction": 1.2, "time_s": 1.0}])),
        "fingers[0].material.relaxation[0].fraction",
        "is 1.2",
    );
    assert_refused(
        &law(json!([{"fraction": 0.6, "time_s": 1.0}, {"fraction": 0.5, "time_s": 2.0}])),
        "fingers[0].material.relaxation",
        "summing to 1.1",
    );
    assert_refused(
        &law(json!([{"fraction": 0.3, "time_s": 0.0}])),
        "fingers[0].material.relaxation[0].time_s",
        "outside",
    );
    assert_refused(
        &law(json!({"long_term_modulus": 1e12, "time_s": 1.0})),
        "fingers[0].material.relaxation.long_term_modulus",
        "is 1e12 Pa",
    );
    // A negative approach withdraws the finger (a jaw opened short of first touch): up to 1 m
    // either way.
    let mut v = cube();
    v["fingers"][1]["control"] = json!({"approach_m": -1.5});
    assert_refused(&v, "fingers[1].control.approach_m", "outside");
    v["fingers"][1]["control"] = json!({"approach_m": -0.001});
    assert!(LoadedScene::from_json_str(&v.to_string()).is_ok());
}

/// Unbounded work: inputs whose cost grows without bound are refused with the
/// bound named. A Prony series of more than 32 terms (its stepping costs the square of the
/// count: 10,000 terms ran 236 s), a patch side of more than 2048 elements (a 1 x 1,048,576
/// strip passed the element count and ran for minutes), a bonded layer's Poisson's ratio
/// within 1e-9 of 0.5.
#[test]
fn unbounded_work_is_refused_with_its_bound() {
    let terms = |n: usize| {
        (0..n)
            .map(|i| json!({"fraction": 0.5 / n as f64, "time_s": 10f64.powf(i as f64 / 8.0)}))
            .collect::<Vec<_>>()
    };
    let mut v = cube();
    v["fingers"][0]["material"]["relaxation"] = json!(terms(32));
    assert!(
        LoadedScene::from_json_str(&v.to_string()).is_ok(),
        "32 terms are a law"
    );
    for n in [33, 1000] {
        v["fingers"][0]["material"]["relaxation"] = json!(terms(n));
        assert_refused(
            &v,
            "fingers[0].material.relaxation",
            &format!("has {n} terms, more than 32"),
        );
    }
    // A layer's Poisson's ratio within 1e-9 of 0.5 (a coating at 0.5 - 1e-14 ran 253 s to
    // no convergence); 0.499999 (the squeeze-film check's) stays a layer.
    let mut v = cube();
    v["fingers"][0]["material"] =
        json!({"youngs_modulus": 1e6, "poisson_ratio": 0.499999, "layer_thickness_m": 1e-3});
    assert!(LoadedScene::from_json_str(&v.to_string()).is_ok());
    for nu in [0.49999999999999, 0.4999999999] {
        v["fingers"][0]["material"]["poisson_ratio"] = json!(nu);
        assert_refused(
            &v,
            "fingers[0].material.poisson_ratio",
            "for a bonded layer, nearer 0.5 than 1e-9",
        );
    }
    for grid in [[1, 4_194_304], [2049, 4], [4, 4096]] {
        let mut v = cube();
        v["fingers"][2]["patch"]["grid"] = json!(grid);
        let k = if grid[0] > 2048 { 0 } else { 1 };
        assert_refused(
            &v,
            &format!("fingers[2].patch.grid[{k}]"),
            "more than 2048 elements along a side",
        );
    }
}

/// Textures (`fingers[i].texture`) with one member too many or too few, numbers out of range,
/// a wavelength the elements cannot resolve, or a generation grid too large: each is named
/// with its path and the fix. Cube A's patches are 10 mm of 5 x 5 elements (2 mm).
#[test]
fn textures_out_of_range_or_unresolved() {
    let ridges = json!({"amplitude_m": 1e-6, "period_m": 5e-3, "angle_deg": 0});
    let random = json!({"rms_m": 1e-6, "hurst": 0.8, "wavelengths_m": [2e-2, 5e-3]});
    let with = |t: Value| {
        let mut v = cube();
        v["fingers"][0]["texture"] = t;
        v
    };
    // The unchanged ones are accepted.
    scene(&with(json!({ "ridges": ridges })));
    scene(&with(json!({ "random": random })));
    let changed = |base: &Value, key: &str, value: Value| {
        let mut t = base.clone();
        t[key] = value;
        t
    };
    let cases = [
        (json!({}), "fingers[0].texture", "has 0 of heights"),
        (
            json!({"ridges": ridges, "random": random}),
            "fingers[0].texture",
            "has 2 of heights",
        ),
        (
            json!({"ridges": changed(&ridges, "amplitude_m", json!(1.0))}),
            "fingers[0].texture.ridges.amplitude_m",
            "larger than the patch",
        ),
        (
            json!({"ridges": changed(&ridges, "period_m", json!(0.0))}),
            "fingers[0].texture.ridges.period_m",
            "outside",
        ),
        // 3 mm across ridges along t1: shorter than two 2 mm elements.
        (
            json!({"ridges": changed(&ridges, "period_m", json!(3e-3))}),
            "fingers[0].texture.ridges.period_m",
            "cannot resolve",
        ),
        (
            json!({"ridges": changed(&ridges, "angle_deg", json!(1e9))}),
            "fingers[0].texture.ridges.angle_deg",
            "outside",
        ),
        (
            json!({"random": changed(&random, "hurst", json!(0.0))}),
            "fingers[0].texture.random.hurst",
            "outside (0, 1]",
        ),
        (
            json!({"random": changed(&random, "hurst", json!(1.5))}),
            "fingers[0].texture.random.hurst",
            "outside (0, 1]",
        ),
        (
            json!({"random": changed(&random, "rms_m", json!(-1e-6))}),
            "fingers[0].texture.random.rms_m",
            "outside",
        ),
        (
            json!({"random": changed(&random, "wavelengths_m", json!([1e-3, 5e-3]))}),
            "fingers[0].texture.random.wavelengths_m",
            "not above short",
        ),
        (
            json!({"random": changed(&random, "wavelengths_m", json!([2e-2, 3e-3]))}),
            "fingers[0].texture.random.wavelengths_m[1]",
            "cannot resolve",
        ),
        // A 2 m roll-off over 5 mm: 3200 pixels of 0.625 mm -> 4096 fits; 20 m does not.
        (
            json!({"random": changed(&random, "wavelengths_m", json!([20.0, 5e-3]))}),
            "fingers[0].texture.random.wavelengths_m",
            "generation grid",
        ),
        (
            json!({"heights": {"file": "h.npy", "pixel_m": [1e-3, 1e-3]}}),
            "fingers[0].texture.heights.file",
            "reads no height maps",
        ),
    ];
    for (texture, path, words) in cases {
        assert_refused(&with(texture), path, words);
    }
    // The fix of an unresolved wavelength names the grid that resolves it: 10 mm over
    // 3 mm / 2 = 6.7 -> 7 elements.
    let p = problems(&with(
        json!({"ridges": changed(&ridges, "period_m", json!(3e-3))}),
    ));
    assert!(
        p.iter()
            .any(|m| m.contains("patch.grid to at least [7, 5]")),
        "{p:#?}"
    );
}

/// Height maps read from files: one that does not cover the patch, one not in metres, one
/// with a NaN, a CSV with a header and a missing file are each named at
/// `fingers[i].texture.heights.file` with the fix.
#[test]
fn height_map_files_that_cannot_serve() {
    let dir = std::env::temp_dir().join(format!("grasp-maps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Each case its own file (named for its pixel size); `None` writes none.
    let read = |csv: Option<&str>, pixel: f64| {
        let file = format!("m{}.csv", pixel.to_bits());
        if let Some(text) = csv {
            std::fs::write(dir.join(&file), text).unwrap();
        }
        let mut v = cube();
        v["fingers"][1]["texture"] = json!({"heights": {"file": file, "pixel_m": [pixel, pixel]}});
        grasp_io::scene_from_json_str(&v.to_string(), &dir)
    };
    let problems_of = |csv: Option<&str>, pixel: f64| match read(csv, pixel) {
        Ok(_) => panic!("accepted"),
        Err(e) => e
            .problems()
            .iter()
            .map(|p| p.to_string())
            .collect::<Vec<_>>(),
    };
    let has = |p: &[String], words: &str| {
        assert!(
            p.iter()
                .any(|m| m.starts_with("fingers[1].texture.heights.file")
                    && m.contains(words)
                    && m.contains("fix")),
            "expected {words}: {p:#?}"
        )
    };
    // 3 x 3 pixels of 1 mm cover +-1 mm; the element centres reach +-4 mm.
    let small = "0,0,0\n0,1e-6,0\n0,0,0\n";
    has(&problems_of(Some(small), 1e-3), "reach +-0.004 m");
    // With 4 mm pixels it covers them.
    assert!(read(Some(small), 4e-3).is_ok());
    has(
        &problems_of(Some("0,0,0\n0,3,0\n0,0,0\n"), 4.1e-3),
        "larger than the patch",
    );
    has(
        &problems_of(Some("0,0,0\n0,nan,0\n0,0,0\n"), 4.2e-3),
        "row 1, column 1",
    );
    has(&problems_of(Some("a,b,c\n0,0,0\n"), 4.3e-3), "header line");
    has(&problems_of(None, 4.4e-3), "relative to the scene file");
}

/// Mounts (`fingers[i].mount`): each bad stiffness named at its path with the fix; a matrix
/// that is not symmetric or not positive definite; a compliance that is not symmetric, not
/// positive semidefinite, all zero or too large; a mount with no stiffness or two forms; a
/// preload a force-controlled finger or a rigid normal cannot take.
#[test]
fn mounts_out_of_range_are_named() {
    let with = |mount: Value| {
        let mut v = cube();
        v["fingers"][0]["mount"] = mount;
        v
    };
    let mut k = [[0.0; 6]; 6];
    for (c, row) in k.iter_mut().enumerate() {
        row[c] = 1e3;
    }
    let cases = [
        (json!({}), "fingers[0].mount", "gives no stiffness"),
        (
            json!({"normal_n_per_m": 0.0}),
            "fingers[0].mount.normal_n_per_m",
            "outside",
        ),
        (
            json!({"tangential_n_per_m": 1e16}),
            "fingers[0].mount.tangential_n_per_m",
            "outside",
        ),
        (
            json!({"rotational_nm_per_rad": -1.0}),
            "fingers[0].mount.rotational_nm_per_rad",
            "outside",
        ),
        (
            json!({"matrix": k, "normal_n_per_m": 1.0}),
            "fingers[0].mount",
            "more than one form",
        ),
        (
            json!({"matrix": k, "compliance": k}),
            "fingers[0].mount",
            "more than one form",
        ),
        (
            json!({ "compliance": k.map(|r| r.map(|_| 0.0)) }),
            "fingers[0].mount.compliance",
            "all zero",
        ),
        (
            json!({"compliance": k.map(|r| r.map(|x| x * 1e4))}),
            "fingers[0].mount.compliance[0][0]",
            "is 1e7",
        ),
        (
            json!({"normal_n_per_m": 1e3, "preload_n": -1.0}),
            "fingers[0].mount.preload_n",
            "is -1",
        ),
        (
            json!({"tangential_n_per_m": 1e3, "preload_n": 1.0}),
            "fingers[0].mount.preload_n",
            "rigid along the normal",
        ),
    ];
    for (mount, path, what) in cases {
        assert_refused(&with(mount), path, what);
    }
    let mut asymmetric = k;
    asymmetric[0][4] = 10.0;
    assert_refused(
        &with(json!({"matrix": asymmetric})),
        "fingers[0].mount.matrix[0][4]",
        "symmetric",
    );
    let mut indefinite = k;
    indefinite[1][3] = 2e3;
    indefinite[3][1] = 2e3;
    assert_refused(
        &with(json!({"matrix": indefinite})),
        "fingers[0].mount.matrix",
        "not positive definite",
    );
    // A compliance: its own checks, by its own path (a hinge's rank-one `J J' / K_q` passes).
    let compliance = |s: [[f64; 6]; 6]| with(json!({ "compliance": s }));
    assert_refused(
        &compliance(asymmetric.map(|r| r.map(|x| x * 1e-6))),
        "fingers[0].mount.compliance[0][4]",
        "symmetric",
    );
    assert_refused(
        &compliance(indefinite.map(|r| r.map(|x| x * 1e-6))),
        "fingers[0].mount.compliance",
        "not positive semidefinite",
    );
    let j = [0.0, 0.0, 0.05, -1.0, 0.0, 0.0];
    let hinge: [[f64; 6]; 6] = std::array::from_fn(|r| std::array::from_fn(|c| j[r] * j[c] / 5.0));
    let mut v = compliance(hinge);
    v["fingers"][0]["mount"]["preload_n"] = json!(1.0);
    v["fingers"][0]["control"] = json!({"approach_m": 0.0});
    let accepted = LoadedScene::from_json_str(&v.to_string());
    assert!(accepted.is_ok(), "{:?}", accepted.err());
    let j = [0.0, 0.05, 0.0, -1.0, 0.0, 0.0];
    let across: [[f64; 6]; 6] = std::array::from_fn(|r| std::array::from_fn(|c| j[r] * j[c] / 5.0));
    let mut v = compliance(across);
    v["fingers"][0]["mount"]["preload_n"] = json!(1.0);
    v["fingers"][0]["control"] = json!({"approach_m": 0.0});
    assert_refused(
        &v,
        "fingers[0].mount.preload_n",
        "does not move the core along the normal",
    );
    let mut loaded = with(json!({"normal_n_per_m": 1e3, "preload_n": 1.0}));
    loaded["fingers"][0]["control"] = json!({"normal_load": 2.0});
    assert_refused(
        &loaded,
        "fingers[0].mount.preload_n",
        "prescribes the normal load",
    );
}
