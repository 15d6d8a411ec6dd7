//! Fingertip pads that are elastic layers bonded to a rigid core: the thick limit
//! (the half-space), the thin limits (a Winkler foundation of stiffness `M / h` normally and
//! `G / h` tangentially for a compressible layer, the squeeze film of a thin incompressible
//! one), and agreement of the dense and FFT compliances with layers on both bodies.
//!
//! Closed forms (derived in `model/elastic_layer.rs`'s limits; `M = E (1 - nu)/((1 + nu)(1 - 2
//! nu))`, `G = E / (2 (1 + nu))`):
//! - Winkler under a flat punch pressed by `delta`: `p = M delta / h`; sheared by `u`: `q = G u / h`.
//! - Winkler under a rigid sphere of radius `R`: `p = (M / h)(delta - r^2 / 2R)`, `a^2 = 2 R delta`,
//!   `P = pi M a^4 / (4 R h)`, so `delta = (P h / (pi M R))^(1/2)` and `p0 = M delta / h`.
//! - Thin incompressible layer, shear-free surface (the squeeze film: `-(h^3 / 3G) lap p = w`
//!   with `p = dp/dr = 0` at the edge; Johnson, Contact Mechanics, section 5.9, treats the
//!   thin layer the same way): `p = 3 G (a^2 - r^2)^2 / (32 R h^3)`, `delta = a^2 / (4 R)`,
//!   `P = pi G a^6 / (32 R h^3)`.

use grasp_model::solve;
use grasp_model::ComplianceChoice;
use grasp_model::{GraspModel, GraspSolver, LoadedScene, Solution, SolveOptions, SolveStatus};

const PI: f64 = std::f64::consts::PI;

/// A material's JSON, with a layer of thickness `h` (m) when given.
fn material(e: f64, nu: f64, h: Option<f64>) -> String {
    match h {
        Some(h) => {
            format!(r#"{{"youngs_modulus": {e}, "poisson_ratio": {nu}, "layer_thickness_m": {h}}}"#)
        }
        None => format!(r#"{{"youngs_modulus": {e}, "poisson_ratio": {nu}}}"#),
    }
}

/// One held finger of `finger_material` (flat pad) under a rigid object of weight `p` (N),
/// whose surface has radius `object_radius` (`null`: flat) at the contact; the object's weight
/// may lean by `tilt` (its tangential share along `+x`) with the centre of mass in the contact
/// plane (no moment). Patch `side` m with `grid x grid` elements, friction `mu`.
fn pad_scene(
    finger_material: &str,
    object_radius: &str,
    p: f64,
    tilt: f64,
    side: f64,
    grid: usize,
    mu: f64,
) -> LoadedScene {
    let json = format!(
        r#"{{
        "object": {{ "weight": {p}, "center_of_mass": [0, 0, 0], "gravity": [{tilt}, 0, -1],
                    "material": "rigid" }},
        "fingers": [ {{ "name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                       "tangent": [1, 0, 0], "material": {finger_material},
                       "object_radius": {object_radius},
                       "patch": {{"size": [{side}, {side}], "grid": [{grid}, {grid}]}},
                       "friction": {{"mu": {mu}}} }} ]
    }}"#
    );
    LoadedScene::from_json_str(&json).expect("valid scene")
}

fn solved(scene: &LoadedScene) -> (GraspModel, Solution) {
    let model = GraspModel::from_loaded(scene).unwrap();
    let sol = solve(&model).unwrap();
    assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
    (model, sol)
}

/// The object's approach towards the held finger (it moves against the normal, +z), m.
fn approach(sol: &Solution) -> f64 {
    -sol.rigid_displacement.unwrap().translation_m[2]
}

/// The element nearest the patch centre.
fn centre(sol: &Solution) -> &grasp_model::ElementSolution {
    let f = &sol.fingers[0];
    f.elements
        .iter()
        .min_by(|a, b| {
            let r = |e: &&grasp_model::ElementSolution| e.local_m[0].hypot(e.local_m[1]);
            r(a).total_cmp(&r(b))
        })
        .unwrap()
}

