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

use crate::cone_program::{ConeLaw, ConeProgram};
use crate::contact_state::ContactState;
use crate::error::ModelError;
use crate::grasp_model::GraspModel;
use crate::residuals::{contact_kinematics, evaluate, tangential, FrictionRule};
use crate::scene::ModelKind;
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
    /// Interior-point iteration limit of each convex solve.
    pub max_iterations: u32,
    /// Time limit of each convex solve, s.
    pub time_limit_s: f64,
    /// Sequential solve: converged when no element normal force changes by more than this
    /// many element force units `Fu` between iterates (dimensionless).
    pub sequential_tolerance: f64,
    /// Sequential solve: largest number of convex solves per step.
    pub max_sequential_iterations: u32,
    /// Sequential solve: start from the previous step's forces when the state has them.
    pub warm_start: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            tolerance: 1e-10,
            max_iterations: 200,
            time_limit_s: f64::INFINITY,
            sequential_tolerance: 1e-7,
            max_sequential_iterations: 50,
            warm_start: true,
        }
    }
}

/// The outcome of one convex solve, scaled.
pub(crate) enum Raw {
    /// Solved (or almost): scaled primal `x` and dual `z`.
    Solved {
        /// Clarabel's status, mapped.
        status: SolveStatus,
        /// Scaled primal.
        x: Vec<f64>,
        /// Scaled dual.
        z: Vec<f64>,
    },
    /// Primal infeasible: the certificate.
    Infeasible {
        /// Clarabel's certificate `z` (`A'z = 0`, `b'z < 0`, `z` in the dual cone).
        z: Vec<f64>,
    },
    /// No answer: why.
    Failed {
        /// Reason for the user.
        reason: String,
    },
}

/// One assembled program and its Clarabel workspace (created at the first solve; later solves
/// update `b`, and `q` or `A` when they changed, in place).
pub(crate) struct ProgramSolver {
    /// The program.
    pub program: ConeProgram,
    clarabel: Option<DefaultSolver<f64>>,
    /// `A` changed since the last solve (frozen `mu` of the energy model).
    pub a_changed: bool,
    /// `q` changed since the last solve (slip memory).
    pub q_changed: bool,
}

impl ProgramSolver {
    pub(crate) fn new(program: ConeProgram) -> Self {
        ProgramSolver {
            program,
            clarabel: None,
            a_changed: false,
            q_changed: false,
        }
    }

    /// Solves the program as it stands. Returns the outcome, IPM iterations and solver time.
    pub fn run(&mut self, settings: &DefaultSettings<f64>) -> Result<(Raw, u32, f64), ModelError> {
        let p = &self.program;
        let err = |e: clarabel::solver::DataUpdateError| ModelError::Solver(e.to_string());
        let solver = match self.clarabel.as_mut() {
            Some(s) => {
                if self.a_changed {
                    s.update_A(&p.a.nzval).map_err(err)?;
                }
                if self.q_changed {
                    s.update_q(&p.q).map_err(err)?;
                }
                s.update_b(&p.b).map_err(err)?;
                s
            }
            None => {
                let s = DefaultSolver::new(&p.p, &p.q, &p.a, &p.b, &p.cones, settings.clone())
                    .map_err(|e| ModelError::Solver(e.to_string()))?;
                self.clarabel.insert(s)
            }
        };
        self.a_changed = false;
        self.q_changed = false;
        solver.solve();
        let sol = &solver.solution;
        let raw = match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Raw::Solved {
                status: if sol.status == SolverStatus::Solved {
                    SolveStatus::Solved
                } else {
                    SolveStatus::ReducedAccuracy
                },
                x: sol.x.clone(),
                z: sol.z.clone(),
            },
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                Raw::Infeasible { z: sol.z.clone() }
            }
            other => Raw::Failed {
                reason: format!(
                    "no convergence: the cone solver stopped with status {other:?} after {} \
                     iterations; try a coarser grid, or report the scene",
                    sol.iterations
                ),
            },
        };
        Ok((raw, sol.iterations, sol.solve_time))
    }
}

/// A solver for one model: the assembled program and, after the first solve, Clarabel's
/// workspace, reused when only loads, radii, memory or frozen `mu` change. The coulomb model
/// also keeps an energy-model program for cold starts.
pub struct GraspSolver {
    pub(crate) main: ProgramSolver,
    pub(crate) start: Option<ProgramSolver>,
    pub(crate) options: SolveOptions,
}

