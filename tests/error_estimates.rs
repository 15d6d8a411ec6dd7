//! Error against run time: the Richardson estimate of the discretisation error is of
//! the size of the true error, refinement studies measure against closed forms or the finest
//! grid, and undersized patches are flagged and grown (thesis section 2.2.1).

mod support;
use support::*;

use grasp_model::auto_patch;
use grasp_model::closed_form::HertzSphere;
use grasp_model::solve;
use grasp_model::{estimate_error, refinement_study, StudyReference};
use grasp_model::{GraspModel, SolveOptions};

fn hertz_reference() -> HertzSphere {
    let m = grasp_model::Material::Elastic {
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    HertzSphere::new(10.0, 0.01, m.effective_modulus_pa(&m))
}

/// On Hertz the estimated peak-pressure error is within a factor 3 of the true error (the
/// estimate assumes first order; the observed order is near 1 at these grids).
#[test]
fn estimate_matches_the_true_error_on_hertz() {
    let v = example_json("hertz_sphere_on_flat.json");
    let s = scene(&v);
    let fine = solve(&GraspModel::from_loaded(&s).unwrap()).unwrap();
    let est = estimate_error(&s, &fine, SolveOptions::default())
        .unwrap()
        .unwrap();
    let truth = (fine.fingers[0].peak_pressure_pa - hertz_reference().peak_pressure_pa).abs()
        / hertz_reference().peak_pressure_pa;
    assert!(
        est.peak_pressure_relative > truth / 3.0 && est.peak_pressure_relative < 3.0 * truth,
        "estimate {} vs true {truth}",
        est.peak_pressure_relative
    );
    assert!(est.extra_time_s > 0.0);
    assert_eq!(est.coarse_grids, vec![[11, 11]]);
}

/// On cube A the estimated force error at 5 x 5 is within a factor 3 of the difference to a
/// 17 x 17 solution (the best available reference).
#[test]
fn estimate_matches_the_finest_grid_difference_on_cube_a() {
    let s = scene(&example_json("cube_a.json"));
    let coarse = solve(&GraspModel::from_loaded(&s).unwrap()).unwrap();
    let est = estimate_error(&s, &coarse, SolveOptions::default())
        .unwrap()
        .unwrap();
    let rows = refinement_study(
        &s,
        &[5, 17],
        StudyReference::FinestGrid,
        SolveOptions::default(),
        || None,
    )
    .unwrap();
    let truth = rows[0].error;
    assert!(
        est.relative > truth / 3.0 && est.relative < 3.0 * truth,
        "estimate {} vs finest-grid difference {truth}",
        est.relative
    );
}

#[test]
fn hertz_study_converges_and_reports_cost() {
    let s = scene(&example_json("hertz_sphere_on_flat.json"));
    let rows = refinement_study(
        &s,
        &[17, 5, 33],
        StudyReference::Hertz,
        SolveOptions::default(),
        || Some(1),
    )
    .unwrap();
    assert_eq!(
        rows.iter().map(|r| r.grid).collect::<Vec<_>>(),
        vec![[5, 5], [17, 17], [33, 33]],
        "ascending"
    );
    assert_eq!(rows[2].unknowns, 33 * 33);
    assert!(rows[2].error < rows[0].error && rows[2].error_2.unwrap() < rows[0].error_2.unwrap());
    assert!(
        rows[2].error < 1e-3,
        "33 x 33 peak pressure error {}",
        rows[2].error
    );
    assert!(rows.iter().all(|r| r.wall_time_s > 0.0
        && r.peak_memory_bytes == Some(1)
        && r.equilibrium_residual < 1e-9));
}

#[test]
fn a_hertz_study_needs_a_hertz_scene() {
    let s = scene(&example_json("cube_a.json"));
    let e = refinement_study(
        &s,
        &[3],
        StudyReference::Hertz,
        SolveOptions::default(),
        || None,
    )
    .unwrap_err();
    assert!(e.contains("exactly one finger"), "{e}");
}

/// A patch smaller than the Hertz contact is flagged; auto-patch grows it until the boundary
/// is unloaded, and the answer then matches Hertz within 1 %.
#[test]
fn undersized_patch_is_flagged_and_grown() {
    let mut v = example_json("hertz_sphere_on_flat.json");
    v["fingers"][0]["patch"]["size"] = serde_json::json!([0.00012, 0.00012]);
    let s = scene(&v);
    let small = solve(&GraspModel::from_loaded(&s).unwrap()).unwrap();
    assert!(small.fingers[0].boundary_load_fraction > 0.1);
    assert!(
        small.warnings.iter().any(|w| w.contains("too small")),
        "{:?}",
        small.warnings
    );
    let a = auto_patch(&s, SolveOptions::default(), 6).unwrap();
    assert!(a.solution.warnings.is_empty(), "{:?}", a.solution.warnings);
    assert!(!a.log.is_empty());
    let h = hertz_reference();
    let e =
        (a.solution.fingers[0].peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
    assert!(e < 0.01, "peak pressure error after growth {e}");
    // Flat pads are the contact: their loaded edge is not a warning.
    assert!(solved(&example_json("cube_a.json")).warnings.is_empty());
}
