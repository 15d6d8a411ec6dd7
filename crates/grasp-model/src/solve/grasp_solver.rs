//! The public entry point: a [`GraspSolver`] for one model, which keeps the model, assembles
//! the program once and answers solves (one grasp) and steps (one step of a loading path:
//! [`StepInputs`] beside a [`ContactState`]) with the strategy the model needs: one convex solve ([`crate::solve::convex_solve`]) or the sequential fixed point
//! ([`crate::solve::sequential`]), each calling down into the backend layer (`solver::program_solver`) and
//! the readout ([`crate::solve::readout`]).

use std::sync::Arc;
use std::time::Instant;

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::model::patch_compliance::CompliancePath;
use crate::model::spring_loads::add_hand_poses;
use crate::program::cone_program::ConeProgram;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::convex_solve::solve_once;
use crate::solve::readout::{enforce_invariant, failed};
use crate::solve::sensitivity::{LoadDirection, Sensitivities};
use crate::solve::sequential::{solve_sequential, StepPrograms};
use crate::solve::solution::{Solution, SolveStatus, SolverStats};
use crate::solve::step_inputs::StepInputs;
use crate::solver::clarabel::ClarabelForm;
use crate::solver::options::{SolveOptions, SolverChoice};
use crate::solver::outcome::SolverKind;
use crate::solver::program_solver::ProgramSolver;
use crate::solver::solve_progress::SolveProgress;

/// A solver for one model: the assembled program and, after the first solve, the solver
/// workspaces (factorisations, Clarabel's KKT structure) and the last solution, reused while
/// only loads, radii, memory or frozen `mu` change. The coulomb model also keeps an
/// energy-model program for cold starts. A viscoelastic model's program answers one time
/// step at a time ([`StepInputs::time_step_s`]): a solve of another step length assembles the
/// program of that step's compliance afresh.
pub struct GraspSolver {
    /// The model as given (its instantaneous response).
    model: Arc<GraspModel>,
    /// The program's time step and its model (the compliance over the step), when it answers
    /// a step of a viscoelastic model's time history.
    stepped: Option<TimeStepModel>,
    main: ProgramSolver,
    energy: Option<ProgramSolver>,
    options: SolveOptions,
    /// Assembly time not yet counted in a solve's `solve_time_s`, s.
    pending_assembly_s: f64,
}

/// A viscoelastic model over one time step: its compliance is the step's.
struct TimeStepModel {
    /// The step, s (`f64::INFINITY`: fully relaxed).
    time_step_s: f64,
    /// The model over the step ([`GraspModel::for_time_step`]).
    model: Arc<GraspModel>,
}

impl GraspSolver {
    /// Assembles the program of `model` with the scene's prescribed loads; the solver keeps
    /// the model (pass an `Arc` to share it, or the model itself to hand it over).
    pub fn new(model: impl Into<Arc<GraspModel>>, options: SolveOptions) -> Self {
        let model: Arc<GraspModel> = model.into();
        let clock = Instant::now();
        let program = ConeProgram::with_scene_loads(&model);
        GraspSolver {
            model,
            stepped: None,
            main: ProgramSolver::new(program),
            energy: None,
            options,
            pending_assembly_s: clock.elapsed().as_secs_f64(),
        }
    }

