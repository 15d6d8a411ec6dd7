//! Springs several fingers share (`hands`, `servos`): two jaws on one servo against the closed
//! form of two Hertz contacts behind one spring, symmetric and pushed aside; a hand's base
//! carrying the weight (the object sags and turns with it, its contacts unchanged); a hand of
//! one finger as that finger's own mount; both solvers and both contact laws alike; and the
//! refusals of what cannot be built.

use grasp_model::closed_form::HertzSphere;
use grasp_model::{
    GraspModel, GraspSolver, LoadedScene, Material, ModelKind, Solution, SolveOptions, SolveStatus,
    SolverChoice, StepInputs,
};
use serde_json::{json, Value};

mod support;

/// Soft pad: E 2 MPa, nu 0.45 (a silicone fingertip).
const PAD_E_PA: f64 = 2e6;
const PAD_NU: f64 = 0.45;
/// Tip radius, m.
const TIP_R_M: f64 = 0.01;

fn solved_with(v: &Value, solver: SolverChoice) -> Solution {
    let scene = LoadedScene::from_json_str(&v.to_string()).expect("valid scene");
    let model = GraspModel::from_loaded(&scene).expect("model");
    let options = SolveOptions {
        solver,
        ..SolveOptions::default()
    };
    let mut solver = GraspSolver::new(model, options);
    let sol = solver
        .solve(&StepInputs::of_scene(solver.model()))
        .expect("solve");
    assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
    sol
}

fn solved(v: &Value) -> Solution {
    solved_with(v, SolverChoice::Native)
}

fn pad_e_star() -> f64 {
    let pad = Material::Elastic {
        youngs_modulus_pa: PAD_E_PA,
        poisson_ratio: PAD_NU,
    };
    pad.effective_modulus_pa(&Material::Rigid)
}

/// Hertz's approach `delta(F) = (9 F^2 / (16 R E*^2))^(1/3)` of a pad on the rigid box, m.
fn delta(load_n: f64) -> f64 {
    HertzSphere::new(load_n, TIP_R_M, pad_e_star()).approach_m
}

/// Hertz's load at approach `d`, `F = 4/3 E* sqrt(R) d^(3/2)` (0 apart), N.
fn hertz_load(d: f64) -> f64 {
    4.0 / 3.0 * pad_e_star() * TIP_R_M.sqrt() * d.max(0.0).powf(1.5)
}

/// A rigid box pinched along x by two spherical pads, both commanded `jaw_m` past first touch
/// and driven by one servo of stiffness `k` N/m; `push_n` along +x on the box. Patches span
/// `2.4 a` at `size_load_n`, `grid` elements a side, frictionless.
fn servo_pinch(k: f64, jaw_m: f64, push_n: f64, size_load_n: f64, grid: usize) -> Value {
    let side = 2.4 * HertzSphere::new(size_load_n, TIP_R_M, pad_e_star()).contact_radius_m;
    let jaw = |name: &str, x: f64, n: f64| {
        json!({"name": name, "contact_point": [x, 0, 0], "normal": [n, 0, 0],
               "material": {"youngs_modulus": PAD_E_PA, "poisson_ratio": PAD_NU},
               "tip_radius": TIP_R_M, "patch": {"size": [side, side], "grid": [grid, grid]},
               "friction": {"mu": 0.0}, "control": {"approach_m": jaw_m}})
    };
    json!({"object": {"weight": 0.0, "center_of_mass": [0, 0, 0], "gravity": [0, 0, -1],
                      "material": "rigid",
                      "external_forces": [{"force": [push_n, 0, 0], "at": [0, 0, 0]}]},
           "fingers": [jaw("left", -0.02, 1.0), jaw("right", 0.02, -1.0)],
           "servos": [{"name": "jaws", "fingers": ["left", "right"], "stiffness_n_per_m": k}]})
}

/// Two jaws on one servo squeezing alike: each jaw's contact compresses by their common travel
/// `q = delta(F)` (Hertz, Johnson 4.2), and the servo carries both, `2 F = k (x - q)`. The jaws are placed where that root is 0.3 N, for k from 1e2 to
/// 1e7 N/m; the squeeze must be the root within 0.5 %, the Hertz discretisation error at 41 x 41
/// elements over 2.4 a (the same grid as `tests/finger_mounts.rs`, which measures it). The
/// servo reports the sum of its jaws' forces and their travel short of the command,
/// `-2 F / k`, to round-off.
#[test]
fn two_jaws_on_one_servo_meet_the_closed_form() {
    let f_root = 0.3;
    for k in [1e2, 1e3, 1e4, 1e5, 1e6, 1e7] {
        let jaw = 2.0 * f_root / k + delta(f_root);
        let sol = solved(&servo_pinch(k, jaw, 0.0, f_root, 41));
        let (left, right) = (sol.fingers[0].normal_force_n, sol.fingers[1].normal_force_n);
        let error = (left - f_root).abs() / f_root;
        let servo = &sol.servos[0];
        eprintln!(
            "k {k:.0e} N/m, jaws at {jaw:.4e} m: F {left:.6} N (error {error:.2e}), servo {:.6} N, travel {:.4e} m",
            servo.force_n, servo.travel_m
        );
        assert!(error < 5e-3, "k {k}: squeeze error {error}");
        assert!(
            (left - right).abs() < 1e-9 * f_root,
            "k {k}: {left} {right}"
        );
        assert!((servo.force_n - left - right).abs() < 1e-9 * f_root);
        assert!(
            (servo.travel_m * k / servo.force_n + 1.0).abs() < 1e-9,
            "k {k}: travel {} against -F/k",
            servo.travel_m
        );
        assert!(sol.hands.is_empty());
    }
}

