//! The sequential (SQP-style) solve: a sequence of convex cone programs iterated to a fixed
//! point (model.md, "coulomb" and "Load-dependent friction"; thesis section 2.6).
//!
//! - **coulomb**: each iterate solves the program with Tresca cones `||G_k|| <= r_k`,
//!   `r_k = mu_i(P_i) F_k` from the previous iterate (normal forces `F_k`, finger loads `P_i`),
//!   and the slip memory `m` in the linear cost. The first iterate comes from the previous
//!   step's forces (warm start; a force-controlled finger's forces are rescaled to its new
//!   load) or, without them, from an energy-model solve (cold start). A warm start that proves
//!   infeasible is retried cold once.
//! - **energy** with a load-dependent `mu`: each iterate solves the energy program with
//!   `mu_i` frozen at the previous iterate's finger load.
//!
//! Converged when no element normal force changes by more than `sequential_tolerance * Fu`
//! between iterates. Outcomes: converged; no equilibrium (for coulomb, with the fingers that
//! lack grip, read from the infeasibility certificate); no convergence within the iteration
//! limit, with the last change.

use std::time::Instant;

use crate::cone_program::{ConeLaw, ConeProgram, ConeRows};
use crate::contact_state::ContactState;
use crate::error::ModelError;
use crate::grasp_model::{Control, GraspModel};
use crate::residuals::FrictionRule;
use crate::scene::ModelKind;
use crate::solution::{SequentialReport, Solution, SolveStatus, SolverStats};
use crate::solve::{
    build_solution, escape_reason, failed, record_state, rigid_from_multipliers, Build,
    GraspSolver, ProgramSolver, Raw,
};

/// Smallest Tresca radius, in element force units `Fu`. A cone of radius 0 has no interior
/// and stalls the interior-point method (measured: "almost solved" on the Cattaneo case of
/// `tests/cattaneo_mindlin.rs` at `Q = 0.5 mu P`); with this floor an unloaded element can carry
/// at most `1e-8 Fu` of friction, which shows as a cone violation of that size.
pub const RADIUS_FLOOR: f64 = 1e-8;

/// A first guess of each finger's total normal load, N: the prescribed load of a
/// force-controlled finger, an equal share of the load scale for a held one.
pub fn guess_loads(model: &GraspModel, loads_n: &[f64]) -> Vec<f64> {
    let share = model.scales.load_n / model.fingers.len().max(1) as f64;
    let mut j = 0;
    model
        .fingers
        .iter()
        .map(|f| match f.control {
            Control::NormalLoad { .. } => {
                j += 1;
                loads_n.get(j - 1).copied().unwrap_or(share)
            }
            Control::Held => share,
        })
        .collect()
}

/// Smallest frozen friction coefficient of a frictional finger. The energy model's cone
/// `(mu F, G)` implies `F >= 0` only while `mu > 0`, and a very thin cone stalls the
/// interior-point method: with a floor of 1e-6, the unloaded finger f4 of the plate example
/// under the law of thesis eq. (40) (`mu(0) = 0`) came back "almost solved" with a negative
/// load. A finger frozen at this floor carries at most `1e-3` of its normal force as friction.
pub const MU_FLOOR: f64 = 1e-3;

/// Each finger's friction coefficient to freeze at finger loads `p_n` (N): its law at that
/// load, at least [`MU_FLOOR`]; 0 for frictionless fingers.
pub fn mu_at(model: &GraspModel, p_n: &[f64]) -> Vec<f64> {
    model
        .fingers
        .iter()
        .zip(p_n)
        .map(|(f, &p)| {
            if f.n_tangential == 0 {
                0.0
            } else {
                f.friction.mu_at(p).max(MU_FLOOR)
            }
        })
        .collect()
}

/// Element normal forces per finger (N) from a scaled primal.
fn normal_forces(model: &GraspModel, x_scaled: &[f64]) -> Vec<Vec<f64>> {
    let fu = model.scales.element_force_n;
    model
        .fingers
        .iter()
        .map(|f| {
            x_scaled[f.offset..f.offset + f.patch.len()]
                .iter()
                .map(|v| v * fu)
                .collect()
        })
        .collect()
}

fn totals(forces: &[Vec<f64>]) -> Vec<f64> {
    forces.iter().map(|f| f.iter().sum()).collect()
}

