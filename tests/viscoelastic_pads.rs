//! Viscoelastic pads and position control (issue 26): a rigid sphere on a viscoelastic pad
//! (the pad a half-space) against Lee and Radok's closed forms, the limits of the time
//! stepping, and a held pinch that relaxes until it slips.
//!
//! Closed forms (Lee and Radok, J. Appl. Mech. 27, 1960; model.md, "Facts for pads"; valid
//! while the contact radius does not decrease):
//! - a load `P` held from `t = 0`: `a(t)^3 = (3/4) R (1 - nu^2) P J(t)`, so the approach
//!   `delta = a^2 / R` grows like `(E_0 J(t))^(2/3)` from its instantaneous Hertz value;
//! - an approach `d` held from `t = 0`: `P(t) = (4/3) R^(1/2) d^(3/2) E(t) / (1 - nu^2)`, so the
//!   load relaxes like `E(t) / E_0`.
//!
//! The creep compliance `J` of a Prony relaxation law is computed here independently of the
//! crate (the Volterra equation `int_0^t E(t - s) dJ(s) = 1` stepped on a fine logarithmic
//! grid), not taken from its creep function.

use grasp_model::analysis::relaxation::{solve_at, TimePoint};
use grasp_model::{GraspModel, Scene, Solution, SolveOptions, SolveStatus};

const E0: f64 = 2e6;
const NU: f64 = 0.45;
const R: f64 = 0.01;

/// A relaxation law as `(fractions and times)`; the normalised relaxation `e(t)`.
type Law = &'static [(f64, f64)];

const SLS: Law = &[(0.6, 1.0)];
const TWO_TERMS: Law = &[(0.3, 0.2), (0.35, 10.0)];

fn relaxation(law: Law, t: f64) -> f64 {
    1.0 - law
        .iter()
        .map(|(g, tau)| g * (1.0 - (-t / tau).exp()))
        .sum::<f64>()
}

/// `E_0 J(t)` by the Volterra equation on a logarithmic grid from 1e-6 of the fastest time to
/// `t_max` (midpoint product rule, 20,000 points: error below 1e-6 here).
fn creep(law: Law, t_max: f64) -> impl Fn(f64) -> f64 {
    let t0 = 1e-6 * law.iter().map(|l| l.1).fold(f64::INFINITY, f64::min);
    let n = 20_000;
    let ratio = (t_max / t0).powf(1.0 / n as f64);
    let mut t = vec![0.0];
    t.extend((0..=n).map(|i| t0 * ratio.powi(i)));
    // phi_0 = 1; sum_j e(t_n - tmid_j)(phi_j - phi_{j-1}) + e(t_n) phi_0 = 1.
    let mut phi = vec![1.0];
    for m in 1..t.len() {
        let mut s = relaxation(law, t[m]);
        for j in 1..m {
            s += relaxation(law, t[m] - 0.5 * (t[j] + t[j - 1])) * (phi[j] - phi[j - 1]);
        }
        let last = relaxation(law, 0.5 * (t[m] - t[m - 1]));
        phi.push(phi[m - 1] + (1.0 - s) / last);
    }
    move |x: f64| {
        let i = t.partition_point(|&v| v < x).clamp(1, t.len() - 1);
        let w = (x - t[i - 1]) / (t[i] - t[i - 1]);
        phi[i - 1] + w * (phi[i] - phi[i - 1])
    }
}

fn pad(law: Law) -> String {
    let terms: Vec<String> = law
        .iter()
        .map(|(g, tau)| format!(r#"{{"fraction": {g}, "time_s": {tau}}}"#))
        .collect();
    format!(
        r#"{{"youngs_modulus": {E0}, "poisson_ratio": {NU}, "relaxation": [{}]}}"#,
        terms.join(", ")
    )
}

fn hertz_radius(p: f64) -> f64 {
    (3.0 * p * R * (1.0 - NU * NU) / (4.0 * E0)).cbrt()
}

/// One held flat pad of `material` under a rigid sphere of radius `R` of weight `p`,
/// frictionless, 31 x 31 over `side` (the Hertz check's grid).
fn sphere_on_pad(material: &str, p: f64, side: f64) -> Scene {
    let json = format!(
        r#"{{
        "object": {{ "weight": {p}, "center_of_mass": [0, 0, 0.02], "gravity": [0, 0, -1],
                    "material": "rigid" }},
        "fingers": [ {{ "name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                       "material": {material}, "object_radius": {R},
                       "patch": {{"size": [{side}, {side}], "grid": [31, 31]}},
                       "friction": {{"mu": 0.0}} }} ]
    }}"#
    );
    Scene::from_json_str(&json).unwrap()
}

