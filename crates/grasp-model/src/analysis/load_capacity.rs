//! The load capacity of a grasp along a disturbance direction: the largest magnitude `s` (N)
//! for which some contact forces within the friction cones balance the step's external wrench
//! plus `s` times the direction, every force-controlled finger carrying its commanded normal
//! load (the equilibrium rows of thesis eqs. 48-49 with the cones of eqs. 21-24; a linear
//! program in the plane, a second-order cone program in 3-D). Beyond it the grasp program has
//! no feasible point, so no model (energy, coulomb, layered or viscoelastic: their cones are
//! these or smaller) holds there, and a margin's search knows without a solve that a trial
//! beyond it fails. Those trials are the costly ones: at the edge of equilibrium the native
//! solver stalls and the fallback's interior-point method takes hundreds of iterations to
//! give up.
//!
//! The proof is a Farkas certificate: multipliers `y` of the equality rows `E x = e(s)`,
//! `e(s) = e0 + s e1`, with `g = E'y` in the dual cones (`g_F >= mu ||g_G||` per element;
//! `g_F >= 0` frictionless). For every `x` in the cones with `E x = e(s)`, `y'e(s) = g'x >= 0`,
//! so `y'e0 + s y'e1 < 0` proves that no equilibrium exists. Clarabel's dual of the capacity
//! program gives the equilibrium rows' multipliers (the object's escape motion); each load
//! row's multiplier is then fitted here, the smallest that puts its finger's elements inside
//! the dual cones, so the proof is checked from `E`, not taken from the solver. `E` depends
//! on the model only, so the certificate is kept along a loading path while the loads change:
//! each step's bound costs two right-hand sides and stays tight while the escape motion stays
//! the best one.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::Vector3;

use crate::model::equilibrium::Wrench;
use crate::model::grasp_model::{Control, GraspModel};
use crate::program::cone_program::ConeProgram;
use crate::program::cones::element_set::ElementSet;
use crate::program::cones::finger_cones::ConeLaw;
use crate::solve::step_inputs::StepInputs;
use crate::solver::clarabel::{settings, ClarabelForm};

/// Unknowns above which no capacity is sought: the capacity program would cost more than
/// the trials it spares (a fine patch's margins are searched as before).
const MAX_UNKNOWNS: usize = 20_000;

/// Clarabel's tolerance on the capacity program. Only the bound's tightness depends on it:
/// the bound itself is proved from `E` and `y` (module docs).
const TOLERANCE: f64 = 1e-9;

/// Clarabel's iteration limit on the capacity program.
const MAX_ITERATIONS: u32 = 100;

/// A proof of the largest magnitude at which a disturbance can be balanced (module docs).
#[derive(Clone)]
pub(crate) struct LoadCapacity {
    /// The program of the associated cones (its right-hand side is rewritten per bound).
    program: ConeProgram,
    /// Multipliers of the equilibrium rows.
    y: Vec<f64>,
    /// Per load row (in the program's order), the smallest multiplier that puts every
    /// element of the finger inside the dual cones.
    load_multipliers: Vec<f64>,
}

/// A disturbance per newton of its magnitude: a force at the centre of mass and a couple.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct UnitDisturbance {
    /// The force, N per N (world).
    pub force_n: Vector3<f64>,
    /// The couple, N m per N (world).
    pub torque_nm: Vector3<f64>,
}

impl UnitDisturbance {
    /// Its wrench about `O` (N, N m per newton of magnitude) on `model`.
    fn wrench(&self, model: &GraspModel) -> Wrench {
        model.wrench_at_center_of_mass(&self.force_n, &self.torque_nm)
    }
}

impl LoadCapacity {
    /// A certificate for the disturbance `per_newton` of `model` under `inputs`, searched up
    /// to `cap_n` newtons; `None` where none is sought (a fine patch, a friction coefficient
    /// that depends on the load) or none was found.
    pub(crate) fn find(
        model: &GraspModel,
        inputs: &StepInputs,
        per_newton: &UnitDisturbance,
        cap_n: f64,
    ) -> Option<LoadCapacity> {
        let mu = constant_mu(model)?;
        let mut program = ConeProgram::assemble(model, &inputs.loads_n, ConeLaw::Associated, &mu);
        let e1 = rhs(&mut program, model, &per_newton.wrench(model), None);
        // The right-hand side left in the program, which the capacity program takes: e0.
        rhs(
            &mut program,
            model,
            &inputs.external_wrench(model),
            Some(inputs),
        );
        if program.unbalanced.is_some() {
            return None;
        }
        let mut y = capacity_multipliers(&program, &e1, cap_n)?;
        y.truncate(program.equilibrium_rows());
        let load_multipliers = load_multipliers(model, &program, &y)?;
        Some(LoadCapacity {
            program,
            y,
            load_multipliers,
        })
    }