fn largest_change(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The previous step's forces as a first iterate, rescaled to the new loads of force-controlled
/// fingers; `None` when the state has none or a force-controlled finger goes from no load to
/// some (its distribution is then unknown).
fn warm_forces(model: &GraspModel, loads_n: &[f64], state: &ContactState) -> Option<Vec<Vec<f64>>> {
    let mut out = Vec::with_capacity(model.fingers.len());
    let mut j = 0;
    for (f, s) in model.fingers.iter().zip(&state.fingers) {
        let prev = s.normal_forces_n.as_ref()?;
        match f.control {
            Control::Held => out.push(prev.clone()),
            Control::NormalLoad { .. } => {
                let p_new = loads_n[j];
                j += 1;
                let p_old: f64 = prev.iter().sum();
                if p_old > 1e-12 * model.scales.load_n {
                    out.push(prev.iter().map(|v| v * p_new / p_old).collect());
                } else if p_new <= 1e-12 * model.scales.load_n {
                    out.push(vec![0.0; prev.len()]);
                } else {
                    return None;
                }
            }
        }
    }
    Some(out)
}

/// Which fingers slide in the infeasibility certificate of a Tresca program, with their share
/// of the total certificate slip.
fn sliding_fingers(model: &GraspModel, program: &ConeProgram, z: &[f64]) -> Vec<(String, f64)> {
    let mut per: Vec<f64> = vec![0.0; model.fingers.len()];
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        per[i] = match program.cone_rows[i] {
            ConeRows::PlanarPairs(r) if f.n_tangential == 1 => (0..ne)
                .map(|k| (z[r + 2 * k] - z[r + 2 * k + 1]).abs())
                .sum(),
            ConeRows::SecondOrder(r) if f.n_tangential == 2 => (0..ne)
                .map(|k| z[r + 3 * k + 1].hypot(z[r + 3 * k + 2]))
                .sum(),
            _ => 0.0,
        };
    }
    let total: f64 = per.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let mut v: Vec<(String, f64)> = model
        .fingers
        .iter()
        .zip(&per)
        .filter(|(_, &s)| s > 0.02 * total)
        .map(|(f, &s)| (f.name.clone(), s / total))
        .collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1));
    v
}

/// The reason of an infeasible Tresca iterate: too little normal force, which fingers slide,
/// and how the object would move.
fn cannot_hold_reason(model: &GraspModel, program: &ConeProgram, z: &[f64]) -> String {
    let mut s = String::from(
        "cannot hold: the commanded loads give too little normal force for Coulomb friction",
    );
    let sliding = sliding_fingers(model, program, z);
    if !sliding.is_empty() {
        let list: Vec<String> = sliding
            .iter()
            .map(|(n, share)| format!("{n} ({:.0} % of the slip)", share * 100.0))
            .collect();
        s.push_str(&format!("; lacking grip: {}", list.join(", ")));
    }
    let (t_o, theta) = rigid_from_multipliers(model, program, z);
    let t = t_o + theta.cross(&(model.center_of_mass_m - model.reference_point_m));
    let scale = t.norm().max(theta.norm() * model.scales.length_m);
    if scale > 0.0 && scale.is_finite() && t.norm() > 1e-6 * scale {
        let d = t.normalize();
        s.push_str(&format!(
            "; the object would slide along [{:.3}, {:.3}, {:.3}]",
            d.x, d.y, d.z
        ));
    }
    s.push_str("; raise the normal load of the fingers lacking grip (or mu)");
    s
}

/// Cold start of the coulomb model: the energy model's forces (same loads and memory).
fn cold_start(
    solver: &mut GraspSolver,
    model: &GraspModel,
    loads_n: &[f64],
    memory: &[Vec<[f64; 2]>],
    counters: &mut (u32, f64),
) -> Result<Result<Vec<Vec<f64>>, (SolveStatus, String)>, ModelError> {
    let settings = solver.settings();
    let guess_mu = mu_at(model, &guess_loads(model, loads_n));
    let start = solver.start.get_or_insert_with(|| {
        ProgramSolver::new(ConeProgram::assemble(
            model,
            loads_n,
            ConeLaw::Associated,
            &guess_mu,
        ))
    });
    start.program.set_loads(model, loads_n);
    start.a_changed |= start.program.set_mu(&guess_mu);
    start.program.set_slip_memory(model, memory);
    start.q_changed = true;
    let (raw, it, time) = start.run(&settings)?;
    counters.0 += it;
    counters.1 += time;
    Ok(match raw {
        Raw::Solved { x, .. } => Ok(normal_forces(model, &x)),
        // Not even the energy model's friction holds the object: Coulomb friction cannot.
        Raw::Infeasible { z } => Err((
            SolveStatus::NoEquilibrium,
            cannot_hold_reason(model, &start.program, &z),
        )),
        Raw::Failed { reason } => Err((SolveStatus::NoConvergence, reason)),
    })
}