fn constrained_modulus(e: f64, nu: f64) -> f64 {
    e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

/// Thick limit: a pad 100 contact radii thick is the half-space. A rubber pad (E 1 MPa,
/// nu 0.45) under a rigid 10 mm sphere at 2 N, 31 x 31 over 2.4 Hertz radii (dense): the same
/// elements in contact and the peak pressure within 1e-3 of the half-space pad's, both within
/// 1 % of Hertz's; the patch compliances differ by at most 1e-3 of the largest entry (the
/// layer's correction at the source, about `0.15 / (G h)`, against the self coefficient,
/// about `3.5 (1 - nu) / (pi G e)`: `e / h` small).
#[test]
fn a_thick_layer_is_the_half_space() {
    let (e, nu, r, p): (f64, f64, f64, f64) = (1e6, 0.45, 0.01, 2.0);
    let e_star = e / (1.0 - nu * nu);
    let a = (3.0 * p * r / (4.0 * e_star)).cbrt();
    let side = 2.4 * a;
    let half = pad_scene(
        &material(e, nu, None),
        &r.to_string(),
        p,
        0.0,
        side,
        31,
        0.0,
    );
    let thick = pad_scene(
        &material(e, nu, Some(100.0 * a)),
        &r.to_string(),
        p,
        0.0,
        side,
        31,
        0.0,
    );
    let (mh, sh) = solved(&half);
    let (mt, st) = solved(&thick);
    let (fh, ft) = (&sh.fingers[0], &st.fingers[0]);
    let p0 = 1.5 * p / (PI * a * a);
    eprintln!(
        "peak pressure: half-space {:.6e}, layer 100 a {:.6e}, Hertz {p0:.6e}; contact area {:.4e} vs {:.4e}",
        fh.peak_pressure_pa, ft.peak_pressure_pa, fh.contact_area_m2, ft.contact_area_m2
    );
    // The elements in contact, whichever their state (this pair is frictionless).
    assert_eq!(
        fh.stick_count + fh.slip_count + fh.frictionless_count,
        ft.stick_count + ft.slip_count + ft.frictionless_count
    );
    assert!((ft.peak_pressure_pa - fh.peak_pressure_pa).abs() <= 1e-3 * fh.peak_pressure_pa);
    assert!((fh.peak_pressure_pa - p0).abs() <= 0.01 * p0);
    let (ch, ct) = (
        mh.fingers()[0].compliance_matrix_m_per_n().unwrap(),
        mt.fingers()[0].compliance_matrix_m_per_n().unwrap(),
    );
    let diff = (&*ch - &*ct).amax();
    eprintln!(
        "largest coefficient change {:.2e} of the largest",
        diff / ch.amax()
    );
    assert!(diff <= 1e-3 * ch.amax());
}

/// Thin compressible layer under a flat punch (Winkler, normal): a rigid flat object pressed
/// into a square pad 30 thicknesses wide (nu 0.3, 60 x 60, the FFT path): at the centre the
/// pressure is `M delta / h`. Tolerance 1e-4: the edge's influence at 15 thicknesses decays
/// like `e^{-0.91 * 15}` (1e-6), and an interior row of the coefficients sums to `h / M`
/// exactly (the element averages integrate the Green's function over the whole patch).
#[test]
fn a_thin_layer_under_a_flat_punch_is_a_winkler_foundation() {
    let (e, nu, h, p) = (2e6, 0.3, 1e-3, 50.0);
    let scene = pad_scene(&material(e, nu, Some(h)), "null", p, 0.0, 30.0 * h, 60, 0.0);
    let (_, sol) = solved(&scene);
    let want = constrained_modulus(e, nu) * approach(&sol) / h;
    let got = centre(&sol).pressure_pa;
    eprintln!("centre pressure {got:.6e} Pa, M delta / h {want:.6e} Pa");
    assert!((got - want).abs() <= 1e-4 * want, "{got:e} vs {want:e}");
    // Not the half-space: there a flat punch's interior pressure is far below M delta / h.
    assert!(got < 1.01 * p / (30.0 * h).powi(2) * 1.5);
}

/// Thin compressible layer sheared (Winkler, tangential): the object's weight leans by 0.2
/// (its centre of mass in the contact plane, so no moment), the pad sticks (mu 1): at the
/// centre the shear traction is `G u / h` with `u` the object's tangential translation, and the
/// pressure `M delta / h` still. Tolerance 1e-3 on the shear: the layer couples normal and
/// tangential, so the sheared pad's edges tilt the rigid object slightly, and the pressure
/// gradient of that tilt shifts the tangential displacement through the coupling (its `k h^2`
/// term): measured 9.6e-5 on this 30 h pad and 5.6e-5 on a 40 h one, falling like
/// `(h / L)^2`. The pressure keeps 1e-4.
#[test]
fn a_thin_layer_sheared_is_a_winkler_foundation() {
    let (e, nu, h, p) = (2e6, 0.3, 1e-3, 50.0);
    let g = e / (2.0 * (1.0 + nu));
    let scene = pad_scene(&material(e, nu, Some(h)), "null", p, 0.2, 30.0 * h, 60, 1.0);
    let (_, sol) = solved(&scene);
    let c = centre(&sol);
    let u = sol.rigid_displacement.unwrap().translation_m[0];
    let want = g * u.abs() / h;
    let got = c.traction_pa[0].abs();
    eprintln!("centre shear {got:.6e} Pa, G u / h {want:.6e} Pa (u {u:.3e} m)");
    assert_eq!(c.state, grasp_model::ElementState::Stick);
    assert!((got - want).abs() <= 1e-3 * want, "{got:e} vs {want:e}");
    let normal = constrained_modulus(e, nu) * approach(&sol) / h;
    assert!((c.pressure_pa - normal).abs() <= 1e-4 * normal);
}

/// Thin compressible layer under a sphere (Winkler): nu 0.3, `a = 10 h` (R 50 mm, h 0.2 mm),
/// 61 x 61 over 2.4 a: `delta = (P h / (pi M R))^(1/2)` and `p0 = M delta / h`. Tolerance
/// 0.5 %: the thin-layer theory's next term, `+0.14 (h/a)^2 = 0.14 %` in `delta` (the
/// layer's `nu (4 nu - 1) k^2 h^3 / (6 (1 - nu)^2 G)`), and the grid's, whose element is 0.4 h.
#[test]
fn a_thin_layer_under_a_sphere_is_a_winkler_foundation() {
    let (e, nu, h, r): (f64, f64, f64, f64) = (2e6, 0.3, 2e-4, 0.05);
    let m = constrained_modulus(e, nu);
    let a = 10.0 * h;
    let p = PI * m * a.powi(4) / (4.0 * r * h);
    let scene = pad_scene(
        &material(e, nu, Some(h)),
        &r.to_string(),
        p,
        0.0,
        2.4 * a,
        61,
        0.0,
    );
    let (_, sol) = solved(&scene);
    let delta = (p * h / (PI * m * r)).sqrt();
    let p0 = m * delta / h;
    let (got_d, got_p) = (approach(&sol), sol.fingers[0].peak_pressure_pa);
    eprintln!(
        "Winkler sphere: approach {got_d:.6e} m vs {delta:.6e} m, peak {got_p:.6e} Pa vs {p0:.6e} Pa"
    );
    assert!((got_d - delta).abs() <= 5e-3 * delta);
    assert!((got_p - p0).abs() <= 5e-3 * p0);
}

/// Thin nearly incompressible layer under a sphere (nu = 0.499999, so the compressibility
/// length `(h^2 nu (4 nu - 1) / (3 (1 - nu)(1 - 2 nu)))^(1/2)` is 408 h, far above `a`):
/// `a = 20 h`, frictionless (the shear-free surface of the squeeze film), 89 x 89 over 2.2 a
/// (the FFT path): `delta = a^2 / (4 R)` with `a = (32 R P h^3 / (pi G))^(1/6)`, and
/// `p0 = 3 G a^4 / (32 R h^3)`. Tolerance 2.5 %: the next terms are `-7.2 (h/a)^2 = -1.8 %`
/// in `delta` and `+1.8 %` in `p0` (measured on a converged FFT solution of the exact layer
/// kernel; the theory is exact as `h / a -> 0`).
#[test]
fn a_thin_incompressible_layer_under_a_sphere_is_a_squeeze_film() {
    let (e, nu, h, r): (f64, f64, f64, f64) = (1e6, 0.499999, 1e-4, 0.05);
    let g = e / (2.0 * (1.0 + nu));
    let a = 20.0 * h;
    let p = PI * g * a.powi(6) / (32.0 * r * h.powi(3));
    let scene = pad_scene(
        &material(e, nu, Some(h)),
        &r.to_string(),
        p,
        0.0,
        2.2 * a,
        89,
        0.0,
    );
    let (_, sol) = solved(&scene);
    let delta = a * a / (4.0 * r);
    let p0 = 3.0 * g * a.powi(4) / (32.0 * r * h.powi(3));
    let (got_d, got_p) = (approach(&sol), sol.fingers[0].peak_pressure_pa);
    eprintln!(
        "squeeze film: approach {got_d:.6e} m vs {delta:.6e} m ({:+.2} %), peak {got_p:.6e} Pa vs {p0:.6e} Pa ({:+.2} %)",
        100.0 * (got_d / delta - 1.0),
        100.0 * (got_p / p0 - 1.0)
    );
    assert!((got_d - delta).abs() <= 0.025 * delta);
    assert!((got_p - p0).abs() <= 0.025 * p0);
}

/// A pinch with layers on both bodies (two different pads, a coated elastic object, friction in
/// 3-D: every block, the coupling included) gives the same forces on the dense and the FFT
/// compliance: within 1e-8 of the load (the two discretise the same operator to round-off;
/// the solves stop at their tolerance).
#[test]
fn dense_and_fft_agree_with_layers_on_both_bodies() {
    let json = format!(
        r#"{{
        "object": {{ "weight": 3.0, "center_of_mass": [0, 0, 0.005], "gravity": [0.3, 0.2, -1],
                    "material": {obj} }},
        "fingers": [
          {{ "name": "left", "contact_point": [-0.02, 0, 0], "normal": [1, 0, 0],
             "material": {left}, "tip_radius": 0.012,
             "patch": {{"size": [0.006, 0.006], "grid": [19, 19]}}, "friction": {{"mu": 0.8}} }},
          {{ "name": "right", "contact_point": [0.02, 0, 0], "normal": [-1, 0, 0],
             "material": {right}, "tip_radius": 0.01,
             "patch": {{"size": [0.006, 0.006], "grid": [19, 19]}}, "friction": {{"mu": 0.8}},
             "control": {{"normal_load": 6.0}} }} ]
    }}"#,
        obj = material(2e9, 0.35, Some(5e-4)),
        left = material(1e6, 0.45, Some(1e-3)),
        right = material(3e6, 0.3, Some(2e-3)),
    );
    let scene = LoadedScene::from_json_str(&json).unwrap();
    let run = |choice| {
        let model = GraspModel::from_loaded_with(&scene, choice).unwrap();
        let options = SolveOptions {
            compliance: choice,
            ..SolveOptions::default()
        };
        let sol = GraspSolver::new(model.clone(), options)
            .solve(&grasp_model::StepInputs::of_scene(&model))
            .unwrap();
        assert_eq!(sol.status, SolveStatus::Solved, "{:?}", sol.reason);
        sol
    };
    let (dense, fft) = (run(ComplianceChoice::Dense), run(ComplianceChoice::Fft));
    let mut worst: f64 = 0.0;
    for (d, f) in dense.fingers.iter().zip(&fft.fingers) {
        for (a, b) in d.elements.iter().zip(&f.elements) {
            worst = worst.max((a.normal_force_n - b.normal_force_n).abs());
            for c in 0..2 {
                worst = worst.max((a.tangential_force_n[c] - b.tangential_force_n[c]).abs());
            }
        }
    }
    eprintln!(
        "dense vs FFT with layers: largest element force difference {:.2e} of the load",
        worst / 6.0
    );
    assert!(worst <= 1e-8 * 6.0);
}

