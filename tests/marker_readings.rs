//! Marker sensors read from solved grasps: the pad's surface displacement under a Hertz
//! contact against Boussinesq's closed form (Johnson eqs. 3.41, 3.42) converging under grid
//! refinement, the rigid shift of the stick zone under Cattaneo-Mindlin partial slip
//! (Johnson 7.2), the invariances (the model's own compliance at the element centres, a rigid
//! finger, a turned grid) and the refusals of sensors the read-out does not describe.

mod support;
use support::*;

use std::f64::consts::PI;

use grasp_model::closed_form::{cattaneo_stick_radius_m, mindlin_displacement_m, HertzSphere};
use grasp_model::{
    sensor_readings, solve, ContactState, GraspModel, GraspSolver, LoadedScene, MarkerReadings,
    Scene, SensorReadings, Solution, SolveOptions, SolveStatus, StepInputs,
};
use serde_json::{json, Value};

/// Solves `v` and reads its sensors.
fn read_all(v: &Value) -> (Solution, Vec<SensorReadings>) {
    let loaded = scene(v);
    let model = GraspModel::from_loaded(&loaded).expect("model");
    let solution = solve(&model).expect("solve");
    assert!(solution.status.has_forces(), "{:?}", solution.reason);
    let r = sensor_readings(&loaded.scene, &model, &solution).expect("readings");
    (solution, r)
}

/// The markers of the first finger of `v`, solved.
fn markers(v: &Value) -> MarkerReadings {
    read_all(v).1.remove(0).markers.expect("markers")
}

// ---- Hertz: a rigid sphere pressed on an elastic flat pad ----

const E_PAD: f64 = 210e9;
const NU_PAD: f64 = 0.3;
const R_SPHERE: f64 = 0.01;
const LOAD: f64 = 10.0;

/// The pad's Hertz contact (the sphere rigid: `1/E* = (1 - nu^2)/E` of the pad alone).
fn pad_hertz() -> HertzSphere {
    HertzSphere::new(LOAD, R_SPHERE, E_PAD / (1.0 - NU_PAD * NU_PAD))
}

/// A rigid sphere (the object, radius 10 mm, 10 N) on a flat frictionless steel pad (the
/// finger) of `n x n` elements over 2.45 a, with the markers `markers`.
fn sphere_on_pad(n: usize, markers: Value) -> Value {
    let side = 2.45 * pad_hertz().contact_radius_m;
    json!({
        "object": {"weight": LOAD, "center_of_mass": [0, 0, 0.02], "gravity": [0, 0, -1],
                   "material": "rigid"},
        "fingers": [{
            "name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
            "material": {"youngs_modulus": E_PAD, "poisson_ratio": NU_PAD},
            "tip_radius": null, "object_radius": R_SPHERE,
            "patch": {"size": [side, side], "grid": [n, n]},
            "friction": {"mu": 0.0}, "control": "held",
            "sensor": {"markers": markers}
        }],
        "model": "energy"
    })
}

/// Boussinesq's surface displacements of the pad under its Hertz pressure at radius `r`
/// (Johnson eqs. 3.41-3.42; `HertzSphere::surface_displacement_m`).
fn boussinesq_hertz(r: f64) -> (f64, f64) {
    pad_hertz().surface_displacement_m(r, E_PAD, NU_PAD)
}

/// The largest errors `(normal, radial)` of 17 markers on a line through the axis, turned by
/// 0.3 rad from `t1` (so off the element centres and the grid's axes), from `r = 0` to `2 a`
/// at a pitch of `a / 4`, against [`boussinesq_hertz`], over the central `u_z` (the
/// approach `a^2 / R`), on an `n x n` grid.
fn hertz_marker_errors(n: usize) -> (f64, f64) {
    let a = pad_hertz().contact_radius_m;
    let m = markers(&sphere_on_pad(
        n,
        json!({"count": [17, 1], "pitch_m": a / 4.0, "rotation_rad": 0.3,
               "offset_m": [2.0 * a * 0.3f64.cos(), 2.0 * a * 0.3f64.sin()]}),
    ));
    let scale = boussinesq_hertz(0.0).0;
    let (mut normal, mut radial) = (0.0f64, 0.0f64);
    for (p, u) in m.position_m.iter().zip(&m.displacement_m) {
        let r = p[0].hypot(p[1]);
        let (uz, ur) = boussinesq_hertz(r);
        let u_r = match r > 0.0 {
            true => (u[1] * p[0] + u[2] * p[1]) / r,
            false => u[1].hypot(u[2]),
        };
        normal = normal.max((u[0] - uz).abs() / scale);
        radial = radial.max((u_r - ur).abs() / scale);
    }
    (normal, radial)
}