/// Two spherical fingertips of `material` pressed by `approach` (m) each into a weightless
/// rigid flat object between them, frictionless, 31 x 31 over `side`.
fn approach_pinch(material: &str, approach: f64, side: f64) -> Scene {
    let finger = |name: &str, x: f64, n: f64| {
        format!(
            r#"{{ "name": "{name}", "contact_point": [{x}, 0, 0], "normal": [{n}, 0, 0],
                "material": {material}, "tip_radius": {R},
                "patch": {{"size": [{side}, {side}], "grid": [31, 31]}},
                "friction": {{"mu": 0.0}}, "control": {{"approach_m": {approach}}} }}"#
        )
    };
    let json = format!(
        r#"{{
        "object": {{ "weight": 0, "center_of_mass": [0, 0, 0], "material": "rigid" }},
        "fingers": [ {}, {} ]
    }}"#,
        finger("left", -0.01, 1.0),
        finger("right", 0.01, -1.0)
    );
    Scene::from_json_str(&json).unwrap()
}

fn at(scene: &Scene, time: TimePoint) -> Solution {
    let model = GraspModel::from_scene(scene).unwrap();
    let s = solve_at(&model, SolveOptions::default(), time).unwrap();
    assert_eq!(
        s.solution.status,
        SolveStatus::Solved,
        "{:?}",
        s.solution.reason
    );
    s.solution
}

fn approach(sol: &Solution) -> f64 {
    -sol.rigid_displacement.unwrap().translation_m[2]
}

/// Position control on an elastic pinch against Hertz: each contact of a symmetric pinch
/// pressed by `d` carries `P = (4/3) E* R^(1/2) d^(3/2)`, `E* = E / (1 - nu^2)` against a rigid
/// object. Tolerance 1 %: the 31 x 31 grid's error (the Hertz check's, below 0.1 % on the
/// approach, 1.5 times that on the load through `d^(3/2)`).
#[test]
fn approach_control_meets_hertz() {
    let d: f64 = 2e-4;
    let e_star = E0 / (1.0 - NU * NU);
    let p = 4.0 / 3.0 * e_star * R.sqrt() * d.powf(1.5);
    let a = (R * d).sqrt();
    let elastic = format!(r#"{{"youngs_modulus": {E0}, "poisson_ratio": {NU}}}"#);
    let sol = at(
        &approach_pinch(&elastic, d, 2.4 * a),
        TimePoint::Instantaneous,
    );
    for f in &sol.fingers {
        eprintln!(
            "{}: P {:.6} N, Hertz {p:.6} N, approach {:e}",
            f.name, f.normal_force_n, f.approach_m
        );
        assert!((f.normal_force_n - p).abs() <= 0.01 * p);
        assert_eq!(f.approach_m, d);
    }
}

/// Lee and Radok under a held load, a standard linear solid and a two-term Prony series: the
/// approach at three decades of time (0.1 s to 100 s against relaxation times of 0.2 s to
/// 10 s) grows like `(E_0 J(t))^(2/3)` within 1 % (the stepping's error, second order in a
/// step of 18 % of its decade, and the grid's, which cancels in the ratio to the
/// instantaneous approach).
#[test]
fn a_held_load_creeps_as_lee_and_radok() {
    let p = 2.0;
    for law in [SLS, TWO_TERMS] {
        let j = creep(law, 200.0);
        let phi_inf = 1.0 / relaxation(law, f64::INFINITY);
        let side = 2.4 * hertz_radius(p) * phi_inf.cbrt();
        let scene = sphere_on_pad(&pad(law), p, side);
        let d0 = approach(&at(&scene, TimePoint::Instantaneous));
        for t in [0.1, 1.0, 10.0, 100.0] {
            let d = approach(&at(&scene, TimePoint::At { seconds: t }));
            let want = j(t).powf(2.0 / 3.0);
            eprintln!(
                "law {law:?}, t {t}: approach ratio {:.6}, Lee-Radok {want:.6}",
                d / d0
            );
            assert!((d / d0 - want).abs() <= 0.01 * want);
        }
        let relaxed = approach(&at(&scene, TimePoint::LongTerm));
        assert!((relaxed / d0 - phi_inf.powf(2.0 / 3.0)).abs() <= 0.01 * phi_inf.powf(2.0 / 3.0));
    }
}

/// Lee and Radok under a held approach: each contact of a pinch pressed by `d` relaxes like
/// `E(t) / E_0` within 1 % over three decades, both laws (the contact radius `(R d)^(1/2)`
/// does not change).
#[test]
fn a_held_approach_relaxes_as_lee_and_radok() {
    let d: f64 = 2e-4;
    for law in [SLS, TWO_TERMS] {
        let scene = approach_pinch(&pad(law), d, 2.4 * (R * d).sqrt());
        let p0 = at(&scene, TimePoint::Instantaneous).fingers[0].normal_force_n;
        for t in [0.1, 1.0, 10.0, 100.0] {
            let p = at(&scene, TimePoint::At { seconds: t }).fingers[0].normal_force_n;
            let want = relaxation(law, t);
            eprintln!(
                "law {law:?}, t {t}: load ratio {:.6}, Lee-Radok {want:.6}",
                p / p0
            );
            assert!((p / p0 - want).abs() <= 0.01 * want);
        }
    }
}
