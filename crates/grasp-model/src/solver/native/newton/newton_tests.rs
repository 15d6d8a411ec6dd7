//! Unit tests of the Newton core (linearisation, reduced factor, one Newton step) on a
//! two-element problem whose answer statics alone fix: a frictionless flat pad of two elements
//! (centres at `x = -h/2` and `x = +h/2`) under an object of weight `W` whose centre of mass
//! lies at `x = c`. Force and moment balance give `F_left + F_right = W` and
//! `(h/2)(F_right - F_left) = W c`, so `F_right = W (1/2 + c/h)`, `F_left = W (1/2 - c/h)`
//! whatever the compliance: the problem is statically determinate.

use crate::model::grasp_model::GraspModel;
use crate::program::cone_program::ConeProgram;
use crate::scene::scene_format::Scene;
use crate::solver::iterate::Iterate;
use crate::solver::native::native_result::NativeStatus;
use crate::solver::native::NativeSolver;

use super::linearisation::{cold_pattern, linearise};
use super::reduced_factor::{key_of, ReducedFactor};
use super::semismooth_newton::{dual_of, Limits, FORCING_MAX};

/// Element spacing `h`, m (the pad is `2h x h` with a 2 x 1 grid).
const H_M: f64 = 1e-3;
/// Weight `W`, N.
const WEIGHT_N: f64 = 2.0;

/// The pad under an object with its centre of mass at `x = com_x_m`.
fn pad(com_x_m: f64) -> GraspModel {
    let text = format!(
        r#"{{
        "planar": null,
        "object": {{"weight": {WEIGHT_N}, "center_of_mass": [{com_x_m}, 0, 0.005],
                    "gravity": [0, 0, -1],
                    "material": {{"youngs_modulus": 2e11, "poisson_ratio": 0.3}}}},
        "fingers": [{{"name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                     "tangent": [1, 0, 0],
                     "material": {{"youngs_modulus": 1e6, "poisson_ratio": 0.45}},
                     "tip_radius": null, "object_radius": null,
                     "patch": {{"size": [{}, {H_M}], "grid": [2, 1]}},
                     "friction": {{"mu": 0.0}}, "control": "held"}}],
        "model": "energy"
    }}"#,
        2.0 * H_M
    );
    let scene = Scene::from_json_str(&text).expect("a valid scene");
    GraspModel::from_scene(&scene).expect("a usable model")
}

/// The statics answer `(F_left, F_right)`, N.
fn statics(com_x_m: f64) -> [f64; 2] {
    let r = WEIGHT_N * (0.5 + com_x_m / H_M);
    [WEIGHT_N - r, r]
}

/// From a cold start (both elements in contact, sticking) the first Newton step solves
/// `P dx + E' dlambda = -y`, `E dx = e` over both elements: with two elements and two
/// independent equilibrium rows the equality rows alone fix `x`, so that one step lands on the
/// answer and the solve ends there. Forces to 1e-12 of the weight (round-off of a 2 x 2
/// system and the row reduction).
#[test]
fn one_newton_step_solves_a_statically_determinate_pad() {
    for c in [0.0, 2e-4, -3e-4] {
        let model = pad(c);
        let program = ConeProgram::with_scene_loads(&model);
        let mut native = NativeSolver::new(&model, &program);
        let limits = Limits {
            tolerance: 1e-12,
            max_iterations: 10,
            forcing: FORCING_MAX,
            progress: None,
        };
        let result = native.solve(&program, &[], limits);
        assert_eq!(result.status, NativeStatus::Converged, "c = {c}");
        assert_eq!(
            result.iterations, 1,
            "c = {c}: the all-stick step is the answer"
        );
        let fu = model.scales.element_force_n;
        let got = [result.iterate.x[0] * fu, result.iterate.x[1] * fu];
        let want = statics(c);
        for k in 0..2 {
            assert!(
                (got[k] - want[k]).abs() < 1e-12 * WEIGHT_N,
                "c = {c}: element {k}: {} vs {}",
                got[k],
                want[k]
            );
        }
    }
}

/// At the answer the natural residual vanishes and both directions are free (`theta = 1`);
/// with the left element's force pushed negative, its projection clips it to zero and its
/// direction becomes fixed with `phi` equal to the clipped amount.
#[test]
fn linearisation_classifies_free_and_fixed_directions() {
    let model = pad(2e-4);
    let program = ConeProgram::with_scene_loads(&model);
    let mut native = NativeSolver::new(&model, &program);
    let limits = Limits {
        tolerance: 1e-12,
        max_iterations: 10,
        forcing: FORCING_MAX,
        progress: None,
    };
    let solved = native.solve(&program, &[], limits).iterate;
    let blocks = native.blocks();
    let y = dual_of(blocks, &program, &solved.x, &solved.lambda);
    let lin = linearise(&blocks[0], &program.blocks[0].cone, &solved.x, &y);
    assert!(lin.residual_max < 1e-12, "residual {}", lin.residual_max);
    assert_eq!((lin.free.len(), lin.fixed.len()), (2, 0));
    assert!(lin.free.iter().all(|d| d.theta == 1.0));

    // Push the left element below zero with y = 0: Proj(x - gamma 0) clips it.
    let x = vec![-0.5, solved.x[1]];
    let lin = linearise(&blocks[0], &program.blocks[0].cone, &x, &[0.0, 0.0]);
    assert_eq!((lin.free.len(), lin.fixed.len()), (1, 1));
    assert_eq!(lin.fixed[0].element, 0);
    assert_eq!(lin.fixed[0].phi, -0.5, "Phi = x - Proj(x) = -0.5 - 0");
    assert_eq!(lin.residual_max, 0.5);
}