#[test]
fn hertz_surface_displacement_converges_to_boussinesq() {
    // The error is the discretisation's: the element pressures uniform, the contact's edge
    // within an element. The read-out itself is exact (the rectangle integrals).
    let a = pad_hertz().contact_radius_m;
    assert!((boussinesq_hertz(0.0).0 - a * a / R_SPHERE).abs() < 1e-12 * a * a / R_SPHERE);
    let e21 = hertz_marker_errors(21);
    let e41 = hertz_marker_errors(41);
    let e81 = hertz_marker_errors(81);
    println!(
        "Hertz markers, largest error over the approach (normal, radial): 21x21 {:.3e} {:.3e}, \
         41x41 {:.3e} {:.3e}, 81x81 {:.3e} {:.3e}",
        e21.0, e21.1, e41.0, e41.1, e81.0, e81.1
    );
    assert!(e21.0 < 5e-3 && e21.1 < 5e-3, "{e21:?}");
    assert!(
        e41.0 <= 0.6 * e21.0 && e41.1 <= 0.6 * e21.1,
        "{e41:?} vs {e21:?}"
    );
    assert!(
        e81.0 <= 0.6 * e41.0 && e81.1 <= 0.6 * e41.1,
        "{e81:?} vs {e41:?}"
    );
}

// ---- Cattaneo-Mindlin: the stick zone moves rigidly ----

const MU: f64 = 0.3;
const GRID: usize = 21;

fn steel_hertz() -> HertzSphere {
    HertzSphere::new(LOAD, R_SPHERE, E_PAD / (2.0 * (1.0 - NU_PAD * NU_PAD)))
}

/// tests/cattaneo_mindlin.rs's scene: a steel sphere (the finger) under a flat steel object,
/// 10 N, mu 0.3, a tangential force `q` along `x` on the object at the contact point, 21 x 21
/// elements over 2.4 a; markers `markers`.
fn cattaneo(q: f64, markers: &Value) -> LoadedScene {
    let side = 2.4 * steel_hertz().contact_radius_m;
    let steel = json!({"youngs_modulus": E_PAD, "poisson_ratio": NU_PAD});
    scene(&json!({
        "object": {"weight": LOAD, "center_of_mass": [0, 0, 0.02], "gravity": [0, 0, -1],
                   "material": steel,
                   "external_forces": [{"force": [q, 0, 0], "at": [0, 0, 0]}]},
        "fingers": [{
            "name": "tip", "contact_point": [0, 0, 0], "normal": [0, 0, 1], "tangent": [1, 0, 0],
            "material": steel, "tip_radius": R_SPHERE,
            "patch": {"size": [side, side], "grid": [GRID, GRID]},
            "friction": {"mu": MU}, "sensor": {"markers": markers}
        }],
        "model": "coulomb"
    }))
}

/// The markers after P (Q = 0) and after P then `q`, the coulomb law stepping from P.
fn cattaneo_markers(q: f64, markers: &Value) -> (MarkerReadings, MarkerReadings) {
    let mut state: Option<ContactState> = None;
    let mut out = Vec::new();
    for load in [0.0, q] {
        let loaded = cattaneo(load, markers);
        let model = GraspModel::from_loaded(&loaded).expect("model");
        let st = state.get_or_insert_with(|| ContactState::new(&model));
        let options = SolveOptions {
            tolerance: 1e-12,
            ..SolveOptions::default()
        };
        let sol = GraspSolver::new(model.clone(), options)
            .solve_step(&StepInputs::loads(vec![]), st)
            .expect("step");
        assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
        let r = sensor_readings(&loaded.scene, &model, &sol).expect("readings");
        out.push(r.into_iter().next().unwrap().markers.unwrap());
    }
    let after = out.pop().unwrap();
    (out.pop().unwrap(), after)
}

/// Each marker's tangential displacement under Q, `[u_t1, u_t2]`: after Q less after P (the
/// pressure, and so its radial displacement, unchanged by Q between equal materials).
fn shear_displacements(p: &MarkerReadings, q: &MarkerReadings) -> Vec<[f64; 2]> {
    p.displacement_m
        .iter()
        .zip(&q.displacement_m)
        .map(|(a, b)| [b[1] - a[1], b[2] - a[2]])
        .collect()
}