/// The servo's jaws move together, so a push `P` along the pinch shifts the box by `s` and
/// the jaws by a common travel `q`: `F_l = H(q - s)`, `F_r = H(q + s)` with Hertz's `H`,
/// `F_r - F_l = P` (the box's equilibrium) and `F_l + F_r = k (x - q)` (the servo's). Solved
/// here by nested bisection; the model must meet both forces within 0.5 % (the Hertz
/// discretisation error as above) and the box's shift within 1 % (an approach, which the
/// grid resolves to about twice the force's error).
#[test]
fn a_servos_jaws_pushed_aside_share_the_push_as_the_closed_form_says() {
    let (k, push) = (1e3, 0.1);
    let jaw = 1e-3;
    let shift = |q: f64| bisect(-q, q, |s| hertz_load(q + s) - hertz_load(q - s) - push);
    let q = bisect(0.0, jaw, |q| {
        let s = shift(q);
        hertz_load(q - s) + hertz_load(q + s) - k * (jaw - q)
    });
    let s = shift(q);
    let (fl, fr) = (hertz_load(q - s), hertz_load(q + s));
    let sol = solved(&servo_pinch(k, jaw, push, fr, 41));
    let (ml, mr) = (sol.fingers[0].normal_force_n, sol.fingers[1].normal_force_n);
    let moved = sol.rigid_displacement.expect("loaded").translation_m[0];
    eprintln!(
        "closed form: F_l {fl:.6} N, F_r {fr:.6} N, shift {s:.4e} m; model: {ml:.6}, {mr:.6}, {moved:.4e}"
    );
    assert!((ml - fl).abs() < 5e-3 * fl, "left {ml} vs {fl}");
    assert!((mr - fr).abs() < 5e-3 * fr, "right {mr} vs {fr}");
    assert!((moved - s).abs() < 1e-2 * s.abs(), "shift {moved} vs {s}");
    assert!((sol.servos[0].travel_m + (ml + mr) / k).abs() < 1e-9 * jaw);
}

/// A jaw opened short of first touch is withdrawn, in a hand-off as in a solve: two rigid
/// jaws pinch a weightless box, the left one pressed in 0.3 mm, the right one opened to
/// -0.1 mm, so the contacts share an interference of 0.2 mm, 0.1 mm each (the box settles
/// midway), and each carries Hertz's `4/3 E* sqrt(R) (0.1 mm)^1.5`, within the 0.5 % of the
/// 41 x 41 grid (as above). The scene's command and a schedule's approach phase must both be
/// that answer; a hand-off that read an opened jaw as held at first touch (0 mm) would press
/// 0.15 mm into each, 84 % more force.
#[test]
fn a_jaw_opened_short_of_first_touch_is_withdrawn_in_a_hand_off() {
    let (left_m, right_m) = (3e-4, -1e-4);
    let expected = hertz_load(0.5 * (left_m + right_m));
    let mut v = servo_pinch(1e3, left_m, 0.0, expected, 41);
    v.as_object_mut().unwrap().remove("servos");
    v["fingers"][1]["control"] = json!({"approach_m": right_m});
    let scene = LoadedScene::from_json_str(&v.to_string()).expect("valid scene");
    let names = scene.finger_names();
    let ramp = json!({"time": {"times": [0.0, 1.0]}, "fingers": {
        "right": [{"approach": {"keyframes": [[0.0, right_m], [1.0, right_m]]}}]}});
    let held = json!({"time": {"times": [0.0, 1.0]}, "fingers": {}});
    for schedule in [held, ramp] {
        let schedule = grasp_transfer::Schedule::from_json_str(
            &schedule.to_string(),
            &names,
            std::path::Path::new("."),
        )
        .expect("schedule");
        let options = grasp_transfer::TransferOptions::default();
        for r in grasp_transfer::Stepper::new(&scene, &schedule, options) {
            let r = r.expect("step");
            let f = r.solution.finger("right").expect("right jaw");
            eprintln!(
                "t {} s: right jaw {:.6} N at approach {:.3e} m; Hertz {expected:.6} N",
                r.time_s, f.normal_force_n, f.approach_m
            );
            assert!(
                (f.normal_force_n - expected).abs() < 5e-3 * expected,
                "{}",
                r.time_s
            );
        }
    }
    let solved = solved(&v);
    let f = solved.finger("right").unwrap().normal_force_n;
    assert!((f - expected).abs() < 5e-3 * expected, "solve: {f}");
}

