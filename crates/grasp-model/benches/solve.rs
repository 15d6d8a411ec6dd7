//! One-shot solve cost: the thesis examples and a Hertz contact at growing grids.
//! Run: `cargo bench -p grasp-model --bench solve`. Prints model build and solve times (best
//! of 5) with the problem size and the error measure of each case.

use std::path::Path;
use std::time::Instant;

use grasp_model::closed_form::HertzSphere;
use grasp_model::material::Material;
use grasp_model::{solve, GraspModel, Scene};

fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..n {
        let t = Instant::now();
        let v = f();
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(v);
    }
    (best, last.unwrap())
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    println!(
        "{:<28} {:>9} {:>11} {:>11} {:>6} {:>14}",
        "case", "unknowns", "build [ms]", "solve [ms]", "iters", "error"
    );
    for name in [
        "plate_four_fingers",
        "disc_three_fingers",
        "pipe_three_fingers",
        "cube_a",
        "cube_b",
    ] {
        let scene = Scene::from_json_str(
            &std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        let (tb, model) = best_of(5, || GraspModel::from_scene(&scene).unwrap());
        let (ts, sol) = best_of(5, || solve(&model).unwrap());
        let err = sol.residuals.map_or(f64::NAN, |r| r.equilibrium_relative);
        println!(
            "{name:<28} {:>9} {:>11.3} {:>11.3} {:>6} {:>14.2e}",
            model.n_unknowns,
            tb * 1e3,
            ts * 1e3,
            sol.solver.iterations,
            err
        );
    }
    let (e, nu, r, p) = (210e9, 0.3, 0.01, 10.0);
    let m = Material::Elastic {
        youngs_modulus_pa: e,
        poisson_ratio: nu,
    };
    let h = HertzSphere::new(p, r, m.effective_modulus_pa(&m));
    for g in [11, 21, 31, 41] {
        let side = 2.4 * h.contact_radius_m;
        let json = format!(
            r#"{{"object": {{"weight": {p}, "center_of_mass": [0,0,0.02], "material": {{"youngs_modulus": {e}, "poisson_ratio": {nu}}}}},
               "fingers": [{{"name": "tip", "contact_point": [0,0,0], "normal": [0,0,1], "material": {{"youngs_modulus": {e}, "poisson_ratio": {nu}}},
               "tip_radius": {r}, "patch": {{"size": [{side}, {side}], "grid": [{g}, {g}]}}, "friction": {{"mu": 0}}}}]}}"#
        );
        let scene = Scene::from_json_str(&json).unwrap();
        let (tb, model) = best_of(3, || GraspModel::from_scene(&scene).unwrap());
        let (ts, sol) = best_of(3, || solve(&model).unwrap());
        let err = (sol.fingers[0].peak_pressure_pa - h.peak_pressure_pa).abs() / h.peak_pressure_pa;
        println!(
            "{:<28} {:>9} {:>11.3} {:>11.3} {:>6} {:>14.2e}",
            format!("hertz {g}x{g} (p0 error)"),
            model.n_unknowns,
            tb * 1e3,
            ts * 1e3,
            sol.solver.iterations,
            err
        );
    }
}