    /// The magnitude (N) from which the disturbance has no equilibrium under `inputs` by this
    /// certificate (infinite when it proves none); `model` must be the one it was found for.
    pub(crate) fn bound_n(
        &mut self,
        model: &GraspModel,
        inputs: &StepInputs,
        per_newton: &UnitDisturbance,
    ) -> f64 {
        let p = &mut self.program;
        let e1 = rhs(p, model, &per_newton.wrench(model), None);
        let e0 = rhs(p, model, &inputs.external_wrench(model), Some(inputs));
        let loads: f64 = p
            .load_rows
            .iter()
            .zip(&self.load_multipliers)
            .map(|(r, y)| y * e0[r.row])
            .sum();
        let (a, b) = (dot(&self.y, &e1), dot(&self.y, &e0) + loads);
        let bound = b / -a;
        // A proof needs `y'e1 < 0`; the bound is raised by a relative 1e-12 for the sums'
        // rounding, so that it stays on the side of holding.
        if a < 0.0 && bound.is_finite() {
            bound.max(0.0) * (1.0 + 1e-12) + f64::MIN_POSITIVE
        } else {
            f64::INFINITY
        }
    }
}

/// Each finger's friction coefficient when every one is constant (frictionless fingers
/// included), else `None`.
fn constant_mu(model: &GraspModel) -> Option<Vec<f64>> {
    if model.n_unknowns > MAX_UNKNOWNS {
        return None;
    }
    model
        .fingers
        .iter()
        .map(|f| f.friction.is_constant().then(|| f.mu_at(0.0)))
        .collect()
}

/// The right-hand side `e` of `program` for the external wrench `wrench` and the loads of
/// `inputs` (none: zero loads).
fn rhs(
    program: &mut ConeProgram,
    model: &GraspModel,
    wrench: &Wrench,
    inputs: Option<&StepInputs>,
) -> Vec<f64> {
    let zeros = vec![0.0; program.load_rows.len()];
    program.set_external_wrench(model, wrench);
    program.set_loads(model, inputs.map_or(&zeros, |i| &i.loads_n));
    program.equality_rhs.clone()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The equality multipliers of the capacity program `maximise s subject to E x - s e1 = e,
/// x in the cones, 0 <= s <= cap` (Clarabel), when it is solved.
fn capacity_multipliers(program: &ConeProgram, e1: &[f64], cap_n: f64) -> Option<Vec<f64>> {
    let form = ClarabelForm::constraints(program, 0.0);
    let (m, n) = (form.a.m, form.a.n);
    let mut a = form.a.clone();
    let column: Vec<(usize, f64)> = (0..program.equality_rows())
        .filter(|&r| e1[r] != 0.0)
        .map(|r| (r, -e1[r]))
        .chain([(m, -1.0), (m + 1, 1.0)])
        .collect();
    a.rowval.extend(column.iter().map(|c| c.0));
    a.nzval.extend(column.iter().map(|c| c.1));
    a.colptr.push(a.rowval.len());
    a.m = m + 2;
    a.n = n + 1;
    let mut b = form.b.clone();
    b.extend([0.0, cap_n]);
    let mut q = vec![0.0; n + 1];
    q[n] = -1.0;
    let mut cones = form.cones.clone();
    cones.push(SupportedConeT::NonnegativeConeT(2));
    let p = CscMatrix::zeros((n + 1, n + 1));
    let settings = settings(TOLERANCE, MAX_ITERATIONS, f64::INFINITY).ok()?;
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    let solved = matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    );
    let y = sol.z[..program.equality_rows()].to_vec();
    (solved && y.iter().all(|v| v.is_finite())).then_some(y)
}