/// The root of an increasing `g` on `[lo, hi]` to 1e-15 of the interval.
fn bisect(mut lo: f64, mut hi: f64, g: impl Fn(f64) -> f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A rigid box of 1 N held between two flat pads (E 200 MPa, mu 1; `a` squeezes 10 N, `b` is
/// held), both on one hand (`hand`: its JSON, or none).
fn held_box(hand: Option<Value>, model: &str) -> Value {
    let pad = |name: &str, x: f64, n: f64| {
        json!({"name": name, "contact_point": [x, 0, 0], "normal": [n, 0, 0],
               "material": {"youngs_modulus": 2e8, "poisson_ratio": 0.45},
               "patch": {"size": [0.008, 0.008], "grid": [9, 9]}, "friction": {"mu": 1.0}})
    };
    let mut a = pad("a", -0.01, 1.0);
    a["control"] = json!({"normal_load": 10.0});
    let mut scene = json!({"object": {"weight": 1.0, "center_of_mass": [0, 0, 0],
                                      "gravity": [0, 0, -1], "material": "rigid"},
                           "fingers": [a, pad("b", 0.01, -1.0)], "model": model});
    if let Some(h) = hand {
        scene["hands"] = json!([h]);
    }
    scene
}

/// The largest difference of any element force between two solutions of one scene, N.
fn element_force_difference_n(a: &Solution, b: &Solution) -> f64 {
    let mut worst: f64 = 0.0;
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        for (ea, eb) in fa.elements.iter().zip(&fb.elements) {
            worst = worst.max((ea.normal_force_n - eb.normal_force_n).abs());
            for c in 0..2 {
                worst = worst.max((ea.tangential_force_n[c] - eb.tangential_force_n[c]).abs());
            }
        }
    }
    worst
}

/// A hand whose base carries both pads moves them, and the object with them, rigidly: its
/// load is the weight `W` at the centre of mass, so it moves by `-S W` (here `W / k_t` down and
/// `(c - h) x W / k_r` about its origin `h`), the object's displacement is the rigid hand's
/// plus that motion (rotation about `h`), and no element force changes (the contacts see no
/// relative motion: an invariance of the linear model). Tolerances: the hand's motion to
/// 1e-9 of itself (the solve's equilibrium residual), element forces to 1e-7 of the 10 N
/// squeeze and the object's extra motion to 1e-6 of the hand's (each solve at 1e-10, the
/// program's scaled tolerance), for both contact laws, and in a planar scene (the x-z plane:
/// the base moves in it and turns about y only).
#[test]
fn a_compliant_hand_carries_the_object_with_it_and_changes_no_contact_force() {
    let (kt, kr, origin) = (500.0, 20.0, [0.03, 0.0, 0.05]);
    let hand = json!({"name": "arm", "fingers": ["a", "b"], "origin_m": origin,
                      "translational_n_per_m": kt, "rotational_nm_per_rad": kr});
    let planar = |mut v: Value| {
        v["planar"] = json!({"normal": [0, 1, 0]});
        v
    };
    for (model, plane) in [("energy", false), ("coulomb", false), ("energy", true)] {
        let scene = |hand: Option<Value>| match plane {
            true => planar(held_box(hand, model)),
            false => held_box(hand, model),
        };
        let model = if plane { "planar energy" } else { model };
        let rigid = solved(&scene(None));
        let soft = solved(&scene(Some(hand.clone())));
        // The load on the object from the fingers is the weight's opposite: 1 N up at the
        // centre of mass; its moment about the origin is (c - h) x (0, 0, 1).
        let lever = [-origin[0], -origin[1], -origin[2]];
        let moment = [lever[1], -lever[0], 0.0];
        let expected_translation = [0.0, 0.0, -1.0 / kt];
        let expected_rotation = moment.map(|m| -m / kr);
        let h = &soft.hands[0];
        eprintln!(
            "{model}: hand force {:?} N, moment {:?} N m, moved {:?} m, turned {:?} rad",
            h.force_n, h.moment_nm, h.translation_m, h.rotation_rad
        );
        for c in 0..3 {
            assert!((h.translation_m[c] - expected_translation[c]).abs() < 1e-9 / kt);
            assert!((h.rotation_rad[c] - expected_rotation[c]).abs() < 1e-9 / kr);
        }
        let difference = element_force_difference_n(&rigid, &soft);
        eprintln!("{model}: largest element force change {difference:.2e} N");
        assert!(difference < 1e-7 * 10.0, "{model}: {difference}");
        // The object moves with the hand: its centre of mass by t + phi x (c - h).
        let (r, s) = (
            rigid.rigid_displacement.unwrap(),
            soft.rigid_displacement.unwrap(),
        );
        let phi = h.rotation_rad;
        let carried = [
            h.translation_m[0] + phi[1] * lever[2] - phi[2] * lever[1],
            h.translation_m[1] + phi[2] * lever[0] - phi[0] * lever[2],
            h.translation_m[2] + phi[0] * lever[1] - phi[1] * lever[0],
        ];
        let size = 1.0 / kt;
        for c in 0..3 {
            let extra = s.translation_m[c] - r.translation_m[c];
            assert!(
                (extra - carried[c]).abs() < 1e-6 * size,
                "{model}: centre of mass [{c}] moved {extra} more, the hand carries {}",
                carried[c]
            );
            let turned = s.rotation_rad[c] - r.rotation_rad[c];
            assert!(
                (turned - phi[c]).abs() < 1e-6 * size / 0.05,
                "{model}: {turned}"
            );
        }
    }
}

/// Three pads hang a rigid box (as in `tests/finger_mounts.rs`); pad `b` is either on its own
/// mount of stiffness `k` along its normal and tangents and `k_r` about every axis, or alone on
/// a hand of translational stiffness `k` and rotational `k_r` whose origin is its contact point
/// (both alike in every direction, so the contact frame and the world's agree): the same
/// spring written twice, so the two
/// solves must agree (element forces to 1e-7 of the 10 N squeeze, the core's and the hand's
/// motion to 1e-6 of it: the solves' tolerance), with either solver (Clarabel to 1e-5, its
/// interior-point accuracy).
#[test]
fn a_hand_of_one_finger_is_that_fingers_mount() {
    let (k, k_r) = (30.0, 2.0);
    let scene = |hand: bool| {
        let pad = |name: &str, at: [f64; 3], n: f64| {
            json!({"name": name, "contact_point": at, "normal": [n, 0, 0],
                   "material": {"youngs_modulus": 2e8, "poisson_ratio": 0.45},
                   "patch": {"size": [0.008, 0.008], "grid": [9, 9]}, "friction": {"mu": 1.0}})
        };
        let mut a = pad("a", [-0.01, 0.0, 0.0], 1.0);
        a["control"] = json!({"normal_load": 10.0});
        let mut b = pad("b", [0.01, 0.01, 0.0], -1.0);
        let mut scene = json!({"object": {"weight": 1.0, "center_of_mass": [0, 0, 0],
                                          "gravity": [0, 0, -1], "material": "rigid"},
                               "fingers": [a, pad("c", [0.01, -0.01, 0.0], -1.0)]});
        if hand {
            scene["hands"] = json!([{"name": "wrist", "fingers": ["b"],
                                     "origin_m": [0.01, 0.01, 0.0],
                                     "translational_n_per_m": k,
                                     "rotational_nm_per_rad": k_r}]);
        } else {
            b["mount"] = json!({"normal_n_per_m": k, "tangential_n_per_m": k,
                                "rotational_nm_per_rad": k_r});
        }
        scene["fingers"].as_array_mut().unwrap().insert(1, b);
        scene
    };
    let mounted = solved(&scene(false));
    let core = mounted.fingers[1]
        .mount_displacement
        .expect("mounted")
        .translation_m;
    for solver in [SolverChoice::Native, SolverChoice::Clarabel] {
        let on_hand = solved_with(&scene(true), solver);
        let tolerance = match solver {
            SolverChoice::Clarabel => 1e-5,
            _ => 1e-7,
        };
        let difference = element_force_difference_n(&mounted, &on_hand);
        let moved = on_hand.hands[0].translation_m;
        eprintln!(
            "{solver}: element forces differ by {difference:.2e} N; core {core:?} m, hand {moved:?} m"
        );
        assert!(difference < tolerance * 10.0, "{solver}: {difference}");
        let size = core.iter().fold(0.0_f64, |a, c| a.max(c.abs()));
        for c in 0..3 {
            assert!(
                (moved[c] - core[c]).abs() < tolerance * 10.0 * size,
                "{solver}: {moved:?} vs {core:?}"
            );
        }
    }
}

/// What a shared spring cannot be is refused before anything is built, naming the field and
/// the fix: an unknown finger, a finger on two hands, a servo's jaw whose load is prescribed,
/// a servo of one jaw, a hand with no stiffness.
#[test]
fn shared_springs_that_cannot_be_built_are_refused_by_field() {
    let base = held_box(None, "energy");
    let cases = [
        (
            json!({"hands": [{"name": "h", "fingers": ["a", "z"], "origin_m": [0, 0, 0],
                              "translational_n_per_m": 100.0}]}),
            "hands[0].fingers[1]",
            "not a finger of the scene",
        ),
        (
            json!({"hands": [{"name": "h", "fingers": ["a"], "origin_m": [0, 0, 0],
                              "translational_n_per_m": 100.0},
                             {"name": "g", "fingers": ["a"], "origin_m": [0, 0, 0],
                              "translational_n_per_m": 100.0}]}),
            "hands[1].fingers[0]",
            "at most one hand",
        ),
        (
            json!({"servos": [{"name": "s", "fingers": ["a", "b"], "stiffness_n_per_m": 100.0}]}),
            "servos[0].fingers[0]",
            "approach_m",
        ),
        (
            json!({"servos": [{"name": "s", "fingers": ["b"], "stiffness_n_per_m": 100.0}]}),
            "servos[0].fingers",
            "at least 2",
        ),
        (
            json!({"hands": [{"name": "h", "fingers": ["a"], "origin_m": [0, 0, 0]}]}),
            "hands[0]",
            "translational_n_per_m",
        ),
    ];
    for (extra, path, fix) in cases {
        let mut scene = base.clone();
        for (key, value) in extra.as_object().unwrap() {
            scene[key] = value.clone();
        }
        let err = LoadedScene::from_json_str(&scene.to_string())
            .err()
            .unwrap_or_else(|| panic!("{path}: accepted"))
            .to_string();
        eprintln!("{err}");
        assert!(err.contains(path) && err.contains(fix), "{path}: {err}");
    }
}

/// A scene without hands or servos reads, writes and solves as before: the solution has no
/// `hands` or `servos` keys and the model kind is unchanged.
#[test]
fn a_scene_without_shared_springs_writes_no_spring_keys() {
    let sol = solved(&held_box(None, "energy"));
    let text = serde_json::to_string(&sol).unwrap();
    assert!(!text.contains("\"hands\"") && !text.contains("\"servos\""));
    let scene = LoadedScene::from_json_str(&held_box(None, "energy").to_string()).unwrap();
    assert_eq!(scene.scene.model, ModelKind::Energy);
}

/// The plate hand-off between two compliant arms (`examples/plate_transfer_gripper.*`): the
/// releasing jaws on one servo on a giving arm, the receivers on a receiving arm. Checked at
/// every step:
/// - the two arms carry the weight between them (their vertical loads sum to `W`, 1e-9) and
///   each moves by its own spring's law, `-F_z / k` (1e-12 of a millimetre: the readout's
///   arithmetic);
/// - the servo's travel is its own law, `-F_sum / k` (1e-9 of the command's scale, 1 mm);
/// - its jaws let go exactly as their command passes first touch (13 s): each carries more
///   than 1e-3 N before and less than 1e-9 N from then on (the plate is held symmetrically,
///   so contact is lost at the jaws' first-touch position);
/// - at the end the arm carries the weight alone: its base sits `W / k_arm` lower (1e-9 of
///   that, the solve's equilibrium residual), and the plate sags by that plus its soft pads'
///   own deflection under the weight (so by more; measured 0.17 mm more, the coulomb path's
///   slip memory leaving no exact twin to compare it with);
/// - warm starts survive: at most 1.5 Newton iterations a step on average.
#[test]
fn a_hand_off_between_two_compliant_arms() {
    let (loaded, schedule) = support::transfer_example("plate_transfer_gripper");
    let scene = support::example_json("plate_transfer_gripper.json");
    let options = grasp_transfer::TransferOptions::default();
    let records: Vec<_> = grasp_transfer::Stepper::new(&loaded, &schedule, options)
        .map(|r| r.unwrap())
        .collect();
    let k_servo = scene["servos"][0]["stiffness_n_per_m"].as_f64().unwrap();
    let stiffness = |name: &str| {
        let hands = scene["hands"].as_array().unwrap();
        let h = hands.iter().find(|h| h["name"] == name).unwrap();
        h["translational_n_per_m"].as_f64().unwrap()
    };
    let (k_arm, k_giver) = (stiffness("arm"), stiffness("giver"));
    let weight = scene["object"]["weight"].as_f64().unwrap();
    let hand = |s: &Solution, name: &str| s.hands.iter().find(|h| h.name == name).cloned();
    let mut iterations = 0;
    for r in &records {
        let s = &r.solution;
        assert!(s.status.has_forces(), "t {}: {:?}", r.time_s, s.reason);
        iterations += s.solver.iterations;
        let (arm, giver) = (hand(s, "arm").unwrap(), hand(s, "giver").unwrap());
        let carried = arm.force_n[2] + giver.force_n[2];
        assert!(
            (carried - weight).abs() < 1e-9 * weight,
            "t {}: {carried}",
            r.time_s
        );
        for (h, k) in [(&arm, k_arm), (&giver, k_giver)] {
            let law = h.translation_m[2] + h.force_n[2] / k;
            assert!(law.abs() < 1e-15, "t {}: {}", r.time_s, h.name);
        }
        let jaws: Vec<_> = ["f1", "f2"].map(|n| s.finger(n).expect("jaw")).into();
        let command = jaws[0].approach_m;
        let servo = &s.servos[0];
        let sum = jaws[0].normal_force_n + jaws[1].normal_force_n;
        assert!((servo.force_n - sum).abs() < 1e-9 * weight);
        assert!(
            (servo.travel_m + sum / k_servo).abs() < 1e-12,
            "t {}",
            r.time_s
        );
        for jaw in &jaws {
            match command > 1e-9 {
                true => assert!(jaw.normal_force_n > 1e-3, "t {}: {:?}", r.time_s, jaw.name),
                false => assert!(jaw.normal_force_n.abs() < 1e-9, "t {}", r.time_s),
            }
        }
    }
    let end = &records.last().unwrap().solution;
    let arm = weight / k_arm;
    let base = hand(end, "arm").unwrap().translation_m[2];
    let giver = hand(end, "giver").unwrap().translation_m[2];
    assert!(
        giver.abs() < 1e-9 * arm,
        "the giving arm sheds the weight: {giver} m"
    );
    let sag = -end.rigid_displacement.unwrap().translation_m[2];
    let per_step = iterations as f64 / records.len() as f64;
    eprintln!(
        "arm base {base:.6e} m (W / k {arm:.6e} m), plate sag {sag:.6e} m; {per_step:.2} iterations a step"
    );
    assert!((base + arm).abs() < 1e-9 * arm, "base {base}");
    assert!(sag > arm, "sag {sag}");
    assert!(per_step <= 1.5, "{per_step} iterations a step");
}

/// The gripper hand-off's outputs carry the hand and the servo at every step: the MCAP's
/// `/grasp/fingers` messages (`hands`, `servos`), the CSV's columns and the recording's
/// `world/hands/arm` arrow and `plots/core/<name>` curves, each equal to the step's solution
/// (to the text's round trip of a float, exact); the `rerun` CLI accepts both files.
#[test]
fn the_outputs_carry_the_hand_and_the_servo() {
    use grasp_transfer::{CsvSink, McapSink, RerunSink, Sink, TransferOptions};
    let (scene, schedule) = support::transfer_example("plate_transfer_gripper");
    let dir = std::env::temp_dir().join(format!("grasp-springs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (rrd, csv, mcap) = (dir.join("g.rrd"), dir.join("g.csv"), dir.join("g.mcap"));
    let mut r = RerunSink::create(&rrd).unwrap();
    let mut c = CsvSink::create(&csv).unwrap();
    let mut m = McapSink::create(&mcap).unwrap();
    let mut sinks: [&mut dyn Sink; 3] = [&mut r, &mut c, &mut m];
    let (records, _) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut sinks)
            .unwrap();
    let bytes = std::fs::read(&mcap).unwrap();
    let mut seen = 0;
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        if msg.channel.topic != grasp_transfer::FINGERS_TOPIC {
            continue;
        }
        let v: Value = serde_json::from_slice(&msg.data).unwrap();
        let s = &records[seen].solution;
        for (k, h) in s.hands.iter().enumerate() {
            assert_eq!(v["hands"][k]["name"], h.name.as_str());
            let z = v["hands"][k]["translation_m"][2].as_f64().unwrap();
            assert_eq!(z, h.translation_m[2], "step {seen}");
        }
        let travel = v["servos"][0]["travel_m"].as_f64().unwrap();
        assert_eq!(travel, s.servos[0].travel_m, "step {seen}");
        seen += 1;
    }
    assert_eq!(seen, records.len());
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (z, travel) = (column("arm_translation_z_m"), column("gripper_travel_m"));
    for (line, rec) in lines.zip(&records) {
        let cells: Vec<&str> = line.split(',').collect();
        let s = &rec.solution;
        let arm = s.hands.iter().find(|h| h.name == "arm").unwrap();
        assert_eq!(cells[z].parse::<f64>().unwrap(), arm.translation_m[2]);
        assert_eq!(cells[travel].parse::<f64>().unwrap(), s.servos[0].travel_m);
    }
    let Some(cli) = support::rerun_cli() else {
        return;
    };
    let run = |args: &[&str], file: &std::path::Path| support::rerun_on(&cli, args, file);
    run(&["rrd", "verify"], &rrd);
    let printed = run(&["rrd", "print"], &rrd);
    for path in ["world/hands/arm", "plots/core/arm", "plots/core/gripper"] {
        assert!(printed.contains(path), "{path} not in\n{printed}");
    }
    run(&["mcap", "check"], &mcap);
}

/// A schedule ramps a hand's pose (`hands.<name>.keyframes`): the box held by the hand's two
/// pads is carried along rigidly, 2 mm up and 10 mrad about x over ten steps. At every step the
/// object's displacement is the unmoved grasp's plus the commanded motion (its centre of mass
/// by `d + phi x (c - h)`, its rotation by `phi`) within 1e-6 of the motion (each solve at
/// 1e-10), the element forces do not change by more than 1e-7 of the 10 N squeeze (the
/// contacts see no relative motion), and the hand's own spring still carries the weight.
/// A schedule naming a hand the scene lacks, turning a hand out of a planar scene's plane or
/// loading a servo's jaw is refused at its first step, naming the field and the fix.
#[test]
fn a_scheduled_hand_pose_carries_the_grasp_along() {
    let hand = json!({"name": "arm", "fingers": ["a", "b"], "origin_m": [0.0, 0.0, 0.05],
                      "translational_n_per_m": 500.0, "rotational_nm_per_rad": 20.0});
    let scene_json = held_box(Some(hand), "coulomb");
    let loaded = LoadedScene::from_json_str(&scene_json.to_string()).unwrap();
    let schedule = |name: &str| {
        let text = json!({"time": {"start": 0.0, "end": 1.0, "step": 0.1},
                          "fingers": {},
                          "hands": {name: {"keyframes": [
                              [0.0, {}],
                              [1.0, {"translation_m": [0.0, 0.0, 0.002],
                                     "rotation_rad": [0.01, 0.0, 0.0]}]]}}});
        grasp_transfer::Schedule::from_json_str(
            &text.to_string(),
            &loaded.finger_names(),
            ".".as_ref(),
        )
        .unwrap()
    };
    let lifted = schedule("arm");
    let options = grasp_transfer::TransferOptions::default();
    let records: Vec<_> = grasp_transfer::Stepper::new(&loaded, &lifted, options)
        .map(|r| r.unwrap())
        .collect();
    let still = solved(&scene_json);
    let origin = [0.0, 0.0, 0.05];
    for r in &records {
        let s = &r.solution;
        let f = r.time_s;
        let (d, phi) = ([0.0, 0.0, 0.002 * f], [0.01 * f, 0.0, 0.0]);
        let lever = [-origin[0], -origin[1], -origin[2]];
        let carried = [
            d[0] + phi[1] * lever[2] - phi[2] * lever[1],
            d[1] + phi[2] * lever[0] - phi[0] * lever[2],
            d[2] + phi[0] * lever[1] - phi[1] * lever[0],
        ];
        let (a, b) = (
            s.rigid_displacement.unwrap(),
            still.rigid_displacement.unwrap(),
        );
        for c in 0..3 {
            let moved = a.translation_m[c] - b.translation_m[c];
            assert!(
                (moved - carried[c]).abs() < 1e-6 * 0.002,
                "t {f}: [{c}] {moved} vs {}",
                carried[c]
            );
            let turned = a.rotation_rad[c] - b.rotation_rad[c];
            assert!(
                (turned - phi[c]).abs() < 1e-6 * 0.01,
                "t {f}: rotation [{c}] {turned}"
            );
        }
        let difference = element_force_difference_n(s, &still);
        assert!(difference < 1e-7 * 10.0, "t {f}: {difference} N");
        assert!((s.hands[0].translation_m[2] + 1.0 / 500.0).abs() < 1e-9 / 500.0);
    }
    eprintln!("{} steps carried to 2 mm and 10 mrad", records.len());
    let wrong = schedule("wrist");
    let Some(Err(first)) = grasp_transfer::Stepper::new(&loaded, &wrong, options).next() else {
        panic!("an unknown hand is refused");
    };
    let first = first.to_string();
    assert!(
        first.contains("hands.wrist") && first.contains("arm"),
        "{first}"
    );
    // Moved out of a planar scene's plane (the x-z plane: a turn about x tilts it).
    let mut flat = scene_json.clone();
    flat["planar"] = json!({"normal": [0, 1, 0]});
    let flat = LoadedScene::from_json_str(&flat.to_string()).unwrap();
    let Some(Err(tilted)) = grasp_transfer::Stepper::new(&flat, &lifted, options).next() else {
        panic!("a hand turned out of the plane is refused");
    };
    let tilted = tilted.to_string();
    eprintln!("{tilted}");
    assert!(
        tilted.contains("hands.arm.keyframes[1]") && tilted.contains("plane"),
        "{tilted}"
    );
    // A load phase on a servo's jaw.
    let pinch = servo_pinch(1e3, 1e-3, 0.0, 0.3, 9);
    let pinch = LoadedScene::from_json_str(&pinch.to_string()).unwrap();
    let text = json!({"time": {"start": 0.0, "end": 1.0, "step": 0.5},
                      "fingers": {"left": [{"ramp": {"keyframes": [[0.0, 0.3], [1.0, 0.0]]}}]}});
    let loads = grasp_transfer::Schedule::from_json_str(
        &text.to_string(),
        &pinch.finger_names(),
        ".".as_ref(),
    )
    .unwrap();
    let Some(Err(loaded)) = grasp_transfer::Stepper::new(&pinch, &loads, options).next() else {
        panic!("a load on a servo's jaw is refused");
    };
    let loaded = loaded.to_string();
    eprintln!("{loaded}");
    assert!(
        loaded.contains("fingers.left") && loaded.contains("approach"),
        "{loaded}"
    );
}

/// A viscoelastic hold on a moving hand (`examples/plate_hold_viscoelastic.*`, both pads on
/// one hand of 5,000 N/m carried 1 mm along x over the first 10 s): the hand moves the pads
/// and the plate together, so every element's reported history displacement equals the
/// unmoved run's (to 1e-9 of its largest: the two solves' round-off), and is not the hand's
/// commanded motion (which a history read off the displacement offsets would include).
#[test]
fn a_viscoelastic_history_on_a_moving_hand_is_the_pads_own() {
    let mut v = support::example_json("plate_hold_viscoelastic.json");
    v["hands"] = json!([{"name": "arm", "fingers": ["f1", "f2"], "origin_m": [0.0, 0.0, 0.0],
                         "translational_n_per_m": 5000.0}]);
    let loaded = LoadedScene::from_json_str(&v.to_string()).unwrap();
    let text = std::fs::read_to_string(support::example_path(
        "plate_hold_viscoelastic.schedule.json",
    ))
    .unwrap();
    let run = |text: &str| -> Vec<Solution> {
        let schedule =
            grasp_transfer::Schedule::from_json_str(text, &loaded.finger_names(), ".".as_ref())
                .unwrap();
        let options = grasp_transfer::TransferOptions::default();
        grasp_transfer::Stepper::new(&loaded, &schedule, options)
            .map(|r| r.unwrap().solution)
            .take(25)
            .collect()
    };
    let still = run(&text);
    let mut moving: Value = serde_json::from_str(&text).unwrap();
    moving["hands"] = json!({"arm": {"keyframes": [[0.0, {}],
                                                    [10.0, {"translation_m": [0.001, 0.0, 0.0]}]]}});
    let moved = run(&moving.to_string());
    let history = |s: &Solution| -> Vec<f64> {
        s.fingers
            .iter()
            .flat_map(|f| f.elements.iter())
            .flat_map(|e| e.viscous_displacement_m.expect("a viscoelastic pad"))
            .collect()
    };
    let mut largest: f64 = 0.0;
    for (a, b) in still.iter().zip(&moved) {
        let (ha, hb) = (history(a), history(b));
        let size = ha.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let worst = ha
            .iter()
            .zip(&hb)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            worst <= 1e-9 * size,
            "history differs by {worst} m of {size} m"
        );
        largest = largest.max(size);
    }
    eprintln!(
        "{} steps, histories up to {largest:.3e} m alike",
        still.len()
    );
    assert!(largest > 0.0);
}