/// Runs the sequential solve of one step (see the module docs).
pub(crate) fn solve_sequential(
    solver: &mut GraspSolver,
    model: &GraspModel,
    loads_n: &[f64],
    state: &mut ContactState,
    stats0: SolverStats,
    start: Instant,
) -> Result<Solution, ModelError> {
    let opts = solver.options;
    let settings = solver.settings();
    let coulomb = model.kind == ModelKind::Coulomb;
    let tol_n = opts.sequential_tolerance * model.scales.element_force_n;
    let memory = state.slip_memory_m();
    let mut counters = (0_u32, 0.0_f64);
    let mut report = SequentialReport {
        iterations: 0,
        last_change_n: f64::INFINITY,
        tolerance_n: tol_n,
        converged: false,
        warm_started: false,
        cold_restarts: 0,
    };
    let fail = |status, reason: String, counters: (u32, f64), report: SequentialReport| {
        let mut s = failed(
            model,
            status,
            reason,
            start,
            SolverStats {
                iterations: counters.0,
                solver_time_s: counters.1,
                ..stats0
            },
        );
        s.sequential = Some(report);
        s
    };
    if coulomb {
        solver.main.program.set_slip_memory(model, &memory);
        solver.main.q_changed = true;
    }

    // First iterate.
    let warm = if opts.warm_start {
        warm_forces(model, loads_n, state)
    } else {
        None
    };
    let mut forces: Option<Vec<Vec<f64>>> = warm;
    report.warm_started = forces.is_some();
    let mut loads_prev: Vec<f64> = match (&forces, coulomb) {
        (Some(f), _) => totals(f),
        (None, false) => guess_loads(model, loads_n),
        (None, true) => Vec::new(),
    };
    if coulomb && forces.is_none() {
        match cold_start(solver, model, loads_n, &memory, &mut counters)? {
            Ok(f) => {
                loads_prev = totals(&f);
                forces = Some(f);
            }
            Err((status, reason)) => return Ok(fail(status, reason, counters, report)),
        }
    }

    let mut j = 0;
    loop {
        j += 1;
        report.iterations = j;
        let mu = mu_at(model, &loads_prev);
        let radii: Option<Vec<Vec<f64>>> = if coulomb {
            let f = forces.as_ref().expect("coulomb iterates start from forces");
            Some(
                f.iter()
                    .zip(&mu)
                    .map(|(fi, &m)| {
                        fi.iter()
                            .map(|v| {
                                (m * v.max(0.0)).max(RADIUS_FLOOR * model.scales.element_force_n)
                            })
                            .collect()
                    })
                    .collect(),
            )
        } else {
            solver.main.a_changed |= solver.main.program.set_mu(&mu);
            None
        };
        if let Some(r) = &radii {
            solver.main.program.set_radii(model, r);
        }
        let (raw, it, time) = solver.main.run(&settings)?;
        counters.0 += it;
        counters.1 += time;
        let (status, x, z) = match raw {
            Raw::Solved { status, x, z } => (status, x, z),
            Raw::Infeasible { z } => {
                if coulomb && report.warm_started && j == 1 && report.cold_restarts == 0 {
                    // The previous step's forces were a poor guess: restart from the energy model.
                    report.cold_restarts += 1;
                    match cold_start(solver, model, loads_n, &memory, &mut counters)? {
                        Ok(f) => {
                            loads_prev = totals(&f);
                            forces = Some(f);
                            j = 0;
                            continue;
                        }
                        Err((status, reason)) => return Ok(fail(status, reason, counters, report)),
                    }
                }
                let reason = if coulomb {
                    cannot_hold_reason(model, &solver.main.program, &z)
                } else {
                    format!(
                        "{} (mu frozen at iterate {j}: {})",
                        escape_reason(model, &solver.main.program, &z),
                        fmt_mu(model, &mu)
                    )
                };
                return Ok(fail(SolveStatus::NoEquilibrium, reason, counters, report));
            }
            Raw::Failed { reason } => {
                return Ok(fail(SolveStatus::NoConvergence, reason, counters, report))
            }
        };
        let new_forces = normal_forces(model, &x);
        let change = forces
            .as_ref()
            .map_or(f64::INFINITY, |f| largest_change(f, &new_forces));
        report.last_change_n = change;
        if change <= tol_n {
            report.converged = true;
            let stats = SolverStats {
                iterations: counters.0,
                solver_time_s: counters.1,
                ..stats0
            };
            let rule = if coulomb {
                FrictionRule::Coulomb { memory_m: &memory }
            } else {
                FrictionRule::Associated
            };
            let mut out = build_solution(
                model,
                &solver.main.program,
                &x,
                &z,
                stats,
                &Build {
                    rule,
                    mu: &mu,
                    radii_n: radii.as_deref(),
                },
            );
            out.status = status;
            if status == SolveStatus::ReducedAccuracy {
                out.reason = Some("solved to reduced accuracy; check the residuals".into());
            }
            out.sequential = Some(report);
            out.solve_time_s = start.elapsed().as_secs_f64();
            record_state(model, &out, state, coulomb);
            return Ok(out);
        }
        if j >= opts.max_sequential_iterations {
            let reason = format!(
                "no convergence: the sequential solve did not reach a fixed point in {j} \
                 iterations; the element normal forces still changed by {change:.3e} N \
                 (tolerance {tol_n:.3e} N); raise the iteration limit, refine the load steps, \
                 or check that mu(P) is not too steep"
            );
            return Ok(fail(SolveStatus::NoConvergence, reason, counters, report));
        }
        loads_prev = totals(&new_forces);
        forces = Some(new_forces);
    }
}

fn fmt_mu(model: &GraspModel, mu: &[f64]) -> String {
    model
        .fingers
        .iter()
        .zip(mu)
        .map(|(f, m)| format!("{} mu = {m:.4}", f.name))
        .collect::<Vec<_>>()
        .join(", ")
}