impl GraspSolver {
    /// Assembles the program of `model` with the scene's prescribed loads.
    pub fn new(model: &GraspModel, options: SolveOptions) -> Self {
        let loads = model.scene_loads_n();
        let law = match model.kind {
            ModelKind::Energy => ConeLaw::Associated,
            ModelKind::Coulomb => ConeLaw::Tresca,
        };
        let mu = crate::sequential::mu_at(model, &crate::sequential::guess_loads(model, &loads));
        let program = ConeProgram::assemble(model, &loads, law, &mu);
        GraspSolver {
            main: ProgramSolver::new(program),
            start: None,
            options,
        }
    }

    /// The assembled program.
    pub fn program(&self) -> &ConeProgram {
        &self.main.program
    }

    /// The options.
    pub fn options(&self) -> &SolveOptions {
        &self.options
    }

    pub(crate) fn settings(&self) -> DefaultSettings<f64> {
        let t = self.options.tolerance;
        DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_feas(t)
            .tol_gap_abs(t)
            .tol_gap_rel(t)
            .max_iter(self.options.max_iterations)
            .time_limit(self.options.time_limit_s)
            .presolve_enable(false)
            .input_sparse_dropzeros(false)
            .direct_solve_method("faer".to_string())
            .build()
            .expect("valid Clarabel settings")
    }

    /// Solves with prescribed loads `loads_n` (N, one per force-controlled finger, scene
    /// order) from a fresh contact state (no slip memory, no warm start). Infeasible grasps
    /// and solver failures are reported in the returned [`Solution`]'s status; `Err` only for
    /// malformed loads or data Clarabel refuses.
    pub fn solve(&mut self, model: &GraspModel, loads_n: &[f64]) -> Result<Solution, ModelError> {
        let mut state = ContactState::new(model);
        self.solve_step(model, loads_n, &mut state)
    }

    /// Solves one step of a loading path: like [`GraspSolver::solve`], starting from `state`
    /// (slip memory of the coulomb model; previous forces for the warm start), which is
    /// updated when the step succeeds and left as it was otherwise.
    pub fn solve_step(
        &mut self,
        model: &GraspModel,
        loads_n: &[f64],
        state: &mut ContactState,
    ) -> Result<Solution, ModelError> {
        model.check_loads(loads_n)?;
        if !state.matches(model) {
            return Err(ModelError::StateMismatch);
        }
        let start = Instant::now();
        self.main.program.set_loads(model, loads_n);
        let p = &self.main.program;
        let stats0 = SolverStats {
            iterations: 0,
            solver_time_s: 0.0,
            unknowns: model.n_unknowns,
            equality_rows: p.equilibrium_rows() + p.load_rows.len(),
            cone_rows: p.b.len() - p.equilibrium_rows() - p.load_rows.len(),
        };
        if let Some(reason) = &p.unbalanced {
            return Ok(failed(
                model,
                SolveStatus::NoEquilibrium,
                reason.clone(),
                start,
                stats0,
            ));
        }
        let sequential = model.kind == ModelKind::Coulomb
            || model
                .fingers
                .iter()
                .any(|f| f.n_tangential > 0 && !f.friction.is_constant());
        if sequential {
            return crate::sequential::solve_sequential(self, model, loads_n, state, stats0, start);
        }
        let settings = self.settings();
        let (raw, iterations, time) = self.main.run(&settings)?;
        let stats = SolverStats {
            iterations,
            solver_time_s: time,
            ..stats0
        };
        let mu = self.main.program.mu.clone();
        match raw {
            Raw::Solved { status, x, z } => {
                let mut out = build_solution(
                    model,
                    &self.main.program,
                    &x,
                    &z,
                    stats,
                    &Build {
                        rule: FrictionRule::Associated,
                        mu: &mu,
                        radii_n: None,
                    },
                );
                out.status = status;
                if status == SolveStatus::ReducedAccuracy {
                    out.reason = Some("solved to reduced accuracy; check the residuals".into());
                }
                out.solve_time_s = start.elapsed().as_secs_f64();
                record_state(model, &out, state, false);
                Ok(out)
            }
            Raw::Infeasible { z } => Ok(failed(
                model,
                SolveStatus::NoEquilibrium,
                escape_reason(model, &self.main.program, &z),
                start,
                stats,
            )),
            Raw::Failed { reason } => Ok(failed(
                model,
                SolveStatus::NoConvergence,
                reason,
                start,
                stats,
            )),
        }
    }
}