/// Per load row, the multiplier that completes the equilibrium multipliers `y` into a
/// certificate: the smallest that puts every element of its finger inside the dual cones
/// (each load row adds its multiplier to the normal part of its finger's columns, and its
/// right-hand side, the load, is not negative, so the smallest gives the tightest bound);
/// `None` when a finger without a load row (held or moved by an approach, its normal forces
/// unbounded) is outside them at all: then `y` proves nothing.
fn load_multipliers(model: &GraspModel, program: &ConeProgram, y: &[f64]) -> Option<Vec<f64>> {
    let rows = program.equilibrium_rows();
    let g = program.equality.rows(0, rows).transpose() * nalgebra::DVector::from_column_slice(y);
    let mut multipliers = Vec::with_capacity(program.load_rows.len());
    for (blk, f) in program.blocks.iter().zip(&model.fingers) {
        let ne = blk.elements;
        let need = (0..ne)
            .map(|k| {
                let v = (1..=blk.n_tangential)
                    .map(|c| g[blk.offset + c * ne + k].powi(2))
                    .sum::<f64>()
                    .sqrt();
                blk.cone.element(k).dual_floor(v) - g[blk.offset + k]
            })
            .fold(f64::NEG_INFINITY, f64::max);
        match f.control {
            Control::NormalLoad { .. } => multipliers.push(need),
            _ if need > 0.0 || need.is_nan() => return None,
            _ => {}
        }
    }
    Some(multipliers)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    /// The coulomb plate: four force-controlled fingers (mu 0.4) in two opposed pairs at
    /// `x = -/+0.1 m`, `z = +/-0.02 m`, a weight of 4.448 N along `-z`.
    fn plate() -> GraspModel {
        let text = include_str!("../../../../examples/plate_handoff_coulomb.json");
        GraspModel::from_scene(&Scene::from_json_str(text).unwrap()).unwrap()
    }

    /// The plate's capacity along `-z` and `+z` is its friction, `mu` times the sum of the
    /// loads, less or plus the weight: with loads equal within each pair, the friction forces
    /// of a pair (at `x = -/+0.1 m`) and their normal forces (at the same height) balance their
    /// own moments, so every element can slide at once. The bound is proved from Clarabel's
    /// multipliers, so it is within Clarabel's tolerance (1e-9) of the capacity: 1e-7 relative
    /// allows for the scaling of the rows. A certificate found at one set of loads is kept for
    /// the others, as along a hand-off: its load multipliers are fitted to each finger's cones
    /// afresh, and its escape motion (the equilibrium multipliers, a slide along `z`) stays the
    /// best one, so it stays exact.
    #[test]
    fn the_plates_capacity_is_its_friction_less_or_plus_its_weight() {
        let model = plate();
        let (mu, weight_n) = (0.4, 4.448);
        let zero = Vector3::zeros();
        for sign in [-1.0, 1.0] {
            let down = UnitDisturbance {
                force_n: Vector3::new(0.0, 0.0, sign),
                torque_nm: zero,
            };
            let first = StepInputs::loads(vec![8.0, 8.0, 0.0, 0.0]);
            let mut kept = LoadCapacity::find(&model, &first, &down, 1e3).unwrap();
            for loads in [
                [8.0, 8.0, 0.0, 0.0],
                [8.0, 8.0, 8.0, 8.0],
                [2.0, 2.0, 6.0, 6.0],
            ] {
                let inputs = StepInputs::loads(loads.to_vec());
                let want = mu * loads.iter().sum::<f64>() + sign * weight_n;
                let mut found = LoadCapacity::find(&model, &inputs, &down, 1e3).unwrap();
                let got = found.bound_n(&model, &inputs, &down);
                let what = format!("along {sign} z at loads {loads:?}");
                assert!(
                    (got - want).abs() <= 1e-7 * want,
                    "{what}: bound {got} N, capacity {want} N"
                );
                let again = kept.bound_n(&model, &inputs, &down);
                assert!(
                    (again - want).abs() <= 1e-7 * want,
                    "{what}: kept bound {again} N"
                );
            }
        }
    }

    /// A push along the pairs' squeeze axis meets only the commanded normal loads, which
    /// balance each other: no magnitude above 0 has an equilibrium, and the certificate says
    /// so (to Clarabel's tolerance on the capacity program, 1e-9 of the loads).
    #[test]
    fn a_push_along_the_squeeze_axis_has_no_capacity() {
        let model = plate();
        let inputs = StepInputs::loads(vec![8.0, 8.0, 8.0, 8.0]);
        let along_x = UnitDisturbance {
            force_n: Vector3::new(1.0, 0.0, 0.0),
            torque_nm: Vector3::zeros(),
        };
        let mut c = LoadCapacity::find(&model, &inputs, &along_x, 1e3).unwrap();
        let bound = c.bound_n(&model, &inputs, &along_x);
        assert!(
            bound <= 1e-6,
            "a push along the squeeze axis is bounded at {bound} N"
        );
    }
}
