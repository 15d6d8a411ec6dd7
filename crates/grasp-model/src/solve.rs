//! Solving the cone program with Clarabel and turning its answer into a [`Solution`] in SI.
//!
//! Multipliers (KKT of `min 1/2 x'Px + q'x, Ax + s = b`: `Px + q + A'z = 0`):
//! - equilibrium rows: the object's rigid displacement, `delta = Fu Cu S' U z_eq`
//!   (translation of `O` in m, rotation in rad);
//! - load rows: minus the approach of the force-controlled finger, `a_i = -Fu Cu z_i`;
//! - cone rows: the gap and slip of each element (`Fu Cu` times the scaled duals).

use std::time::Instant;

use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus,
};
use nalgebra::{DVector, Vector3};

use crate::cone_program::ConeProgram;
use crate::error::ModelError;
use crate::grasp_model::GraspModel;
use crate::residuals::{contact_kinematics, evaluate, tangential};
use crate::solution::{
    ElementSolution, ElementState, FingerSolution, RigidDisplacement, Solution, SolveStatus,
    SolverStats,
};

/// Options of a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Feasibility and gap tolerance of the scaled program (Clarabel `tol_feas`,
    /// `tol_gap_abs`, `tol_gap_rel`).
    pub tolerance: f64,
    /// Interior-point iteration limit.
    pub max_iterations: u32,
    /// Time limit, s.
    pub time_limit_s: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            tolerance: 1e-10,
            max_iterations: 200,
            time_limit_s: f64::INFINITY,
        }
    }
}

/// A solver for one model: the assembled program and, after the first solve, Clarabel's
/// workspace, reused when only the loads change.
pub struct GraspSolver {
    program: ConeProgram,
    clarabel: Option<DefaultSolver<f64>>,
    options: SolveOptions,
}

impl GraspSolver {
    /// Assembles the program of `model` with the scene's prescribed loads.
    pub fn new(model: &GraspModel, options: SolveOptions) -> Self {
        let program = ConeProgram::assemble(model, &model.scene_loads_n());
        GraspSolver {
            program,
            clarabel: None,
            options,
        }
    }

    /// The assembled program.
    pub fn program(&self) -> &ConeProgram {
        &self.program
    }

    fn settings(&self) -> DefaultSettings<f64> {
        let t = self.options.tolerance;
        DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_feas(t)
            .tol_gap_abs(t)
            .tol_gap_rel(t)
            .max_iter(self.options.max_iterations)
            .time_limit(self.options.time_limit_s)
            .presolve_enable(false)
            .direct_solve_method("faer".to_string())
            .build()
            .expect("valid Clarabel settings")
    }

    /// Solves with prescribed loads `loads_n` (N, one per force-controlled finger, scene
    /// order). Infeasible grasps and solver failures are reported in the returned
    /// [`Solution`]'s status; `Err` only for malformed loads or data Clarabel refuses.
    pub fn solve(&mut self, model: &GraspModel, loads_n: &[f64]) -> Result<Solution, ModelError> {
        model.check_loads(loads_n)?;
        let start = Instant::now();
        self.program.set_loads(model, loads_n);
        let stats0 = SolverStats {
            iterations: 0,
            solver_time_s: 0.0,
            unknowns: model.n_unknowns,
            equality_rows: self.program.equilibrium_rows() + self.program.load_rows.len(),
            cone_rows: self.program.b.len()
                - self.program.equilibrium_rows()
                - self.program.load_rows.len(),
        };
        if let Some(reason) = &self.program.unbalanced {
            return Ok(failed(
                model,
                SolveStatus::NoEquilibrium,
                reason.clone(),
                start,
                stats0,
            ));
        }
        let settings = self.settings();
        let p = &self.program;
        let solver = match self.clarabel.as_mut() {
            Some(s) => {
                s.update_b(&p.b)
                    .map_err(|e| ModelError::Solver(e.to_string()))?;
                s
            }
            None => {
                let s = DefaultSolver::new(&p.p, &p.q, &p.a, &p.b, &p.cones, settings)
                    .map_err(|e| ModelError::Solver(e.to_string()))?;
                self.clarabel.insert(s)
            }
        };
        solver.solve();
        let sol = &solver.solution;
        let stats = SolverStats {
            iterations: sol.iterations,
            solver_time_s: sol.solve_time,
            ..stats0
        };
        let status = match sol.status {
            SolverStatus::Solved => SolveStatus::Solved,
            SolverStatus::AlmostSolved => SolveStatus::ReducedAccuracy,
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                let reason = escape_reason(model, &self.program, &sol.z);
                return Ok(failed(
                    model,
                    SolveStatus::NoEquilibrium,
                    reason,
                    start,
                    stats,
                ));
            }
            other => {
                let reason = format!(
                    "no convergence: the cone solver stopped with status {other:?} after {} \
                     iterations; try a coarser grid, or report the scene",
                    sol.iterations
                );
                return Ok(failed(
                    model,
                    SolveStatus::NoConvergence,
                    reason,
                    start,
                    stats,
                ));
            }
        };
        let x = sol.x.clone();
        let z = sol.z.clone();
        let mut out = build_solution(model, &self.program, &x, &z, stats);
        out.status = status;
        if status == SolveStatus::ReducedAccuracy {
            out.reason = Some("solved to reduced accuracy; check the residuals".into());
        }
        out.solve_time_s = start.elapsed().as_secs_f64();
        Ok(out)
    }
}