#[test]
fn the_stick_zone_moves_rigidly_under_cattaneo_mindlin() {
    // Markers at the 21 x 21 element centres. In the stick zone the two surfaces move
    // together, and between equal bodies each carries half of the rigid shift (Johnson 7.2):
    // there the markers read one shift, to the solver's tolerance (1e-6 of it stated); the
    // stick radius they imply (the area-equivalent radius of the markers at the central
    // shift) is within one element of c = a (1 - Q/(mu P))^(1/3) (the stick set is a union
    // of whole elements); the shift is Mindlin's (Johnson eq. 7.42, half of it a body) within
    // 1 % (the tolerance; measured 0.08 to 0.2 % on this grid).
    let (h, a) = (steel_hertz(), steel_hertz().contact_radius_m);
    let el = 2.4 * a / GRID as f64;
    let m = json!({"count": [GRID, GRID], "pitch_m": el});
    for x in [0.2, 0.5, 0.8] {
        let q = x * MU * LOAD;
        let (p, after) = cattaneo_markers(q, &m);
        let u = shear_displacements(&p, &after);
        let centre = u[(GRID * GRID) / 2];
        let stuck: Vec<usize> = (0..u.len())
            .filter(|&k| (u[k][0] - centre[0]).hypot(u[k][1] - centre[1]) <= 1e-6 * centre[0])
            .collect();
        let c_markers = (stuck.len() as f64 * el * el / PI).sqrt();
        let c = cattaneo_stick_radius_m(a, q, MU, LOAD);
        let g = E_PAD / (2.0 * (1.0 + NU_PAD));
        let shift = mindlin_displacement_m(a, 2.0 * (2.0 - NU_PAD) / g, q, MU, LOAD) / 2.0;
        println!(
            "Q/(mu P) = {x}: {} stick markers, radius {:.4} a (c = {:.4} a, {:.2} elements off), \
             shift {:.5e} m (Mindlin per body {shift:.5e} m, {:.2} %), u_t2 {:.1e} m",
            stuck.len(),
            c_markers / a,
            c / a,
            (c_markers - c).abs() / el,
            centre[0],
            100.0 * (centre[0] - shift).abs() / shift,
            centre[1]
        );
        assert!(centre[0] > 0.0, "the object drags the pad along +t1");
        assert!(
            (c_markers - c).abs() <= el,
            "stick radius {c_markers} vs {c}"
        );
        assert!((centre[0] - shift).abs() <= 0.01 * shift);
        assert!(centre[1].abs() <= 1e-9 * centre[0]);
        // Outside the stick zone the markers lag: every one reads less than the shift.
        let inside: std::collections::HashSet<usize> = stuck.iter().copied().collect();
        let contact = h.contact_radius_m;
        for (k, uk) in u.iter().enumerate() {
            let pos = after.position_m[k];
            if !inside.contains(&k) && pos[0].hypot(pos[1]) < contact {
                assert!(uk[0] < centre[0] * (1.0 - 1e-6), "marker {k}: {uk:?}");
            }
        }
    }
}

#[test]
fn markers_between_the_element_centres_read_the_stick_shift_within_the_discretisation() {
    // Markers off the element centres (a 15 x 15 grid at 0.11 a, turned by 0.4 rad) inside
    // r < c - h: the read-out is exact for the element forces, which are uniform per element,
    // so the shift varies between the centres by the discretisation's error: within 1 % of it.
    let a = steel_hertz().contact_radius_m;
    let el = 2.4 * a / GRID as f64;
    let q = 0.5 * MU * LOAD;
    let c = cattaneo_stick_radius_m(a, q, MU, LOAD);
    let m = json!({"count": [15, 15], "pitch_m": 0.11 * a, "rotation_rad": 0.4});
    let (p, after) = cattaneo_markers(q, &m);
    let u = shear_displacements(&p, &after);
    let inner: Vec<[f64; 2]> = u
        .iter()
        .zip(&after.position_m)
        .filter(|(_, x)| x[0].hypot(x[1]) < c - el)
        .map(|(u, _)| *u)
        .collect();
    let mean = inner.iter().map(|u| u[0]).sum::<f64>() / inner.len() as f64;
    let spread = inner
        .iter()
        .map(|u| (u[0] - mean).abs().max(u[1].abs()))
        .fold(0.0, f64::max);
    println!(
        "{} markers inside c - h: shift {mean:.5e} m, largest departure {:.2e} of it",
        inner.len(),
        spread / mean
    );
    assert!(inner.len() >= 20);
    assert!(spread <= 0.01 * mean, "{spread} of {mean}");
}

// ---- Invariances ----

