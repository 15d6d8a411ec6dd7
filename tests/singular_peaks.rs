//! A peak pressure at a sharp edge of a contact is a property of the grid: the edge pinch's
//! peak (a spherical pad cut off by a box's edge) grows as the grid is refined, as a
//! square-root singularity predicts, and every solve labels it grid-dependent and every study
//! reports its growth; the same pinch with the quadratic gap (no edge) and the Hertz contact
//! converge and are not labelled; a flat pad's rim is a sharp edge too.

mod support;

use grasp_model::{
    grid_with_first_side, peak_trend, refinement_study, with_grids, GraspModel, LoadedScene,
    SolveOptions, StudyReference,
};

/// The edge pinch, its grids `n x n`, with the exact gaps or the thesis's quadratic one.
fn edge_pinch(exact: bool) -> LoadedScene {
    let mut v = support::example_json("edge_pinch.json");
    if !exact {
        for f in v["fingers"].as_array_mut().unwrap() {
            f["gap"] = "quadratic".into();
        }
    }
    support::scene(&v)
}

/// The peak pressures (Pa) of `scene` on grids of `n` elements a side, with their labels.
fn peaks(scene: &LoadedScene, sides: &[usize]) -> Vec<(f64, bool)> {
    sides
        .iter()
        .map(|&n| {
            let s = with_grids(scene, |_, g| grid_with_first_side(g, n));
            let sol = grasp_model::solve(&GraspModel::from_loaded(&s).unwrap()).unwrap();
            let f = &sol.fingers[0];
            (f.peak_pressure_pa, f.peak_pressure_grid_dependent)
        })
        .collect()
}

#[test]
fn the_edge_pinchs_peak_pressure_grows_with_the_grid_and_is_labelled_grid_dependent() {
    let p = peaks(&edge_pinch(true), &[24, 48]);
    // The figures: 0.45 and 0.59 MPa at 24 and 48 elements a side.
    assert!((p[0].0 / 0.453e6 - 1.0).abs() < 0.01, "{p:?}");
    assert!((p[1].0 / 0.589e6 - 1.0).abs() < 0.01, "{p:?}");
    assert!(p.iter().all(|&(_, label)| label), "{p:?}");
}

#[test]
fn a_contact_that_closes_smoothly_has_no_label() {
    let p = peaks(&edge_pinch(false), &[24]);
    assert!(!p[0].1, "{p:?}");
    let hertz = support::solved(&support::example_json("hertz_sphere_on_flat.json"));
    assert!(!hertz.fingers[0].peak_pressure_grid_dependent);
}

#[test]
fn a_flat_pads_peak_at_its_rim_is_labelled_grid_dependent() {
    // Cube A's flat pads: the patch is the pad, its rim a real edge (a flat punch's).
    let cube = support::solved(&support::example_json("cube_a.json"));
    assert!(
        cube.fingers.iter().all(|f| f.peak_pressure_grid_dependent),
        "{:?}",
        cube.fingers
            .iter()
            .map(|f| f.peak_pressure_grid_dependent)
            .collect::<Vec<_>>()
    );
}

#[test]
fn a_study_of_the_edge_pinch_reports_its_peak_growing_as_a_singular_edge() {
    let rows = refinement_study(
        &edge_pinch(true),
        &[12, 24, 48],
        StudyReference::FinestGrid,
        SolveOptions::default(),
        || None,
    )
    .unwrap();
    assert!(rows.iter().all(|r| r.peak_pressure_grid_dependent));
    let trend = peak_trend(&rows).unwrap();
    // A square-root singularity gives n^0.5 in the limit; these grids see about 0.35.
    assert!((0.25..0.6).contains(&trend.exponent), "{trend:?}");
    assert!(trend.at_sharp_edge && trend.grid_dependent, "{trend:?}");
}

#[test]
fn a_study_of_a_smooth_contact_reports_its_peak_converging() {
    let rows = refinement_study(
        &edge_pinch(false),
        &[12, 24, 48],
        StudyReference::FinestGrid,
        SolveOptions::default(),
        || None,
    )
    .unwrap();
    let trend = peak_trend(&rows).unwrap();
    assert!(trend.exponent.abs() < 0.05, "{trend:?}");
    assert!(!trend.at_sharp_edge && !trend.grid_dependent, "{trend:?}");
    // The scene's own warning (the quadratic gap's patch hangs over the edge) on every grid.
    assert!(
        rows.iter()
            .all(|r| r.warnings.iter().any(|w| w.contains("hangs"))),
        "{:?}",
        rows[0].warnings
    );
}