/// Convenience: builds a solver and solves with the scene's own loads.
pub fn solve(model: &GraspModel) -> Result<Solution, ModelError> {
    GraspSolver::new(model, SolveOptions::default()).solve(model, &model.scene_loads_n())
}

fn failed(
    model: &GraspModel,
    status: SolveStatus,
    reason: String,
    start: Instant,
    solver: SolverStats,
) -> Solution {
    Solution {
        status,
        reason: Some(reason),
        warnings: Vec::new(),
        fingers: Vec::new(),
        rigid_displacement: None,
        residuals: None,
        load_scale_n: model.scales.load_n,
        solve_time_s: start.elapsed().as_secs_f64(),
        solver,
    }
}

/// Rigid displacement `(translation of O, rotation)` from the scaled equality multipliers.
fn rigid_from_multipliers(
    model: &GraspModel,
    program: &ConeProgram,
    z: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let r = program.equilibrium_rows();
    let zr = DVector::from_column_slice(&z[..r]);
    let full = &program.reduction.basis * zr; // scaled equilibrium coordinates
                                              // delta = Fu Cu S' full; S has 1/L on moment rows.
    let d = model.equilibrium.select.transpose() * full * model.scales.displacement_m();
    (
        Vector3::new(d[0], d[1], d[2]),
        Vector3::new(d[3], d[4], d[5]),
    )
}

fn fmt3(v: &Vector3<f64>) -> String {
    format!("[{:.3}, {:.3}, {:.3}]", v.x, v.y, v.z)
}

/// Reads Clarabel's infeasibility certificate as the rigid motion by which the object escapes.
fn escape_reason(model: &GraspModel, program: &ConeProgram, z: &[f64]) -> String {
    let (t_o, theta) = rigid_from_multipliers(model, program, z);
    let t = t_o + theta.cross(&(model.center_of_mass_m - model.reference_point_m));
    let mut s = String::from(
        "no equilibrium: the friction cones cannot balance the load (friction too low, or the \
         contacts cannot resist it)",
    );
    let scale = t.norm().max(theta.norm() * model.scales.length_m);
    if scale > 0.0 && scale.is_finite() {
        s.push_str("; the object would escape");
        if t.norm() > 1e-6 * scale {
            s.push_str(&format!(" moving along {}", fmt3(&t.normalize())));
        }
        if theta.norm() * model.scales.length_m > 1e-6 * scale {
            s.push_str(&format!(" turning about {}", fmt3(&theta.normalize())));
        }
    }
    s.push_str("; raise mu or move the fingers");
    s
}