/// On fine patches (the FFT compliance, 64 x 64 elements a jaw) a servo's dense block joins
/// the projected conjugate-gradient step: two jaws squeezing alike on one servo of `k` are the
/// same as each jaw on its own mount of `k / 2` (both meet `F = k/2 (x - delta(F))`), so every
/// element force agrees within 1e-8 of the squeeze (two solves at 1e-10, the second's path
/// entirely different), and the servo's solve takes at most twice the mounts' conjugate-gradient
/// iterations (its block's diagonal preconditioner; measured 49 against 38 at 128 x 128).
#[test]
fn a_servo_on_fine_patches_solves_as_its_jaws_own_mounts() {
    let (k, jaw) = (1e3, 3e-4);
    let servo = servo_pinch(k, jaw, 0.0, 0.15, 64);
    let mut mounts = servo.clone();
    mounts.as_object_mut().unwrap().remove("servos");
    for f in mounts["fingers"].as_array_mut().unwrap() {
        f["mount"] = json!({"normal_n_per_m": k / 2.0});
    }
    let (a, b) = (solved(&servo), solved(&mounts));
    assert_eq!(a.solver.compliance, b.solver.compliance);
    let squeeze = a.fingers[0].normal_force_n;
    let difference = element_force_difference_n(&a, &b);
    eprintln!(
        "squeeze {squeeze:.6} N; element forces differ by {difference:.2e} N; CG {} against {}",
        a.solver.inner_iterations, b.solver.inner_iterations
    );
    assert!(difference < 1e-8 * squeeze, "{difference}");
    assert!(a.solver.inner_iterations <= 2 * b.solver.inner_iterations.max(1));
}

/// The disturbance margins of a grasp held through hands and servos are the compliant grasp's,
/// and the report says so: `shared_springs` names them (and `mounted` the fingers on mounts of
/// their own), in scene order; a grasp without any names none.
#[test]
fn margins_name_the_springs_that_make_the_grasp_compliant() {
    use grasp_model::{axis_directions, disturbance_margins, ContactState, MarginOptions};
    let margins = |v: &Value| {
        let model = std::sync::Arc::new(
            GraspModel::from_loaded(&LoadedScene::from_json_str(&v.to_string()).unwrap()).unwrap(),
        );
        disturbance_margins(
            &model,
            &StepInputs::of_scene(&model),
            &ContactState::new(&model),
            SolveOptions::default(),
            &axis_directions(&model),
            &MarginOptions::default(),
        )
        .unwrap()
    };
    let gripper = margins(&support::example_json("plate_transfer_gripper.json"));
    assert_eq!(gripper.shared_springs, ["giver", "arm", "gripper"]);
    assert_eq!(gripper.mounted, ["f3", "f4"]);
    let plain = margins(&held_box(None, "energy"));
    assert!(plain.shared_springs.is_empty() && plain.mounted.is_empty());
}
