//! Every bundled example in working order, found by listing `examples/` and `examples/mujoco/`
//! (not a hand-kept list): each scene solves in equilibrium with its cones satisfied, and each
//! schedule steps its scene to the end, every step solved in equilibrium with its cones
//! satisfied.

mod support;
use support::*;

use grasp_model::{GraspModel, Solution, SolveStatus};
use grasp_transfer::{Stepper, TransferOptions};

/// Solved, equilibrium below 1e-9 of the load scale, cones satisfied, compatibility and
/// complementarity at solver tolerance, every finger's normal force finite and not negative
/// (beyond round-off).
fn assert_in_equilibrium_with_cones_satisfied(what: &str, s: &Solution) {
    assert_eq!(s.status, SolveStatus::Solved, "{what}: {:?}", s.reason);
    let r = s.residuals.unwrap();
    assert!(
        r.equilibrium_relative < 1e-9,
        "{what}: equilibrium {}",
        r.equilibrium_relative
    );
    // Cone violation over the element force unit: a convex solve's answer is feasible up to
    // round-off. A sequential answer (coulomb, load-dependent mu) is a fixed point known to its
    // sequential tolerance (1e-7 of the element force unit between the last two iterates): its
    // forces meet the cones at the radii of the iterate before, so at their own radii to about
    // mu times that (mu <= 2 here).
    let cones = if s.sequential.is_some() { 1e-6 } else { 1e-9 };
    assert!(
        r.cone_violation_relative < cones,
        "{what}: cones {}",
        r.cone_violation_relative
    );
    // KKT conditions hold to the solver tolerance (1e-10 on the scaled program) times the
    // conditioning of the compliance (soft rubber on aluminium): 1e-6 of the displacement
    // unit is far below any physical effect.
    for (name, v) in [
        ("penetration", r.penetration_relative),
        ("compatibility", r.compatibility_relative),
        ("complementarity", r.complementarity_relative),
        ("stick motion", r.stick_motion_relative),
        ("slip direction", r.slip_direction_error),
    ] {
        assert!(v < 1e-6, "{what}: {name} residual {v}");
    }
    // An unloaded finger's resultant is a sum of zeros and round-off (disc_transfer's f2:
    // -4.6e-18 N).
    for f in &s.fingers {
        let p = f.normal_force_n;
        let floor = -1e-12 * s.load_scale_n;
        assert!(
            p >= floor && p.is_finite(),
            "{what}: {} carries {p} N",
            f.name
        );
    }
}

#[test]
fn every_example_scene_is_in_equilibrium_with_cones_satisfied() {
    let names = example_scenes();
    assert!(names.len() >= 20, "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("mujoco/")), "{names:?}");
    for name in &names {
        let model = GraspModel::from_loaded(&example_scene(name)).expect("a usable model");
        let s = grasp_model::solve(&model).expect("the solve runs");
        assert_in_equilibrium_with_cones_satisfied(name, &s);
    }
    println!("{} example scenes solved", names.len());
}

#[test]
fn every_example_schedule_steps_in_equilibrium_with_cones_satisfied() {
    let pairs = example_schedules();
    assert!(pairs.len() >= 10, "{pairs:?}");
    assert!(
        pairs.iter().any(|(_, s)| s.starts_with("mujoco/")),
        "{pairs:?}"
    );
    let mut steps = 0;
    for (scene_name, schedule_name) in &pairs {
        let (scene, schedule) = scene_and_schedule(scene_name, schedule_name);
        let mut n = 0;
        for record in Stepper::new(&scene, &schedule, TransferOptions::default()) {
            let r = record.unwrap_or_else(|e| panic!("{schedule_name} on {scene_name}: {e}"));
            let what = format!("{schedule_name} on {scene_name}, step {}", r.index);
            assert_in_equilibrium_with_cones_satisfied(&what, &r.solution);
            n += 1;
        }
        assert!(n > 1, "{schedule_name}: {n} steps");
        steps += n;
    }
    println!("{} example schedules, {steps} steps solved", pairs.len());
}