/// Builds the SI solution from the scaled primal `x` and dual `z`.
fn build_solution(
    model: &GraspModel,
    program: &ConeProgram,
    x_scaled: &[f64],
    z: &[f64],
    stats: SolverStats,
) -> Solution {
    let s = model.scales;
    let x_n: Vec<f64> = x_scaled.iter().map(|v| v * s.element_force_n).collect();
    let (t_o, theta) = rigid_from_multipliers(model, program, z);
    let mut approach = vec![0.0; model.fingers.len()];
    for &(i, row) in &program.load_rows {
        approach[i] = -z[row] * s.displacement_m();
    }
    let kin = contact_kinematics(model, &x_n, &t_o, &theta, &approach);
    let du = s.displacement_m();
    let fu = s.element_force_n;

    let mut states = Vec::with_capacity(model.fingers.len());
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let mu = f.mu();
        let st: Vec<ElementState> = (0..ne)
            .map(|k| {
                let fk = x_n[f.offset + k] / fu;
                let g = tangential(&x_n, f.offset, ne, f.n_tangential, k);
                let gn = (g[0] * g[0] + g[1] * g[1]).sqrt() / fu;
                let w = kin.tangential_m[i][k];
                let wn = (w[0] * w[0] + w[1] * w[1]).sqrt() / du;
                let gap = kin.gap_m[i][k] / du;
                let opening = if f.n_tangential == 0 {
                    gap
                } else {
                    gap - mu * wn
                };
                // Primal slack against dual slack: the larger one says which side is active.
                if fk < opening.max(1e-7) {
                    ElementState::Separated
                } else if f.n_tangential == 0 || wn > mu * fk - gn {
                    ElementState::Slip
                } else {
                    ElementState::Stick
                }
            })
            .collect();
        states.push(st);
    }
    let residuals = evaluate(model, &x_n, &kin, &states);

    let mut fingers = Vec::with_capacity(model.fingers.len());
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let area = f.patch.element_area_m2();
        let mu = f.mu();
        let mut elements = Vec::with_capacity(ne);
        let (mut p, mut q, mut torsion, mut cx, mut cy) = (0.0, Vector3::zeros(), 0.0, 0.0, 0.0);
        let (mut n_stick, mut n_slip, mut n_sep, mut peak) = (0, 0, 0, 0.0_f64);
        let mut boundary = 0.0;
        for k in 0..ne {
            let fk = x_n[f.offset + k];
            let g = tangential(&x_n, f.offset, ne, f.n_tangential, k);
            let [x, y] = f.patch.centres_m[k];
            p += fk;
            if f.patch.on_boundary(k) {
                boundary += fk;
            }
            q += f.frame.t1 * g[0] + f.frame.t2 * g[1];
            torsion += x * g[1] - y * g[0];
            cx += fk * x;
            cy += fk * y;
            peak = peak.max(fk / area);
            match states[i][k] {
                ElementState::Stick => n_stick += 1,
                ElementState::Slip => n_slip += 1,
                ElementState::Separated => n_sep += 1,
            }
            let pos = f.element_point(k);
            elements.push(ElementSolution {
                index: [k / f.patch.grid.ny, k % f.patch.grid.ny],
                local_m: [x, y],
                position_m: [pos.x, pos.y, pos.z],
                normal_force_n: fk,
                tangential_force_n: g,
                pressure_pa: fk / area,
                traction_pa: [g[0] / area, g[1] / area],
                gap_m: kin.gap_m[i][k],
                slip_m: kin.tangential_m[i][k],
                state: states[i][k],
            });
        }
        let cop = if p > 0.0 {
            f.frame.point(cx / p, cy / p)
        } else {
            f.frame.origin_m
        };
        let qn = q.norm();
        fingers.push(FingerSolution {
            name: f.name.clone(),
            normal_force_n: p,
            tangential_force_n: [q.x, q.y, q.z],
            tangential_magnitude_n: qn,
            torsional_moment_nm: torsion,
            center_of_pressure_m: [cop.x, cop.y, cop.z],
            contact_area_m2: (ne - n_sep) as f64 * area,
            peak_pressure_pa: peak,
            friction_utilization: if mu > 0.0 && p > 0.0 {
                qn / (mu * p)
            } else {
                0.0
            },
            boundary_load_fraction: if p > 0.0 { boundary / p } else { 0.0 },
            approach_m: approach[i],
            stick_count: n_stick,
            slip_count: n_slip,
            separated_count: n_sep,
            elements,
        });
    }
    let t_com = t_o + theta.cross(&(model.center_of_mass_m - model.reference_point_m));
    let mut sol = Solution {
        status: SolveStatus::Solved,
        reason: None,
        warnings: Vec::new(),
        fingers,
        // With no contact force at all the multipliers are any interior point: the object's
        // position is not determined by the grasp, so none is reported.
        rigid_displacement: (x_n
            .iter()
            .take(model.n_unknowns)
            .any(|&v| v.abs() > 1e-12 * s.element_force_n))
        .then_some(RigidDisplacement {
            translation_m: [t_com.x, t_com.y, t_com.z],
            rotation_rad: [theta.x, theta.y, theta.z],
        }),
        residuals: Some(residuals),
        load_scale_n: s.load_n,
        solve_time_s: 0.0,
        solver: stats,
    };
    sol.warnings = crate::patch_sizing::patch_warnings(model, &sol);
    sol
}
