//! Disturbance margins against closed forms and an independent computation:
//!
//! - a two-finger pinch of a block (flat pads, commanded loads `P`, weight `W`) under a
//!   vertical force: the margin downwards is `2 mu P - W`, upwards `2 mu P + W` (friction
//!   capacity of the two pads), in both models;
//! - the same pinch with spherical fingertips under a torque about the pinch axis: the margin
//!   is the friction moment of the two pads at full slip, `2 x 3 pi mu P a / 16` with the Hertz
//!   radius `a` (Johnson section 7.3; 1 %: the grid's integration error), and exactly
//!   `2 mu sum_k F_k |r_k|` of the grid's
//!   element loads (equal materials: twisting does not change the normal forces);
//! - the energy model's margins of a three-finger cube grasp with commanded loads against its
//!   rigid-body bound, the largest wrench that forces within the element cones can balance,
//!   computed here by an SOCP written from the scene's geometry and solved by Clarabel.
//!
//! Margins are searched to a relative bracket of 1e-3 ([`MarginOptions`]), so each comparison
//! allows 2e-3 of the expected value (the bracket plus solver tolerances).

mod support;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use grasp_model::Material;
use grasp_model::{closed_form::full_slip_torque_nm, closed_form::HertzSphere};
use grasp_model::{disturbance_margins, spread_directions, MarginOptions, WrenchDirection};
use grasp_model::{ContactState, GraspModel, GraspSolver, LoadedScene, SolveOptions};
use nalgebra::Vector3;
use serde_json::{json, Value};
use support::{example_json, scene};

const MU: f64 = 0.5;
const P: f64 = 10.0;
const W: f64 = 4.0;

/// A block of width 0.04 m pinched along x by two steel pads (commanded load `P`), weight `w`,
/// Poisson's ratio `nu` for both bodies.
fn pinch(
    model: &str,
    w: f64,
    tip_radius: Option<f64>,
    side: f64,
    grid: usize,
    nu: f64,
) -> LoadedScene {
    let finger = |name: &str, x: f64, nx: f64| {
        json!({
            "name": name, "contact_point": [x, 0.0, 0.0], "normal": [nx, 0.0, 0.0],
            "tangent": [0.0, 1.0, 0.0],
            "material": {"youngs_modulus": 210e9, "poisson_ratio": nu},
            "tip_radius": tip_radius,
            "patch": {"size": [side, side], "grid": [grid, grid]},
            "friction": {"mu": MU}, "control": {"normal_load": P}
        })
    };
    scene(&json!({
        "object": {"weight": w, "center_of_mass": [0.0, 0.0, 0.0],
                   "material": {"youngs_modulus": 210e9, "poisson_ratio": nu}},
        "fingers": [finger("left", -0.02, 1.0), finger("right", 0.02, -1.0)],
        "model": model
    }))
}

fn margins_along(scene: &LoadedScene, dirs: &[WrenchDirection], length_m: f64) -> Vec<f64> {
    let model = std::sync::Arc::new(GraspModel::from_loaded(scene).unwrap());
    let options = MarginOptions {
        length_m: Some(length_m),
        ..MarginOptions::default()
    };
    let report = disturbance_margins(
        &model,
        &grasp_model::StepInputs::of_scene(&model),
        &ContactState::new(&model),
        SolveOptions::default(),
        dirs,
        &options,
    )
    .unwrap();
    report
        .directions
        .iter()
        .map(|d| d.margin_n.expect("a bounded margin"))
        .collect()
}

fn force(f: [f64; 3]) -> WrenchDirection {
    WrenchDirection {
        force: f,
        torque: [0.0; 3],
    }
}

fn assert_close(got: f64, want: f64, rel: f64, what: &str) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: {got} vs {want} (allowed {rel:e} relative)"
    );
}

