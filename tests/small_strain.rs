//! Nonsense that used to pass as an answer: a contact pressed beyond the small
//! strains of linear elasticity is warned about, naming the finger, its compression and the
//! limit, for force- and position-controlled fingers alike; and "solved" means the usual
//! residuals (within 1e-6), or the answer says reduced accuracy with the residual named.

mod support;

use grasp_model::SolveStatus;
use serde_json::json;
use support::*;

/// The warnings of `sol` about small strain.
fn strain_warnings(sol: &grasp_model::Solution) -> Vec<&String> {
    sol.warnings
        .iter()
        .filter(|w| w.contains("beyond small strain"))
        .collect()
}

/// The 1 mm pads of `pad_pinch.json`: squeezed by 2 N (compression 0.16 mm, 16 % of the pad)
/// no warning; by 200 N (measured 2.15 mm, over twice the pad's thickness) both pads are
/// warned about, with the layer's figure and the 30 % limit.
#[test]
fn a_pad_squeezed_through_its_thickness_is_warned_about() {
    let v = example_json("pad_pinch.json");
    let calm = solve_json(&v);
    assert!(strain_warnings(&calm).is_empty(), "{:?}", calm.warnings);
    let mut hard = v.clone();
    hard["fingers"][1]["control"] = json!({"normal_load": 200.0});
    let s = solve_json(&hard);
    let w = strain_warnings(&s);
    assert_eq!(w.len(), 2, "{:?}", s.warnings);
    assert!(
        w.iter()
            .all(|w| w.contains("layer's thickness") && w.contains("(30 %)")),
        "{w:?}"
    );
    assert!(w[0].starts_with("fingers[0] `left`"), "{w:?}");
}

/// A rubber fingertip of radius 10 mm pressed in by a prescribed 5 mm (half its radius: a
/// contact radius near 0.7 R by Hertz's `delta = a^2 / R`) is warned about against its radius;
/// the same tip pressed by 0.2 mm (`a = 0.14 R`) is not. A steel Hertz contact at 10 N (the
/// bundled check, approach 0.75 um on R = 10 mm) is not either.
#[test]
fn a_tip_pressed_in_by_half_its_radius_is_warned_about() {
    let tip = |approach_m: f64| {
        let mut v = example_json("cube_a.json");
        let f = &mut v["fingers"][0];
        f["tip_radius"] = json!(0.01);
        f["material"] = json!({"youngs_modulus": 2e6, "poisson_ratio": 0.45});
        f["patch"] = json!({"size": [0.02, 0.02], "grid": [15, 15]});
        f["control"] = json!({"approach_m": approach_m});
        v
    };
    let deep = solve_json(&tip(0.005));
    assert!(deep.status.has_forces(), "{:?}", deep.reason);
    let w = strain_warnings(&deep);
    assert_eq!(w.len(), 1, "{:?}", deep.warnings);
    assert!(
        w[0].starts_with("fingers[0]") && w[0].contains("radius of curvature"),
        "{w:?}"
    );
    let shallow = solve_json(&tip(0.0002));
    assert!(
        strain_warnings(&shallow).is_empty(),
        "{:?}",
        shallow.warnings
    );
    let hertz = solve_json(&example_json("hertz_sphere_on_flat.json"));
    assert!(strain_warnings(&hertz).is_empty(), "{:?}", hertz.warnings);
}

/// "Solved" means residuals within 1e-6: the viscoelastic hold solved by Clarabel through its
/// history to t = 5 s reaches a stick-motion residual of 2.6e-6 and says reduced accuracy,
/// naming it; the native solver's answer (residuals near 1e-15) is solved.
#[test]
fn an_answer_above_the_usual_residuals_says_reduced_accuracy() {
    let scene = example_scene("plate_hold_viscoelastic.json");
    let model = grasp_model::GraspModel::from_loaded(&scene).unwrap();
    let at = grasp_model::TimePoint::At { seconds: 5.0 };
    let solve = |solver| {
        let options = grasp_model::SolveOptions {
            solver,
            ..Default::default()
        };
        grasp_model::solve_at(&model, options, at).unwrap().solution
    };
    let clarabel = solve(grasp_model::SolverChoice::Clarabel);
    let r = clarabel.residuals.unwrap();
    assert!(r.stick_motion_relative > 1e-6, "{r:?}");
    assert_eq!(clarabel.status, SolveStatus::ReducedAccuracy);
    let reason = clarabel.reason.unwrap();
    assert!(
        reason.contains("stick motion residual") && reason.contains("above 1e-6"),
        "{reason}"
    );
    let native = solve(grasp_model::SolverChoice::Native);
    assert_eq!(native.status, SolveStatus::Solved, "{:?}", native.reason);
    assert!(native.residuals.unwrap().worst() <= 1e-6);
}