/// The reference pad's figures (computed outside this project, given with the layered-pad
/// work as what it must reproduce): a rigid sphere of radius
/// 10 mm pressed with 2 N into a 1 mm pad (E 1 MPa, nu 0.45) on a rigid base has a contact
/// radius about 20 % smaller, a peak pressure about 1.9 times higher and an approach about
/// three times smaller than Hertz's (the half-space pad). 61 x 61 over 5.5 mm (2.4 Hertz
/// radii), the FFT path. Bounds: the figures as stated ("about") with the grid's resolution
/// of the radius (one element, 0.09 mm, 4 % of it): ratio of radii in [0.75, 0.85], of peak
/// pressures in [1.8, 2.0], of approaches in [0.28, 0.38].
#[test]
fn the_reference_pad_matches_its_outside_figures() {
    let pad = |h: Option<f64>| material(1e6, 0.45, h);
    let solve_with = |h| {
        let scene = pad_scene(&pad(h), "0.01", 2.0, 0.0, 0.0055, 61, 0.0);
        solved(&scene).1
    };
    let (layer, half) = (solve_with(Some(1e-3)), solve_with(None));
    let radius = |s: &Solution| (s.fingers[0].contact_area_m2 / PI).sqrt();
    let ratios = [
        radius(&layer) / radius(&half),
        layer.fingers[0].peak_pressure_pa / half.fingers[0].peak_pressure_pa,
        approach(&layer) / approach(&half),
    ];
    eprintln!(
        "pad / half-space: contact radius {:.3}, peak pressure {:.3}, approach {:.3}",
        ratios[0], ratios[1], ratios[2]
    );
    assert!((0.75..=0.85).contains(&ratios[0]), "{ratios:?}");
    assert!((1.8..=2.0).contains(&ratios[1]), "{ratios:?}");
    assert!((0.28..=0.38).contains(&ratios[2]), "{ratios:?}");
}