/// Poisson's ratio 0: Cerruti's tangential field then has no cross term, so the elements of a
/// pad slip in parallel and the last one sticks until `Q = mu P` exactly, as in the continuum.
/// (With `nu = 0.3` the discrete pad's slips fan out by the cross-compliance and every element
/// slips, by about 1e-10 m, from `Q = 0.998 mu P`: the coulomb criterion "keeps a sticking
/// element" then answers 0.2 % low.)
#[test]
fn pinch_takes_twice_mu_p_less_the_weight_downwards() {
    let dirs = [force([0.0, 0.0, -1.0]), force([0.0, 0.0, 1.0])];
    for model in ["coulomb", "energy"] {
        let m = margins_along(&pinch(model, W, None, 0.01, 5, 0.0), &dirs, 1.0);
        assert_close(m[0], 2.0 * MU * P - W, 2e-3, &format!("{model} down"));
        assert_close(m[1], 2.0 * MU * P + W, 2e-3, &format!("{model} up"));
    }
}

#[test]
fn pinch_torque_about_its_axis_is_the_pads_friction_moment() {
    let (radius, grid) = (0.01, 11);
    let steel = Material::Elastic {
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let a = HertzSphere::new(P, radius, steel.effective_modulus_pa(&steel)).contact_radius_m;
    let scene = pinch("coulomb", 0.0, Some(radius), 2.4 * a, grid, 0.3);
    // The torque direction with L = 1 m: the margin is the torque in N m.
    let twist = WrenchDirection {
        force: [0.0; 3],
        torque: [1.0, 0.0, 0.0],
    };
    let margin = margins_along(&scene, &[twist], 1.0)[0];
    // The grid's own full-slip moment, from the untwisted element loads.
    let model = GraspModel::from_loaded(&scene).unwrap();
    let base = GraspSolver::new(model.clone(), SolveOptions::default())
        .solve(&grasp_model::StepInputs::loads(vec![P, P]))
        .unwrap();
    let grid_moment: f64 = base
        .fingers
        .iter()
        .zip([-0.02, 0.02])
        .map(|(f, x)| {
            f.elements
                .iter()
                .map(|e| {
                    let r = Vector3::from(e.position_m) - Vector3::new(x, 0.0, 0.0);
                    MU * e.normal_force_n * r.norm()
                })
                .sum::<f64>()
        })
        .sum();
    assert_close(margin, grid_moment, 2e-3, "twist against the grid's moment");
    // Against Johnson's closed form: the 11 x 11 grid (h = 0.22 a) integrates the Hertz
    // pressure's moment `int p r dA` to better than 1 % (the midpoint rule on a field that is
    // smooth inside the circle and vanishes like a square root at its edge).
    let closed = 2.0 * full_slip_torque_nm(MU, P, a);
    assert_close(
        margin,
        closed,
        1e-2,
        "twist against 3 pi mu P a / 16 per pad",
    );
}

/// The largest `s` for which forces in the element cones, with the commanded loads, balance
/// the scene's load plus `s` along `d` (force at the centre of mass, couple `s L t`): an SOCP
/// in `(s, F_k, g_k)` with `g_k` the friction force in world coordinates (`n . g_k = 0`).
/// `None` when unbounded.
fn rigid_body_bound(v: &Value, d: &WrenchDirection, length_m: f64) -> Option<f64> {
    let model = GraspModel::from_loaded(&scene(v)).unwrap();
    let com = Vector3::from_iterator(
        v["object"]["center_of_mass"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap()),
    );
    let weight = Vector3::new(0.0, 0.0, -v["object"]["weight"].as_f64().unwrap());
    let elements: Vec<(usize, Vector3<f64>, Vector3<f64>)> = model
        .fingers()
        .iter()
        .enumerate()
        .flat_map(|(i, f)| {
            let n = Vector3::from_iterator(
                v["fingers"][i]["normal"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap()),
            )
            .normalize();
            (0..f.patch().len()).map(move |k| (i, f.element_point(k), n))
        })
        .collect();
    let nvar = 1 + 4 * elements.len();
    let (fd, td) = (Vector3::from(d.force), Vector3::from(d.torque) * length_m);
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut b: Vec<f64> = Vec::new();
    // Force and moment balance (about the origin).
    for c in 0..6 {
        let mut row = vec![0.0; nvar];
        let unit = |dir: &Vector3<f64>, at: &Vector3<f64>| {
            if c < 3 {
                dir[c]
            } else {
                at.cross(dir)[c - 3]
            }
        };
        row[0] = if c < 3 {
            fd[c]
        } else {
            (com.cross(&fd) + td)[c - 3]
        };
        for (j, (_, r, n)) in elements.iter().enumerate() {
            row[1 + 4 * j] = unit(n, r);
            for a in 0..3 {
                row[2 + 4 * j + a] = unit(&Vector3::ith(a, 1.0), r);
            }
        }
        rows.push(row);
        b.push(
            -(if c < 3 {
                weight[c]
            } else {
                com.cross(&weight)[c - 3]
            }),
        );
    }
    // Friction in the tangent plane; commanded loads.
    for (j, (_, _, n)) in elements.iter().enumerate() {
        let mut row = vec![0.0; nvar];
        for a in 0..3 {
            row[2 + 4 * j + a] = n[a];
        }
        rows.push(row);
        b.push(0.0);
    }
    for (i, f) in v["fingers"].as_array().unwrap().iter().enumerate() {
        if let Some(p) = f["control"]["normal_load"].as_f64() {
            let mut row = vec![0.0; nvar];
            for (j, e) in elements.iter().enumerate() {
                if e.0 == i {
                    row[1 + 4 * j] = 1.0;
                }
            }
            rows.push(row);
            b.push(p);
        }
    }
    let n_eq = rows.len();
    // Cones (mu F_k, g_k) in SOC(4): s = -A x.
    let mut cones = vec![SupportedConeT::ZeroConeT(n_eq)];
    for (j, (i, _, _)) in elements.iter().enumerate() {
        let mu = v["fingers"][*i]["friction"]["mu"].as_f64().unwrap();
        for a in 0..4 {
            let mut row = vec![0.0; nvar];
            row[1 + 4 * j + a] = if a == 0 { -mu } else { -1.0 };
            rows.push(row);
            b.push(0.0);
        }
        cones.push(SupportedConeT::SecondOrderConeT(4));
    }
    let a = CscMatrix::from(rows.iter().map(|r| r.iter()));
    let p = CscMatrix::zeros((nvar, nvar));
    let mut q = vec![0.0; nvar];
    q[0] = -1.0;
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-10)
        .tol_gap_rel(1e-10)
        .tol_feas(1e-10)
        .build()
        .unwrap();
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).unwrap();
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Some(solver.solution.x[0]),
        SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => None,
        other => panic!("rigid-body bound: {other:?}"),
    }
}

