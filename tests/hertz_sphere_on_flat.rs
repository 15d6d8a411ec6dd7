//! Hertz: a spherical fingertip pressed on a flat object (Johnson, Contact Mechanics,
//! section 4.2). The model must reproduce the peak pressure and the approach within 1 % at a
//! stated grid, and the error must shrink as the grid is refined.

use grasp_model::closed_form::HertzSphere;
use grasp_model::solve;
use grasp_model::Material;
use grasp_model::{GraspModel, LoadedScene, SolveStatus};

const E: f64 = 210e9; // steel, Pa
const NU: f64 = 0.3;
const R: f64 = 0.01; // tip radius, m
const P: f64 = 10.0; // load, N

fn hertz() -> HertzSphere {
    let m = Material::Elastic {
        youngs_modulus_pa: E,
        poisson_ratio: NU,
    };
    HertzSphere::new(P, R, m.effective_modulus_pa(&m))
}

/// One frictionless spherical fingertip under an object of weight `P` resting on it: the
/// finger is held, so the object's downward translation is the Hertz approach.
fn scene(grid: usize, patch_over_a: f64) -> LoadedScene {
    let side = patch_over_a * hertz().contact_radius_m;
    let json = format!(
        r#"{{
        "object": {{ "weight": {P}, "center_of_mass": [0, 0, 0.02], "gravity": [0, 0, -1],
                    "material": {{"youngs_modulus": {E}, "poisson_ratio": {NU}}} }},
        "fingers": [ {{ "name": "tip", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                       "material": {{"youngs_modulus": {E}, "poisson_ratio": {NU}}},
                       "tip_radius": {R}, "patch": {{"size": [{side}, {side}], "grid": [{grid}, {grid}]}},
                       "friction": {{"mu": 0.0}} }} ]
    }}"#
    );
    LoadedScene::from_json_str(&json).expect("valid scene")
}