    /// Makes the program answer `inputs`' time step: for a viscoelastic model the compliance
    /// over the step ([`GraspModel::for_time_step`], assembled afresh when the step length
    /// changes); the model as given outside a time history, for a step of 0 s (the
    /// instantaneous response is the model's own) and for an elastic model.
    fn use_time_step(&mut self, inputs: &StepInputs) -> Result<(), ModelError> {
        let viscous = self.model.is_viscoelastic();
        let step = inputs.time_step_s.filter(|&dt| viscous && dt != 0.0);
        let current = self.stepped.as_ref().map(|s| s.time_step_s.to_bits());
        if step.map(f64::to_bits) == current {
            return Ok(());
        }
        let clock = Instant::now();
        self.stepped = match step {
            Some(dt) => Some(TimeStepModel {
                time_step_s: dt,
                model: Arc::new(self.model.for_time_step(dt)?),
            }),
            None => None,
        };
        self.main = ProgramSolver::new(ConeProgram::with_scene_loads(self.step_model()));
        self.energy = None;
        self.pending_assembly_s += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The model the program answers: the model over the current time step, or as given.
    fn step_model(&self) -> &Arc<GraspModel> {
        self.stepped.as_ref().map_or(&self.model, |s| &s.model)
    }

    /// Reports the native solver's Newton steps and conjugate-gradient iterations to
    /// `progress` as this solver's solves go (a display reads it from another thread; the
    /// solver only stores counters, once per Newton step).
    pub fn set_progress(&mut self, progress: Arc<SolveProgress>) {
        self.main.progress = Some(progress);
    }

    /// The model this solver was built for (as given: a viscoelastic model's instantaneous
    /// response).
    pub fn model(&self) -> &GraspModel {
        &self.model
    }

    /// The model this solver was built for, shared.
    pub fn shared_model(&self) -> &Arc<GraspModel> {
        &self.model
    }

    /// The model this solver was built for, handed back (a copy only when it is still shared
    /// elsewhere).
    pub fn into_model(self) -> GraspModel {
        Arc::unwrap_or_clone(self.model)
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
    pub fn clarabel_form(&self) -> ClarabelForm {
        let floor = crate::solver::clarabel::radius_floor(self.options.tolerance);
        ClarabelForm::assemble(self.step_model(), &self.main.program, floor)
    }

    /// The sensitivities of `solution`, this solver's last answer: derivatives of the finger
    /// and element forces with respect to an extra wrench on the object and to the commanded
    /// loads, at the active set (the KKT system's derivative, `solve/sensitivity.rs`).
    pub fn sensitivities(&mut self, solution: &Solution) -> Result<Sensitivities, ModelError> {
        let model = Arc::clone(self.step_model());
        crate::solve::sensitivity::sensitivities(&mut self.main, &model, solution, &[])
    }

    /// [`GraspSolver::sensitivities`] with a column per [`LoadDirection`] besides (named
    /// `loads:<name>`): commanded loads moved together, where single loads have no
    /// derivative (the two jaws of a pinch).
    pub fn sensitivities_along(
        &mut self,
        solution: &Solution,
        directions: &[LoadDirection],
    ) -> Result<Sensitivities, ModelError> {
        let model = Arc::clone(self.step_model());
        crate::solve::sensitivity::sensitivities(&mut self.main, &model, solution, directions)
    }

    /// Solves with `inputs` (loads, extra wrench, approaches) from a fresh contact state (no
    /// slip memory). Infeasible grasps and solver failures are reported in the returned
    /// [`Solution`]'s status; `Err` only for inputs that do not fit the model or data a solver
    /// refuses.
    pub fn solve(&mut self, inputs: &StepInputs) -> Result<Solution, ModelError> {
        let mut state = ContactState::new(&self.model);
        self.solve_step(inputs, &mut state)
    }

    /// Solves one step of a loading path: like [`GraspSolver::solve`], starting from `state`
    /// (slip memory of the coulomb model; previous forces for the warm start; a viscoelastic
    /// history) and from this solver's last solution (when `options.warm_start`). A step of a
    /// viscoelastic model's time history ([`StepInputs::time_step_s`]) is solved with the
    /// compliance over the step, `state` prepared for it first
    /// (`ContactState::prepare_time_step`); time moves on when the caller, content with the
    /// step, calls [`ContactState::advance_time_step`]. `state` is updated when the step
    /// succeeds and left as it was otherwise (its preparation for the step aside).
    pub fn solve_step(
        &mut self,
        inputs: &StepInputs,
        state: &mut ContactState,
    ) -> Result<Solution, ModelError> {
        inputs.check(&self.model)?;
        if !state.matches(&self.model) {
            return Err(ModelError::StateMismatch);
        }
        self.use_time_step(inputs)?;
        let model = Arc::clone(self.step_model());
        if let Some(dt) = inputs.time_step_s {
            state.prepare_time_step(&model, dt);
        }
        model.solve_size().check_room()?;
        let clock = Instant::now();
        let mut sol = self.dispatch(&model, inputs, state, clock)?;
        enforce_invariant(&mut sol);
        // The scene's warnings hold whatever the outcome; the solve's own follow them.
        let scene_warnings = model.object.scene_warnings.iter().cloned();
        sol.warnings.splice(0..0, scene_warnings);
        sol.solve_time_s = clock.elapsed().as_secs_f64() + self.pending_assembly_s;
        self.pending_assembly_s = 0.0;
        Ok(sol)
    }

    /// Writes the step's inputs into the program: loads, external wrench, commanded approaches
    /// and the displacement offsets (approaches, hand poses and viscoelastic history).
    fn set_step(&mut self, model: &GraspModel, inputs: &StepInputs, state: &ContactState) {
        let program = &mut self.main.program;
        program.set_loads(model, &inputs.loads_n);
        program.set_external_wrench(model, &inputs.external_wrench(model));
        let approaches = inputs.approaches_per_finger_m(model);
        program.set_approaches(&approaches);
        let mut offsets = state.offsets_m(model, &approaches);
        add_hand_poses(model, &inputs.hand_poses, &mut offsets);
        program.set_hand_poses(&inputs.hand_poses);
        program.set_offsets(model, &offsets);
    }

    fn dispatch(
        &mut self,
        model: &GraspModel,
        inputs: &StepInputs,
        state: &mut ContactState,
        clock: Instant,
    ) -> Result<Solution, ModelError> {
        self.set_step(model, inputs, state);
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
        let sequential = model.kind() == ModelKind::Coulomb
            || model
                .fingers
                .iter()
                .any(|f| f.n_tangential > 0 && !f.friction.is_constant());
        if sequential {
            let programs = StepPrograms {
                main: &mut self.main,
                energy: &mut self.energy,
            };
            solve_sequential(
                programs,
                model,
                &inputs.loads_n,
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

/// Convenience: builds a solver for (a copy of) `model` and solves with the scene's own
/// inputs.
pub fn solve(model: &GraspModel) -> Result<Solution, ModelError> {
    GraspSolver::new(model.clone(), SolveOptions::default()).solve(&StepInputs::of_scene(model))
}