#[test]
fn energy_margins_of_a_commanded_cube_grasp_are_its_rigid_body_bound() {
    // Cube A with every finger force-controlled at the loads of its held solve.
    let mut v = example_json("cube_a.json");
    let held = support::solved(&v);
    for (f, s) in v["fingers"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .zip(&held.fingers)
    {
        f["control"] = json!({"normal_load": s.normal_force_n});
    }
    let model = std::sync::Arc::new(GraspModel::from_loaded(&scene(&v)).unwrap());
    let dirs = spread_directions(&model, 20);
    let options = MarginOptions::default();
    let report = disturbance_margins(
        &model,
        &grasp_model::StepInputs::of_scene(&model),
        &ContactState::new(&model),
        SolveOptions::default(),
        &dirs,
        &options,
    )
    .unwrap();
    let cap = options.max_factor * model.scales().load_n;
    let mut bounded = 0;
    for (d, m) in dirs.iter().zip(&report.directions) {
        match rigid_body_bound(&v, d, report.length_m) {
            Some(bound) if bound < cap => {
                bounded += 1;
                let margin = m.margin_n.expect("a bounded margin");
                assert_close(margin, bound, 2e-3, &format!("{d:?}"));
            }
            _ => assert!(!m.bounded, "{d:?}: margin {:?} but no bound", m.margin_n),
        }
    }
    assert!(bounded >= 10, "only {bounded} bounded directions");
}