/// Relative errors (peak pressure, approach) at an odd grid over a patch of 2.4 a.
fn errors(grid: usize) -> (f64, f64) {
    let model = GraspModel::from_loaded(&scene(grid, 2.4)).unwrap();
    let sol = solve(&model).unwrap();
    assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
    let f = &sol.fingers[0];
    assert!((f.normal_force_n - P).abs() < 1e-9 * P);
    let h = hertz();
    // Approach: the object moves toward the held finger, i.e. against the normal (+z).
    let approach = -sol.rigid_displacement.unwrap().translation_m[2];
    let e_p = (f.peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
    let e_d = (approach - h.approach_m).abs() / h.approach_m;
    (e_p, e_d)
}

#[test]
fn peak_pressure_and_approach_within_one_percent_at_31x31() {
    let (e_p, e_d) = errors(31);
    eprintln!("31x31 over 2.4a: peak pressure error {e_p:.4}, approach error {e_d:.4}");
    assert!(e_p < 0.01, "peak pressure error {e_p}");
    assert!(e_d < 0.01, "approach error {e_d}");
}

#[test]
fn error_shrinks_as_the_grid_is_refined() {
    let e: Vec<(f64, f64)> = [11, 21, 31].iter().map(|&g| errors(g)).collect();
    eprintln!("errors (peak, approach) at 11, 21, 31: {e:?}");
    for w in e.windows(2) {
        assert!(w[1].0 < w[0].0, "peak pressure error did not shrink: {e:?}");
        assert!(w[1].1 < w[0].1, "approach error did not shrink: {e:?}");
    }
}

/// Fine grids on the FFT compliance operator: at 128x128 and 256x256 over a patch
/// of 2.4 a (the automatic choice takes the FFT path above 64x64), the peak pressure within
/// 0.2 % of Hertz's p0 (the 31x31 dense grid is already within 1 %; the error falls roughly
/// with the element size), the contact radius within one element of Hertz's a (from the loaded
/// elements' area, which a one-element ring shifts by about h), and the total load exact to
/// round-off (it is an equality row of the program).
#[test]
fn fine_grids_on_the_fft_operator_meet_hertz() {
    use grasp_model::CompliancePath;
    let h = hertz();
    for grid in [128, 256] {
        let model = GraspModel::from_loaded(&scene(grid, 2.4)).unwrap();
        let sol = solve(&model).unwrap();
        assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
        assert_eq!(sol.solver.compliance, CompliancePath::Fft);
        let f = &sol.fingers[0];
        assert!(
            (f.normal_force_n - P).abs() <= 1e-9 * P,
            "{}",
            f.normal_force_n
        );
        let e_p = (f.peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
        let el = 2.4 * h.contact_radius_m / grid as f64;
        let loaded = f.elements.iter().filter(|e| e.normal_force_n > 0.0).count();
        let radius = (loaded as f64 * el * el / std::f64::consts::PI).sqrt();
        eprintln!(
            "{grid}x{grid} (FFT, {} conjugate-gradient iterations): peak pressure error \
             {e_p:.2e}, contact radius {radius:.4e} m against a = {:.4e} m (element {el:.2e} m)",
            sol.solver.inner_iterations, h.contact_radius_m
        );
        assert!(e_p < 2e-3, "peak pressure error {e_p}");
        assert!(
            (radius - h.contact_radius_m).abs() <= el,
            "contact radius {radius}"
        );
    }
}

/// A fine patch gives the same bits on one thread as on four: every transform, product and
/// sum of the FFT path is split the same way whatever the threads (a 192 x 192 patch runs
/// the transforms, the vector updates, the equality rows' sums and the linearisation on all
/// cores), and a second run on four threads gives them again. Exact equality is the claim, so
/// there is no tolerance; the solution also meets Hertz as above.
#[test]
fn fine_patches_give_the_same_bits_on_one_thread_as_on_four() {
    let model = GraspModel::from_loaded(&scene(192, 2.4)).unwrap();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| solve(&model).unwrap())
    };
    let (one, four, again) = (on(1), on(4), on(4));
    assert_eq!(one.status, SolveStatus::Solved, "{:?}", one.reason);
    let bits = |s: &grasp_model::Solution| -> Vec<u64> {
        s.fingers[0]
            .elements
            .iter()
            .map(|e| e.normal_force_n.to_bits())
            .collect()
    };
    assert_eq!(bits(&one), bits(&four));
    assert_eq!(
        bits(&four),
        bits(&again),
        "a second solve of the same model"
    );
    assert_eq!(
        one.solver.inner_iterations, four.solver.inner_iterations,
        "conjugate-gradient iterations"
    );
    let h = hertz();
    let e_p = (one.fingers[0].peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
    assert!(e_p < 2e-3, "peak pressure error {e_p}");
}

/// What needs matrix entries is refused on an FFT patch too large to write out, with the
/// option that changes it: the sensitivities (a dense system over the free
/// directions), Clarabel, and a dense matrix forced on a grid whose blocks cannot fit.
#[test]
fn fine_fft_patches_refuse_what_needs_matrix_entries_by_name() {
    use grasp_model::ComplianceChoice;
    use grasp_model::{GraspSolver, ModelError, SceneError, SolveOptions, SolverChoice};
    let model = GraspModel::from_loaded(&scene(128, 2.4)).unwrap();
    let mut solver = GraspSolver::new(model.clone(), SolveOptions::default());
    let sol = solver
        .solve(&grasp_model::StepInputs::of_scene(&model))
        .unwrap();
    match solver.sensitivities(&sol) {
        Err(ModelError::Derivative(m)) => assert!(m.contains("`SolveOptions::compliance`"), "{m}"),
        other => panic!("sensitivities on a 128x128 FFT patch: {other:?}"),
    }
    // At 256 x 256 the dense path would need 32 GiB as well: the grid is too fine, said so
    // instead of sending the caller to a dense compliance it cannot afford.
    let fine = GraspModel::from_loaded(&scene(256, 2.4)).unwrap();
    let mut solver = GraspSolver::new(fine.clone(), SolveOptions::default());
    let sol = solver
        .solve(&grasp_model::StepInputs::of_scene(&fine))
        .unwrap();
    match solver.sensitivities(&sol) {
        Err(ModelError::Derivative(m)) => {
            assert!(m.contains("the grid is too fine"), "{m}");
            assert!(!m.contains("to dense"), "{m}");
        }
        other => panic!("sensitivities on a 256x256 FFT patch: {other:?}"),
    }
    let clarabel = SolveOptions {
        solver: SolverChoice::Clarabel,
        ..SolveOptions::default()
    };
    match GraspSolver::new(model.clone(), clarabel)
        .solve(&grasp_model::StepInputs::of_scene(&model))
    {
        Err(ModelError::Solver(m)) => assert!(m.contains("`SolveOptions::compliance`"), "{m}"),
        other => panic!(
            "Clarabel on a 128x128 FFT patch: {:?}",
            other.map(|s| s.status)
        ),
    }
    match GraspModel::from_loaded_with(&scene(1024, 2.4), ComplianceChoice::Dense) {
        Err(SceneError::Invalid(p)) => {
            assert_eq!(p[0].path, "fingers");
            assert!(
                p[0].fix.contains("`SolveOptions::compliance`"),
                "{:?}",
                p[0]
            );
        }
        other => panic!(
            "a dense 1024x1024 patch: {:?}",
            other.map(|m| m.n_unknowns())
        ),
    }
}
