//! The public entry point: a [`GraspSolver`] for one model, which assembles the program once
//! and answers solves (one grasp) and steps (one step of a loading path) with the strategy the
//! model needs: one convex solve ([`crate::solve::convex_solve`]) or the sequential fixed point
//! ([`crate::solve::sequential`]), each calling down into the backend layer (`solver::program_solver`) and
//! the readout ([`crate::solve::readout`]).

use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::model::patch_compliance::CompliancePath;
use crate::program::cone_program::{ConeLaw, ConeProgram};
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::convex_solve::solve_once;
use crate::solve::readout::{enforce_invariant, failed};
use crate::solve::sensitivity::Sensitivities;
use crate::solve::sequential::solve_sequential;
use crate::solve::solution::{Solution, SolveStatus, SolverStats};
use crate::solver::clarabel::ClarabelForm;
use crate::solver::options::{SolveOptions, SolverChoice};
use crate::solver::outcome::SolverKind;
use crate::solver::program_solver::ProgramSolver;

/// A solver for one model: the assembled program and, after the first solve, the solver
/// workspaces (factorisations, Clarabel's KKT structure) and the last solution, reused while
/// only loads, radii, memory or frozen `mu` change. The coulomb model also keeps an
/// energy-model program for cold starts.
pub struct GraspSolver {
    main: ProgramSolver,
    energy: Option<ProgramSolver>,
    options: SolveOptions,
    /// Assembly time not yet counted in a solve's `solve_time_s`, s.
    pending_assembly_s: f64,
}

impl GraspSolver {
    /// Assembles the program of `model` with the scene's prescribed loads.
    pub fn new(model: &GraspModel, options: SolveOptions) -> Self {
        let clock = Instant::now();
        let loads = model.scene_loads_n();
        let law = match model.kind {
            ModelKind::Energy => ConeLaw::Associated,
            ModelKind::Coulomb => ConeLaw::Tresca,
        };
        let mu = model.mu_at(&model.guess_loads(&loads));
        let program = ConeProgram::assemble(model, &loads, law, &mu);
        GraspSolver {
            main: ProgramSolver::new(program),
            energy: None,
            options,
            pending_assembly_s: clock.elapsed().as_secs_f64(),
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

    /// The program in Clarabel's conic form (for inspection: sizes and nonzeros).
    pub fn clarabel_form(&self, model: &GraspModel) -> ClarabelForm {
        let floor = crate::solver::clarabel::radius_floor(self.options.tolerance);
        ClarabelForm::assemble(model, &self.main.program, floor)
    }

    /// The sensitivities of `solution`, this solver's last answer for `model`
    /// (`crate::solve::sensitivity`): derivatives of the finger and element forces with respect to
    /// an extra wrench on the object and to the commanded loads, at the active set.
    pub fn sensitivities(
        &mut self,
        model: &GraspModel,
        solution: &Solution,
    ) -> Result<Sensitivities, ModelError> {
        crate::solve::sensitivity::sensitivities(&mut self.main, model, solution)
    }

    /// Solves with prescribed loads `loads_n` (N, one per force-controlled finger, scene
    /// order) and the external wrench of `model` (which may be this solver's model with another
    /// external wrench, [`GraspModel::with_extra_wrench`]) from a fresh contact state (no slip memory). Infeasible grasps and solver
    /// failures are reported in the returned [`Solution`]'s status; `Err` only for malformed
    /// loads or data a solver refuses.
    pub fn solve(&mut self, model: &GraspModel, loads_n: &[f64]) -> Result<Solution, ModelError> {
        let mut state = ContactState::new(model);
        self.solve_step(model, loads_n, &mut state)
    }

    /// Solves one step of a loading path: like [`GraspSolver::solve`], starting from `state`
    /// (slip memory of the coulomb model; previous forces for the warm start) and from this
    /// solver's last solution (when `options.warm_start`). `state` is updated when the step
    /// succeeds and left as it was otherwise.
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
        let clock = Instant::now();
        let mut sol = self.dispatch(model, loads_n, state, clock)?;
        enforce_invariant(&mut sol);
        // The scene's warnings hold whatever the outcome; the solve's own follow them.
        let scene_warnings = model.object.scene_warnings.iter().cloned();
        sol.warnings.splice(0..0, scene_warnings);
        sol.solve_time_s = clock.elapsed().as_secs_f64() + self.pending_assembly_s;
        self.pending_assembly_s = 0.0;
        Ok(sol)
    }

    fn dispatch(
        &mut self,
        model: &GraspModel,
        loads_n: &[f64],
        state: &mut ContactState,
        clock: Instant,
    ) -> Result<Solution, ModelError> {
        self.main.program.set_loads(model, loads_n);
        self.main.program.set_external_wrench(model);
        let offsets = state.offsets_m(model);
        self.main.program.set_offsets(model, &offsets);
        let p = &self.main.program;
        let stats = SolverStats {
            solver: match self.options.solver {
                SolverChoice::Clarabel => SolverKind::Clarabel,
                _ => SolverKind::Native,
            },
            fallback: None,
            iterations: 0,
            factorizations: 0,
            compliance: CompliancePath::of(
                model.fingers.iter().map(|f| f.compliance_m_per_n.is_fft()),
            ),
            inner_iterations: 0,
            solver_time_s: 0.0,
            unknowns: model.n_unknowns,
            equality_rows: p.equality_rows(),
            cone_rows: model.n_unknowns,
        };
        if let Some(reason) = &p.unbalanced {
            let reason = reason.clone();
            return Ok(failed(
                model,
                SolveStatus::NoEquilibrium,
                reason,
                clock,
                stats,
            ));
        }
        let sequential = model.kind == ModelKind::Coulomb
            || model
                .fingers
                .iter()
                .any(|f| f.n_tangential > 0 && !f.friction.is_constant());
        if sequential {
            solve_sequential(
                &mut self.main,
                &mut self.energy,
                model,
                loads_n,
                state,
                &self.options,
                stats,
                clock,
            )
        } else {
            let sol = solve_once(&mut self.main, model, &self.options, stats, clock)?;
            if sol.status.has_forces() {
                state.record(model, &sol, false);
            }
            Ok(sol)
        }
    }
}

/// Convenience: builds a solver and solves with the scene's own loads.
pub fn solve(model: &GraspModel) -> Result<Solution, ModelError> {
    GraspSolver::new(model, SolveOptions::default()).solve(model, &model.scene_loads_n())
}