/// The reduced matrix over both (free, `theta = 1`) directions is the scaled compliance block
/// `P` itself, so its factor satisfies `L L' = P` (to 1e-14 relative: a 2 x 2 Cholesky), and
/// `W = L^-1 E'` satisfies `L W = E'` on the equality rows.
#[test]
fn reduced_factor_reproduces_the_block_and_the_equality_rows() {
    let model = pad(0.0);
    let program = ConeProgram::with_scene_loads(&model);
    let native = NativeSolver::new(&model, &program);
    let block = &native.blocks()[0];
    let lin = cold_pattern(block, &[0.0, 0.0], &[true, true]);
    let key = key_of(&lin.free);
    let factor = ReducedFactor::new(block, &lin.free, &lin.fixed, key, None).expect("SPD");
    // Columns of P from products with unit vectors.
    let column = |c: usize| {
        let mut e = [0.0; 2];
        e[c] = 1.0;
        let mut out = [0.0; 2];
        block.apply(&e, &mut out);
        out
    };
    let p = [column(0), column(1)];
    for (c, column_c) in p.iter().enumerate() {
        // (L L')^-1 P e_c = e_c: a forward and a backward triangular solve.
        let mut v = column_c.to_vec();
        factor.forward(&mut v);
        factor.backward(&mut v);
        for (r, &vr) in v.iter().enumerate() {
            let want = if r == c { 1.0 } else { 0.0 };
            assert!((vr - want).abs() < 1e-14, "(L L')^-1 P e_{c}: [{r}] = {vr}");
        }
    }
    // W = L^-1 E': L^-T W then equals (L L')^-1 E' = P^-1 E'; so P L^-T W = E'.
    let m = program.equality_rows();
    for row in 0..m {
        let mut v: Vec<f64> = (0..2).map(|a| factor.w[(a, row)]).collect();
        factor.backward(&mut v);
        let mut pv = [0.0; 2];
        block.apply(&v, &mut pv);
        for (c, &got) in pv.iter().enumerate() {
            let want = block.equality(row, c);
            assert!(
                (got - want).abs() < 1e-12 * (1.0 + want.abs()),
                "row {row}, column {c}: {got} vs {want}"
            );
        }
    }
}

/// The limits of the pad's solves: a tight tolerance, a few steps.
const LIMITS: Limits = Limits {
    tolerance: 1e-12,
    max_iterations: 10,
    forcing: FORCING_MAX,
    progress: None,
};

/// The pad with its centre of mass at `x = -1e-4` m, its program and a native solver.
fn pad_and_solver() -> (GraspModel, ConeProgram, NativeSolver) {
    let model = pad(-1e-4);
    let program = ConeProgram::with_scene_loads(&model);
    let native = NativeSolver::new(&model, &program);
    (model, program, native)
}

/// Warm-started from the answer, the solve takes no Newton step.
#[test]
fn a_start_at_the_answer_takes_no_step() {
    let (_model, program, mut native) = pad_and_solver();
    let answer: Iterate = native.solve(&program, &[], LIMITS).iterate;
    let again = native.solve(&program, &[&answer], LIMITS);
    assert_eq!(again.status, NativeStatus::Converged);
    assert_eq!(again.iterations, 0);
    assert_eq!(again.iterate, answer);
}

/// A start with numbers that are not finite (an interior-point answer that lost positive
/// definiteness, say) is never reported converged: its residuals are not finite, and the
/// iteration starts again from scratch, converging to the statics answer (to 1e-9 of `W`:
/// the solver's tolerance on a 2-element problem), or stalls; either way no NaN is an answer.
#[test]
fn a_start_with_numbers_that_are_not_finite_is_never_converged() {
    let (model, program, mut native) = pad_and_solver();
    let answer: Iterate = native.solve(&program, &[], LIMITS).iterate;
    for bad in [f64::NAN, f64::INFINITY] {
        let mut start = answer.clone();
        start.x[0] = bad;
        let r = native.solve(&program, &[&start], LIMITS);
        let finite = r
            .iterate
            .x
            .iter()
            .chain(&r.iterate.lambda)
            .all(|v| v.is_finite());
        assert!(
            r.status != NativeStatus::Converged || finite,
            "{bad}: {r:?}"
        );
        if r.status == NativeStatus::Converged {
            let [left, right] = statics(-1e-4);
            let fu = model.scales.element_force_n;
            assert!(
                (r.iterate.x[0] * fu - left).abs() < 1e-9 * WEIGHT_N,
                "{bad}: {r:?}"
            );
            assert!(
                (r.iterate.x[1] * fu - right).abs() < 1e-9 * WEIGHT_N,
                "{bad}: {r:?}"
            );
        }
    }
}