/// The Hertz example with an aluminium fingertip (so the finger's share of the compliance is
/// not the object's, and its normal/tangential coupling is not zero), friction 0.5 and a
/// push of [2, 1, 0] N through the contact point; the sensor `sensor`.
fn pushed_aluminium(sensor: Value) -> Value {
    let mut v = example_json("hertz_sphere_on_flat.json");
    v["fingers"][0]["material"] = json!({"youngs_modulus": 70e9, "poisson_ratio": 0.33});
    v["fingers"][0]["friction"] = json!({"mu": 0.5});
    v["fingers"][0]["sensor"] = sensor;
    v["object"]["external_forces"] = json!([{"force": [2.0, 1.0, 0.0], "at": [0.0, 0.0, 0.0]}]);
    v
}

#[test]
fn markers_at_the_element_centres_read_the_fingers_share_of_the_compliance() {
    // The finger's share of C x: the compliance of the same patch with the object rigid
    // (the model's own matrix), times the solved forces of the scene with the object
    // elastic. A marker reads [s_n, -s_1, -s_2] (module doc of marker_readings.rs): equal to
    // round-off (1e-12 of the largest; the two differ only in the offsets' round-off and the
    // matrix's symmetrisation).
    let h = 0.000212 / 21.0;
    let v = pushed_aluminium(json!({"markers": {"count": [21, 21], "pitch_m": h}}));
    let (solution, r) = read_all(&v);
    let m = r[0].markers.as_ref().expect("markers");
    let mut rigid_object = v.clone();
    rigid_object["object"]["material"] = json!("rigid");
    let model = GraspModel::from_loaded(&scene(&rigid_object)).expect("model");
    let c = model.fingers()[0]
        .compliance_matrix_m_per_n()
        .expect("a dense compliance");
    let els = &solution.fingers[0].elements;
    let n = els.len();
    let mut x = nalgebra::DVector::zeros(3 * n);
    for (k, e) in els.iter().enumerate() {
        x[k] = e.normal_force_n;
        x[n + k] = e.tangential_force_n[0];
        x[2 * n + k] = e.tangential_force_n[1];
    }
    let s = c.as_ref() * x;
    let largest = s.amax();
    let mut worst = 0.0f64;
    for k in 0..n {
        assert!((m.position_m[k][0] - els[k].local_m[0]).abs() < 1e-15);
        let want = [s[k], -s[n + k], -s[2 * n + k]];
        for (got, want) in m.displacement_m[k].iter().zip(want) {
            worst = worst.max((got - want).abs() / largest);
        }
    }
    println!("markers against C_f x: largest difference {worst:.2e} of {largest:.3e} m");
    assert!(worst < 1e-12, "{worst}");
    // The coupling is there: the pressure moves the surface radially, and the tangential
    // readings are not the shear's alone.
    assert!(s.rows(n, n).amax() > 1e-3 * largest);
}

#[test]
fn a_rigid_finger_reads_zero() {
    let mut v = pushed_aluminium(json!({"markers": {"count": [7, 7], "pitch_m": 20e-6}}));
    v["fingers"][0]["material"] = json!("rigid");
    let m = markers(&v);
    assert!(m.displacement_m.iter().flatten().all(|u| *u == 0.0));
    assert_eq!(m.displacement_m.len(), 49);
}

#[test]
fn turning_the_grid_by_a_quarter_permutes_the_readings() {
    // Turned by pi/2 about its centre, marker (i, j) stands where (n - 1 - j, i) stood: the
    // same reading (components along t1, t2, n, not the grid's sides) to round-off (the
    // positions differ by cos(pi/2) = 6e-17 of the pitch; 1e-10 of the largest stated).
    let grid = |turn: f64| {
        json!({"markers": {"count": [6, 6], "pitch_m": 25e-6, "rotation_rad": turn,
                           "offset_m": [8e-6, -5e-6]}})
    };
    let straight = markers(&pushed_aluminium(grid(0.0)));
    let turned = markers(&pushed_aluminium(grid(std::f64::consts::FRAC_PI_2)));
    let largest = straight
        .displacement_m
        .iter()
        .flatten()
        .fold(0.0f64, |m, u| m.max(u.abs()));
    for i in 0..6 {
        for j in 0..6 {
            let (a, b) = (
                turned.displacement_m[i * 6 + j],
                straight.displacement_m[(5 - j) * 6 + i],
            );
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-10 * largest,
                    "[{i}, {j}] {c}: {a:?} {b:?}"
                );
            }
        }
    }
    // And the readings are not symmetric under the turn by themselves.
    assert!((straight.displacement_m[0][1] - straight.displacement_m[5][1]).abs() > 1e-3 * largest);
}