/// Convenience: builds a solver and solves with the scene's own loads.
pub fn solve(model: &GraspModel) -> Result<Solution, ModelError> {
    GraspSolver::new(model, SolveOptions::default()).solve(model, &model.scene_loads_n())
}

/// Writes a successful solution into the state: forces and loads (warm start) and, for the
/// coulomb model (`memory`), the accumulated slip as the new slip memory.
pub(crate) fn record_state(
    model: &GraspModel,
    sol: &Solution,
    state: &mut ContactState,
    memory: bool,
) {
    for ((fs, f), fm) in state
        .fingers
        .iter_mut()
        .zip(&sol.fingers)
        .zip(&model.fingers)
    {
        fs.normal_forces_n = Some(f.elements.iter().map(|e| e.normal_force_n).collect());
        fs.normal_load_n = Some(f.normal_force_n);
        if memory && fm.n_tangential > 0 {
            for (m, e) in fs.slip_memory_m.iter_mut().zip(&f.elements) {
                *m = e.slip_m;
            }
        }
    }
}

pub(crate) fn failed(
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
        sequential: None,
    }
}

/// Rigid displacement `(translation of O, rotation)` from the scaled equality multipliers.
pub(crate) fn rigid_from_multipliers(
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
pub(crate) fn escape_reason(model: &GraspModel, program: &ConeProgram, z: &[f64]) -> String {
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

/// How to read a solved program.
pub(crate) struct Build<'a> {
    /// The friction rule (energy: associated; coulomb: with the step's starting memory).
    pub rule: FrictionRule<'a>,
    /// Friction coefficient per finger the program was solved with.
    pub mu: &'a [f64],
    /// Tresca radii per finger, per element (N), coulomb model only.
    pub radii_n: Option<&'a [Vec<f64>]>,
}

/// Builds the SI solution from the scaled primal `x` and dual `z`.
pub(crate) fn build_solution(
    model: &GraspModel,
    program: &ConeProgram,
    x_scaled: &[f64],
    z: &[f64],
    stats: SolverStats,
    how: &Build<'_>,
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
        let mu = how.mu[i];
        let dilatancy = if how.rule.is_associated() { mu } else { 0.0 };
        let st: Vec<ElementState> = (0..ne)
            .map(|k| {
                let fk = x_n[f.offset + k] / fu;
                let g = tangential(&x_n, f.offset, ne, f.n_tangential, k);
                let gn = (g[0] * g[0] + g[1] * g[1]).sqrt() / fu;
                let w = how.rule.step_slip(i, k, kin.tangential_m[i][k]);
                let wn = (w[0] * w[0] + w[1] * w[1]).sqrt() / du;
                let gap = kin.gap_m[i][k] / du;
                let opening = if f.n_tangential == 0 {
                    gap
                } else {
                    gap - dilatancy * wn
                };
                let radius = match how.radii_n {
                    Some(r) => r[i][k] / fu,
                    None => mu * fk,
                };
                // Primal slack against dual slack: the larger one says which side is active.
                if fk < opening.max(1e-7) {
                    ElementState::Separated
                } else if f.n_tangential == 0 || wn > radius - gn {
                    ElementState::Slip
                } else {
                    ElementState::Stick
                }
            })
            .collect();
        states.push(st);
    }
    // The law's coefficient at each finger's load (equal to the frozen one at a fixed point).
    let mu_at_load: Vec<f64> = model
        .fingers
        .iter()
        .map(|f| {
            let p: f64 = x_n[f.offset..f.offset + f.patch.len()].iter().sum();
            f.friction.mu_at(p)
        })
        .collect();
    let residuals = evaluate(model, &x_n, &kin, &states, &mu_at_load, how.rule);

    let mut fingers = Vec::with_capacity(model.fingers.len());
    for (i, f) in model.fingers.iter().enumerate() {
        let ne = f.patch.len();
        let area = f.patch.element_area_m2();
        let mu = if f.n_tangential == 0 {
            0.0
        } else {
            mu_at_load[i]
        };
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
                step_slip_m: how.rule.step_slip(i, k, kin.tangential_m[i][k]),
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
            friction_coefficient: mu,
            // An unloaded finger (interior-point noise only) has no meaningful ratio.
            friction_utilization: if mu > 0.0 && p > 1e-9 * s.load_n {
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
        sequential: None,
    };
    sol.warnings = crate::patch_sizing::patch_warnings(model, &sol);
    sol
}