/// Coefficient of friction of the rough pad.
const MU: f64 = 0.2;

/// The pad with friction `MU`, the same material on both sides (no normal/tangential coupling)
/// and the centre of mass at `(com_x_m, 0, 0)` on the contact plane, under gravity tilted by
/// `tilt` (sine of its angle from `-z`) towards `-x`.
fn rough_pad(com_x_m: f64, tilt: f64) -> GraspModel {
    let (gx, gz) = (-tilt, -(1.0 - tilt * tilt).sqrt());
    let text = format!(
        r#"{{
        "planar": null,
        "object": {{"weight": {WEIGHT_N}, "center_of_mass": [{com_x_m}, 0, 0],
                    "gravity": [{gx}, 0, {gz}],
                    "material": {{"youngs_modulus": 2e11, "poisson_ratio": 0.3}}}},
        "fingers": [{{"name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
                     "tangent": [1, 0, 0],
                     "material": {{"youngs_modulus": 2e11, "poisson_ratio": 0.3}},
                     "tip_radius": null, "object_radius": null,
                     "patch": {{"size": [{}, {H_M}], "grid": [2, 1]}},
                     "friction": {{"mu": {MU}}}, "control": "held"}}],
        "model": "energy"
    }}"#,
        2.0 * H_M
    );
    let scene = Scene::from_json_str(&text).expect("a valid scene");
    GraspModel::from_scene(&scene).expect("a usable model")
}

/// A frictional pad with one element slipping and one sticking, against its known answer.
///
/// With the centre of mass on the contact plane at `x = c`, the tangential load makes no moment
/// about the pad, so statics alone still fix the normal forces: `F_left, F_right =
/// W_n (1/2 -+ c/h)` (`W_n` the weight's normal part). The tangential load `Q` (the weight's
/// part along `x`) is shared: sticking, both elements move with the rigid object, and with the
/// same material on both sides (no normal/tangential coupling) the two identical elements'
/// tangential compliance is symmetric, so each would carry `Q/2`. With `c = 0.3 h`, a tilt of
/// 0.1 and `mu = 0.2`, the left element's cone (`mu F_left = 0.0398 W`) is smaller than
/// `Q/2 = 0.05 W`: it slips at its cone, `|G_left| = mu F_left`, and the right element sticks
/// inside its own (`Q - mu F_left = 0.060 W < mu F_right = 0.159 W`). Forces to `1e-12` of the
/// weight: once the stick / slip pattern is found, a Newton step solves the linear KKT system
/// of that pattern exactly up to round-off (a 6 x 6 system of order-1 scaled entries), and the
/// solve stops at a natural residual of `1e-12`.
#[test]
fn a_rough_pad_slips_on_its_lighter_element_and_sticks_on_the_other() {
    let (c, tilt) = (0.3 * H_M, 0.1);
    let model = rough_pad(c, tilt);
    let program = ConeProgram::with_scene_loads(&model);
    let mut native = NativeSolver::new(&model, &program);
    let limits = Limits {
        tolerance: 1e-12,
        max_iterations: 30,
        forcing: FORCING_MAX,
        progress: None,
    };
    let result = native.solve(&program, &[], limits);
    assert_eq!(result.status, NativeStatus::Converged);
    let block = &native.blocks()[0];
    let fu = model.scales.element_force_n;
    let force = |k: usize, c: usize| result.iterate.x[block.offset + block.index(k, c)] * fu;
    let normal = WEIGHT_N * (1.0 - tilt * tilt).sqrt();
    let load = WEIGHT_N * tilt;
    let f_left = normal * (0.5 - c / H_M);
    let f_right = normal * (0.5 + c / H_M);
    // The object pushes the pad towards -x, so the pad's friction on it points along +x.
    let want = [
        [f_left, MU * f_left, 0.0],
        [f_right, load - MU * f_left, 0.0],
    ];
    for (k, want_k) in want.iter().enumerate() {
        for (c, &w) in want_k.iter().enumerate() {
            let got = force(k, c);
            assert!(
                (got - w).abs() < 1e-12 * WEIGHT_N,
                "element {k}, component {c}: {got} vs {w}"
            );
        }
    }
    // The pattern: the right element well inside its cone (the left one is on it, above).
    assert!(force(1, 1) < 0.5 * MU * force(1, 0));
}