#[test]
fn a_sensor_of_both_kinds_reads_each_as_alone() {
    let taxels = json!({"count": [5, 5], "pitch_m": 40e-6, "size_m": 40e-6, "depth_m": 20e-6});
    let marks = json!({"count": [4, 3], "pitch_m": 30e-6});
    let both = read_all(&pushed_aluminium(
        json!({"taxels": taxels, "markers": marks}),
    ))
    .1;
    let t = read_all(&pushed_aluminium(json!({ "taxels": taxels }))).1;
    let m = read_all(&pushed_aluminium(json!({ "markers": marks }))).1;
    assert_eq!(both[0].taxels, t[0].taxels);
    assert_eq!(both[0].markers, m[0].markers);
    assert!(t[0].markers.is_none() && m[0].taxels.is_none());
    // As JSON: the taxels' fields at the top as before, the markers under "markers".
    let j = serde_json::to_value(&both[0]).unwrap();
    assert_eq!(j["finger"], "tip");
    assert_eq!(j["force_n"].as_array().unwrap().len(), 25);
    assert_eq!(j["markers"]["displacement_m"].as_array().unwrap().len(), 12);
    let j = serde_json::to_value(&m[0]).unwrap();
    let keys: Vec<&String> = j.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["finger", "markers"]);
}

// ---- Refusals ----

fn good_markers() -> Value {
    json!({"count": [5, 5], "pitch_m": 40e-6})
}

fn with_markers(markers: Value) -> Value {
    pushed_aluminium(json!({ "markers": markers }))
}

#[test]
fn a_layered_or_viscoelastic_pad_is_refused_for_markers() {
    let mut v = with_markers(good_markers());
    v["fingers"][0]["material"]["layer_thickness_m"] = json!(1e-3);
    assert_refused(
        &v,
        "fingers[0].sensor",
        "markers need a half-space pad; fingers[0].material has a bonded layer",
    );
    let mut v = with_markers(good_markers());
    v["fingers"][0]["material"]["relaxation"] = json!({"long_term_modulus": 30e9, "time_s": 1.0});
    assert_refused(
        &v,
        "fingers[0].sensor",
        "markers need an elastic half-space pad; fingers[0].material is viscoelastic",
    );
}

#[test]
fn bad_marker_numbers_are_named_with_their_path() {
    let p = "fingers[0].sensor.markers";
    for (field, value, path, words) in [
        ("count", json!([5, 0]), format!("{p}.count[1]"), "is 0"),
        (
            "count",
            json!([257, 1]),
            format!("{p}.count[0]"),
            "outside [1, 256]",
        ),
        ("pitch_m", json!(0.0), format!("{p}.pitch_m"), "is 0"),
        (
            "rotation_rad",
            json!(-7.0),
            format!("{p}.rotation_rad"),
            "outside",
        ),
        (
            "offset_m",
            json!([0.0, 2e3]),
            format!("{p}.offset_m[1]"),
            "outside",
        ),
    ] {
        let mut m = good_markers();
        m[field] = value;
        assert_refused(&with_markers(m), &path, words);
    }
    // An unknown key, and a sensor of no kind, are named.
    let mut m = good_markers();
    m["size_m"] = json!(1e-5);
    assert!(problems(&with_markers(m))
        .iter()
        .any(|m| m.contains("fingers[0].sensor.markers") && m.contains("size_m")));
    assert_refused(
        &pushed_aluminium(json!({})),
        "fingers[0].sensor",
        "has no kind of sensor",
    );
}

#[test]
fn non_finite_marker_numbers_are_refused_without_a_panic() {
    let v = with_markers(good_markers());
    for field in ["pitch_m", "rotation_rad", "offset_m"] {
        for bad in [f64::NAN, f64::INFINITY] {
            let mut s = Scene::from_json_str(&v.to_string()).expect("scene");
            let sensor = s.fingers[0].sensor.as_mut().expect("sensor");
            let m = sensor.markers.as_mut().expect("markers");
            match field {
                "pitch_m" => m.pitch_m = bad,
                "rotation_rad" => m.rotation_rad = bad,
                _ => m.offset_m[0] = bad,
            }
            let text = s.validate().expect_err("refused").to_string();
            assert!(
                text.contains(&format!("fingers[0].sensor.markers.{field}")),
                "{field} {bad}: {text}"
            );
        }
    }
}

#[test]
fn a_marker_read_out_of_too_much_work_is_refused() {
    // 256 x 256 markers on a 101 x 101 patch: 6.7e8 evaluations, above 2e8.
    let mut v = with_markers(json!({"count": [256, 256], "pitch_m": 1e-6}));
    v["fingers"][0]["patch"]["grid"] = json!([101, 101]);
    assert_refused(&v, "fingers[0].sensor", "(markers x elements)");
}
