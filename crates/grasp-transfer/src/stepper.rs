//! Quasi-static stepping of a hand-off (thesis section 4.2.1).
//!
//! At each step the schedule gives every finger a command (held, prescribed load, released);
//! the active fingers and their controls form the step's grasp, solved by the scene's model
//! (energy, or coulomb with its sequential solve).
//!
//! - Warm stepping reuses the model, the program and the solver of the same structure (active
//!   set and which fingers are force-controlled): only loads, radii and memory change. Every
//!   step starts from the previous step's solution (the native solver's Newton iteration from
//!   its forces and multipliers, reusing its factorisations while the stick / slip / separation
//!   pattern holds), and the sequential solve from the previous step's forces. A new structure
//!   starts cold.
//! - Cold stepping rebuilds the model and the program at every step and starts every convex
//!   solve from scratch, every sequential solve from an energy-model solve (the reference for
//!   checking and benchmarking).
//! - A step's model is the scene's model restricted to the active fingers
//!   ([`GraspModel::restricted`]): their compliance blocks are shared, not recomputed.
//! - The contact state (slip memory of the coulomb model) follows each finger by name from
//!   step to step, in warm and cold stepping alike: it is physics, not a guess. A released
//!   finger's memory is cleared (a new contact starts without slip).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::time::Instant;

use grasp_model::{
    sensor_readings_drawn, ContactState, Control, FingerState, GraspModel, GraspSolver,
    LoadDirection, LoadedScene, MarginOptions, Scene, SceneError, Sensitivities, SensorReadings,
    Solution, SolveOptions, SolvedStep, SolverStats, StepInputs,
};
use serde::Serialize;

use crate::error::TransferError;
use crate::schedule::{Command, ExternalWrench, Schedule};
use crate::schedule_scene_checks::schedule_against_scene;
use crate::step_margin::{step_margin, MarginPath, StepMargin};

/// Options of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransferOptions {
    /// Continue past a step without equilibrium (default: stop there).
    pub keep_going: bool,
    /// Reuse assembled programs between steps and start sequential solves from the previous
    /// step's forces (default true).
    pub warm_start: bool,
    /// Options of each solve.
    pub solve: SolveOptions,
    /// Compute each solved step's smallest disturbance margin ([`crate::step_margin`]): each
    /// step's search starts from the last step's margins (two solves per axis direction and
    /// step when they move smoothly).
    pub margins: bool,
    /// With `margins`, search every step's margins from scratch instead (about 10 to 20
    /// solves per axis direction and step; the reference the continued search is checked
    /// against).
    pub margins_from_scratch: bool,
    /// With `margins`, the summary says when the smallest margin first fell below this many
    /// newtons.
    pub margin_threshold_n: Option<f64>,
    /// With `margins`, the options of the margins' search (its bisection tolerance above all;
    /// the default's is 1e-3 of the margin).
    pub margin_options: MarginOptions,
    /// Differentiate every solved step ([`GraspSolver::sensitivities`]: the finger forces'
    /// derivatives with respect to the commanded loads and an extra wrench, from the KKT
    /// system at the step's active set), kept in [`StepRecord::sensitivities`] (the
    /// planner's linearisation).
    pub sensitivities: bool,
}

impl Default for TransferOptions {
    fn default() -> Self {
        TransferOptions {
            keep_going: false,
            warm_start: true,
            solve: SolveOptions::default(),
            margins: false,
            margins_from_scratch: false,
            margin_threshold_n: None,
            // A hand-off's margins are continued from step to step for a few solves each; the
            // probe would cost several times that, so a hand-off asks for it.
            margin_options: MarginOptions {
                probe_equilibria: false,
                ..MarginOptions::default()
            },
            sensitivities: false,
        }
    }
}

/// A finger's command at one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FingerCommand {
    /// Finger name.
    pub name: String,
    /// What it was told.
    pub command: Command,
}

/// Everything recorded at one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepRecord {
    /// Step index (0-based).
    pub index: usize,
    /// Schedule time, s.
    pub time_s: f64,
    /// Command of every scene finger, scene order.
    pub commands: Vec<FingerCommand>,
    /// The solution of the active fingers (status, forces, residuals, solver statistics).
    pub solution: Solution,
    /// Wall time of the step (model and program building if any, solve), s.
    pub wall_time_s: f64,
    /// True when the step reused an assembled program (warm).
    pub reused_program: bool,
    /// The scheduled external force at the centre of mass, N (zero without one).
    pub external_force_n: [f64; 3],
    /// The scheduled external couple, N m (zero without one).
    pub external_torque_nm: [f64; 3],
    /// The step's smallest disturbance margin, when asked for and the step solved.
    pub margin: Option<StepMargin>,
    /// The step's sensitivities, when asked for and the step solved (`Err`: why there are
    /// none, such as a solution Clarabel answered). Not logged.
    #[serde(skip)]
    pub sensitivities: Option<Result<Sensitivities, String>>,
    /// The tactile sensors' readings of the step's active fingers with a `sensor`, scene
    /// order ([`grasp_model::sensor_readings_drawn`], the step's index the noise's draw); empty when the scene has none or the step
    /// found no forces.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<SensorReadings>,
}

impl StepRecord {
    /// The normal force of scene finger `name` (0 if released or failed), N.
    pub fn normal_force_n(&self, name: &str) -> f64 {
        self.solution.finger(name).map_or(0.0, |f| f.normal_force_n)
    }
}

/// The structure of a step: each active finger's scene index and whether it is
/// force-controlled (a program is assembled once per structure).
type StructureKey = Vec<(usize, bool)>;

/// What a cached solver answers: a structure, and the length of the steps it solves (a
/// viscoelastic program is one time step's).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct ProgramKey {
    structure: StructureKey,
    /// The time step's bits (0 for an elastic scene).
    time_step_bits: u64,
}

impl ProgramKey {
    /// The time step, s.
    fn time_step_s(&self) -> f64 {
        f64::from_bits(self.time_step_bits)
    }
}

/// A cached program is reused while the step's load scale is within this factor range of the
/// scale the program was built with (the scaled problem stays well conditioned).
const PROGRAM_REUSE_SCALE_RANGE: std::ops::RangeInclusive<f64> = 1e-3..=1e3;

/// The structure of a step and the loads of its force-controlled fingers (N), in order.
fn structure_of(commands: &[Command]) -> (StructureKey, Vec<f64>) {
    let key = commands
        .iter()
        .enumerate()
        .filter_map(|(i, c)| match c {
            Command::Held | Command::Approach(_) => Some((i, false)),
            Command::Load(_) => Some((i, true)),
            Command::Released => None,
        })
        .collect();
    let loads = commands
        .iter()
        .filter_map(|c| match c {
            Command::Load(p) => Some(*p),
            _ => None,
        })
        .collect();
    (key, loads)
}

/// Where a step is: its index, its schedule time and the scheduled external wrench there.
#[derive(Debug, Clone, Copy)]
struct StepTime {
    /// Step index (0-based).
    index: usize,
    /// Schedule time, s.
    time_s: f64,
    /// The scheduled external wrench at the centre of mass, if any.
    external: Option<ExternalWrench>,
}

/// What the schedule commands at a step: the loads of the force-controlled fingers (N, in
/// order), every finger's command, and the scheduled external wrench.
struct StepCommands<'c> {
    loads: &'c [f64],
    commands: &'c [Command],
    external: Option<ExternalWrench>,
    /// The step's index: its sensors' read-out (the noise's draw).
    index: usize,
}

/// A step's answer: the solution, its margin and sensitivities when asked for, and its
/// sensors' readings.
struct Solved {
    solution: Solution,
    margin: Option<StepMargin>,
    sensitivities: Option<Result<Sensitivities, String>>,
    sensors: Vec<SensorReadings>,
}

/// Steps a schedule over a scene.
pub struct Stepper<'a> {
    scene: &'a Scene,
    /// The model of the whole scene (every finger as written), or why there is none.
    base: Result<Cow<'a, GraspModel>, SceneError>,
    schedule: &'a Schedule,
    options: TransferOptions,
    /// Per structure and time step (the step's bits; 0 for an elastic scene), the solver of
    /// the step's model.
    cache: BTreeMap<ProgramKey, GraspSolver>,
    /// Schedule time of the last step that found forces, s (the next step's viscoelastic
    /// history runs from it).
    last_solved_s: Option<f64>,
    /// Contact state of each active finger, by name.
    states: BTreeMap<String, FingerState>,
    /// Normal force of each scene finger at the last successful step, N.
    previous_normal_n: Vec<f64>,
    /// Per scene finger: `(phase index, resolved "current" value N)` of its active phase.
    current: Vec<Option<(usize, f64)>>,
    next: usize,
    stopped: bool,
    /// Largest external load (weight, external forces), N.
    external_scale_n: f64,
    /// The margins' searches along the path, when margins are asked for.
    margin_path: Option<MarginPath>,
    /// Extra columns of the sensitivities: loads moved together.
    load_directions: Vec<LoadDirection>,
}

impl<'a> Stepper<'a> {
    /// A stepper at the first step. The schedule must have been resolved against this scene.
    pub fn new(scene: &'a LoadedScene, schedule: &'a Schedule, options: TransferOptions) -> Self {
        Self::build(
            scene,
            GraspModel::from_loaded_with(scene, options.solve.compliance).map(Cow::Owned),
            schedule,
            options,
        )
    }

    /// A stepper on `model`, the model of `scene` as written (built by the caller, who also
    /// hands it to the sinks: the scene's model is built once per run).
    pub fn with_model(
        scene: &'a Scene,
        model: &'a GraspModel,
        schedule: &'a Schedule,
        options: TransferOptions,
    ) -> Self {
        Self::build(scene, Ok(Cow::Borrowed(model)), schedule, options)
    }

    fn build(
        scene: &'a Scene,
        base: Result<Cow<'a, GraspModel>, SceneError>,
        schedule: &'a Schedule,
        mut options: TransferOptions,
    ) -> Self {
        let n = scene.fingers.len();
        // Every step's margins in the units of the whole scene (its reach and load scale),
        // as `grasp margin` measures them, whichever fingers the step holds with.
        if let Ok(model) = &base {
            options.margin_options = options.margin_options.in_units_of(model);
        }
        Stepper {
            scene,
            base,
            schedule,
            options,
            cache: BTreeMap::new(),
            last_solved_s: None,
            states: BTreeMap::new(),
            previous_normal_n: vec![0.0; n],
            current: vec![None; n],
            next: 0,
            stopped: false,
            external_scale_n: scene
                .object
                .external_forces
                .iter()
                .map(|r| r.force.iter().map(|c| c * c).sum::<f64>().sqrt())
                .fold(scene.object.weight, f64::max)
                .max(schedule.external_scale()),
            margin_path: (options.margins && !options.margins_from_scratch)
                .then(|| MarginPath::with_options(options.margin_options)),
            load_directions: Vec::new(),
        }
    }

    /// With `sensitivities`, also differentiate along these combinations of commanded loads
    /// (columns `loads:<name>`; [`GraspSolver::sensitivities_along`]).
    pub fn with_load_directions(mut self, directions: Vec<LoadDirection>) -> Self {
        self.load_directions = directions;
        self
    }

    /// Number of steps of the schedule.
    pub fn len(&self) -> usize {
        self.schedule.times.len()
    }

    /// True for a schedule without steps.
    pub fn is_empty(&self) -> bool {
        self.schedule.times.is_empty()
    }

    fn scene_command(&self, i: usize) -> Command {
        let control = &self.scene.fingers[i].control;
        match (control.normal_load_n(), control.approach_m()) {
            (Some(p), _) if p > 0.0 => Command::Load(p),
            (Some(_), _) => Command::Released,
            // Pressed in, or opened short of first touch (a withdrawn jaw); 0 is held.
            (None, Some(d)) if d != 0.0 => Command::Approach(d),
            (None, _) => Command::Held,
        }
    }

    /// Loads the fingers carry in the scene as written (the `"current"` of a first step). If
    /// that grasp has no equilibrium, force-controlled fingers keep their commanded loads and a
    /// held finger's `"current"` cannot be resolved: a named error.
    /// With warm starts, the program (and its solution) is kept for the steps of the same
    /// structure: step 0 usually is one, and starts from it.
    fn initial_loads(&mut self) -> Result<Vec<Option<f64>>, TransferError> {
        let model = self.base_model(self.schedule.times[0])?;
        let inputs = StepInputs::of_scene(model);
        let mut solver = GraspSolver::new(model.clone(), self.options.solve);
        let sol = solver.solve(&inputs)?;
        if self.options.warm_start {
            let structure = model
                .fingers()
                .iter()
                .enumerate()
                .map(|(i, f)| (i, matches!(f.control(), Control::NormalLoad { .. })))
                .collect();
            let key = ProgramKey {
                structure,
                time_step_bits: 0,
            };
            self.cache.insert(key, solver);
        }
        Ok(self
            .scene
            .fingers
            .iter()
            .map(
                |f| match (sol.status.has_forces(), f.control.normal_load_n()) {
                    (true, _) => Some(sol.finger(&f.name).map_or(0.0, |s| s.normal_force_n)),
                    (false, Some(p)) => Some(p),
                    (false, None) => None,
                },
            )
            .collect::<Vec<_>>())
    }

    /// The model of the whole scene, or the scene's error (at schedule time `time_s`).
    fn base_model(&self, time_s: f64) -> Result<&GraspModel, TransferError> {
        match &self.base {
            Ok(model) => Ok(model),
            Err(e) => Err(TransferError::Scene {
                time_s,
                source: e.clone(),
            }),
        }
    }

    /// The options of a step's solves: warm starts only when the run starts warm.
    fn step_solve_options(&self) -> SolveOptions {
        let mut options = self.options.solve;
        options.warm_start &= self.options.warm_start;
        options
    }

    /// The commands of every finger at step `k`, resolving `"current"` on phase entry.
    fn commands(&mut self, k: usize) -> Result<Vec<Command>, TransferError> {
        let t = self.schedule.times[k];
        let mut out = Vec::with_capacity(self.scene.fingers.len());
        let mut initial: Option<Vec<Option<f64>>> = None;
        for i in 0..self.scene.fingers.len() {
            let phase = self.schedule.phase_index(i, t);
            if let Some(p) = phase {
                if self.current[i].map(|c| c.0) != Some(p) {
                    let value = if k == 0 {
                        let loads = match &mut initial {
                            Some(l) => l,
                            None => initial.insert(self.initial_loads()?),
                        };
                        loads[i].ok_or_else(|| TransferError::Current {
                            finger: self.scene.fingers[i].name.clone(),
                        })?
                    } else {
                        self.previous_normal_n[i]
                    };
                    self.current[i] = Some((p, value));
                }
            }
            let cur = self.current[i].map_or(0.0, |c| c.1);
            out.push(self.schedule.command(i, t, cur, self.scene_command(i)));
        }
        Ok(out)
    }

    /// The time step of step `k` at `t` s for the viscoelastic history: the time since the
    /// last step that found forces (0 at the first: the loads applied as a step); always 0 for
    /// an elastic scene.
    fn time_step_s(&self, t: f64) -> f64 {
        let viscous = self.base.as_ref().is_ok_and(|m| m.is_viscoelastic());
        match (viscous, self.last_solved_s) {
            (true, Some(prev)) => nine_digits(t - prev),
            _ => 0.0,
        }
    }

    /// Solves step `k` of the schedule.
    fn solve_step(&mut self, k: usize) -> Result<StepRecord, TransferError> {
        let start = Instant::now();
        let t = self.schedule.times[k];
        let external = self.schedule.external_at(t);
        let commands = self.commands(k)?;
        let (structure, loads) = structure_of(&commands);
        let key = ProgramKey {
            structure,
            time_step_bits: self.time_step_s(t).to_bits(),
        };
        let reused = self.reusable(&key, &loads);
        if !reused {
            if key.structure.is_empty() {
                // Nothing holds the object: a reported outcome, not an error.
                self.states.clear();
                let sol = empty_grasp_solution(self.scene);
                let solved = Solved {
                    solution: sol,
                    margin: None,
                    sensitivities: None,
                    sensors: Vec::new(),
                };
                let at = StepTime {
                    index: k,
                    time_s: t,
                    external,
                };
                return Ok(self.record(at, commands, solved, start, false));
            }
            self.build_program(t, &key, &commands)?;
        }
        let step = StepCommands {
            loads: &loads,
            commands: &commands,
            external,
            index: k,
        };
        let solved = self.solve_cached(&key, step)?;
        if solved.solution.status.has_forces() {
            self.last_solved_s = Some(t);
        }
        let at = StepTime {
            index: k,
            time_s: t,
            external,
        };
        Ok(self.record(at, commands, solved, start, reused))
    }

    /// True when the cached program of structure `key` can answer a step with `loads` (N):
    /// warm stepping, and the step's load scale within a factor 1e3 of the one the program was
    /// scaled with (the scaled problem stays well conditioned).
    fn reusable(&self, key: &ProgramKey, loads: &[f64]) -> bool {
        let step_scale = loads.iter().copied().fold(self.external_scale_n, f64::max);
        self.options.warm_start
            && self.cache.get(key).is_some_and(|solver| {
                let r = step_scale / solver.model().scales().load_n;
                step_scale <= 0.0 || PROGRAM_REUSE_SCALE_RANGE.contains(&r)
            })
    }

    /// Builds and caches the model and program of structure `key`: the scene's model
    /// restricted to the active fingers, each driven as `commands` says (a force-controlled
    /// finger's load sets the program's scale); its solves are of the key's time step.
    fn build_program(
        &mut self,
        t: f64,
        key: &ProgramKey,
        commands: &[Command],
    ) -> Result<(), TransferError> {
        let active: Vec<(usize, Control)> = commands
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.control().map(|control| (i, control)))
            .collect();
        // The full scene was validated; a subset of its fingers needs no new validation
        // (the reach heuristic, say, would judge the subset differently).
        let model = self
            .base_model(t)?
            .restricted(&active)
            .ok_or(TransferError::Internal(
                "a step's active fingers are not in the scene",
            ))?;
        let solver = GraspSolver::new(model, self.step_solve_options());
        if !self.options.warm_start {
            self.cache.clear();
        }
        self.cache.insert(key.clone(), solver);
        Ok(())
    }

    /// The contact state of the active fingers of `model`: each carries its own over by name;
    /// released fingers lose theirs.
    fn contact_state_of(&mut self, model: &GraspModel) -> ContactState {
        let active: Vec<&str> = model.fingers().iter().map(|f| f.name()).collect();
        self.states
            .retain(|name, _| active.contains(&name.as_str()));
        ContactState::of_fingers(
            model
                .fingers()
                .iter()
                .map(|f| {
                    self.states
                        .get(f.name())
                        .filter(|s| s.slip_memory_m.len() == f.patch().len())
                        .cloned()
                        .unwrap_or_else(|| FingerState::fresh(f.name(), f.patch().len()))
                })
                .collect(),
        )
    }

    /// The inputs of a step of `model` of `time_step_s` seconds: the loads (N) of its
    /// force-controlled fingers, every other active finger's approach as commanded (0 when
    /// held; m), and the scheduled external wrench at the centre of mass.
    fn step_inputs(&self, model: &GraspModel, step: &StepCommands, time_step_s: f64) -> StepInputs {
        let mut inputs = StepInputs::loads(step.loads.to_vec()).with_time_step(time_step_s);
        for (f, c) in self.scene.fingers.iter().zip(step.commands) {
            let d = match c {
                Command::Approach(d) => *d,
                Command::Held => 0.0,
                Command::Load(_) | Command::Released => continue,
            };
            if let Some((i, _)) = model.finger(&f.name) {
                inputs = inputs.with_approach(i, d);
            }
        }
        // A hand whose fingers are all released is not in the step's model: nothing to move.
        let t = self.schedule.times[step.index];
        for (name, pose) in self.schedule.hand_poses_at(t) {
            if let Some(j) = model.springs().iter().position(|s| s.name() == name) {
                inputs = inputs.with_hand_pose(j, pose);
            }
        }
        match step.external {
            Some(e) => {
                inputs.with_load_at_center_of_mass(model, &e.force_n.into(), &e.torque_nm.into())
            }
            None => inputs,
        }
    }

    /// Solves the cached program of `key` with the step's loads (N), the commands' approaches
    /// and the scheduled external wrench, and the step's margin when asked for.
    fn solve_cached(
        &mut self,
        key: &ProgramKey,
        step: StepCommands,
    ) -> Result<Solved, TransferError> {
        let options = self.options;
        let Some(mut solver) = self.cache.remove(key) else {
            return Err(TransferError::Internal("the step's program is not cached"));
        };
        let model = std::sync::Arc::clone(solver.shared_model());
        let mut state = self.contact_state_of(&model);
        let inputs = self.step_inputs(&model, &step, key.time_step_s());
        // A continued search starts its trials where the step's solve left the state, before
        // time moves on (no second solve of the step); one from scratch solves the step again
        // from its start.
        let continued = options.margins && self.margin_path.is_some();
        let before = (options.margins && !continued).then(|| state.clone());
        let solved = solver.solve_step(&inputs, &mut state);
        let after = continued.then(|| state.clone());
        if let Ok(sol) = &solved {
            if sol.status.has_forces() {
                state.advance_time_step(&model, sol);
            }
        }
        let margin = match (&solved, &mut self.margin_path, before, after) {
            (Ok(sol), Some(path), _, Some(after)) if sol.status.has_forces() => {
                let solved = SolvedStep {
                    state: &after,
                    solution: sol,
                };
                Some(path.step_margin(&model, &inputs, solved, options.solve))
            }
            (Ok(sol), None, Some(b), _) if sol.status.has_forces() => Some(step_margin(
                &model,
                &inputs,
                &b,
                options.solve,
                &options.margin_options,
            )),
            _ => None,
        };
        let mut sol = solved?;
        let sensitivities = (options.sensitivities && sol.status.has_forces()).then(|| {
            solver
                .sensitivities_along(&sol, &self.load_directions)
                .map_err(|e| e.to_string())
        });
        self.cache.insert(key.clone(), solver);
        let margin = margin.transpose()?;
        // A read-out refused (an automatic patch finer than the scene's: too many kernel
        // evaluations, named with its fix) is the step's warning, not the run's end.
        let sensors = match sol.status.has_forces() {
            true => sensor_readings_drawn(self.scene, &model, &sol, step.index as u64)
                .unwrap_or_else(|e| {
                    sol.warnings.push(e.to_string());
                    Vec::new()
                }),
            false => Vec::new(),
        };
        for f in state.fingers {
            self.states.insert(f.name.clone(), f);
        }
        Ok(Solved {
            solution: sol,
            margin,
            sensitivities,
            sensors,
        })
    }

    /// The record of the step `at`.
    fn record(
        &mut self,
        at: StepTime,
        commands: Vec<Command>,
        solved: Solved,
        start: Instant,
        reused: bool,
    ) -> StepRecord {
        let Solved {
            solution,
            margin,
            sensitivities,
            sensors,
        } = solved;
        let (external_force_n, external_torque_nm) = at
            .external
            .map_or(([0.0; 3], [0.0; 3]), |w| (w.force_n, w.torque_nm));
        if solution.status.has_forces() {
            for (i, f) in self.scene.fingers.iter().enumerate() {
                self.previous_normal_n[i] =
                    solution.finger(&f.name).map_or(0.0, |s| s.normal_force_n);
            }
        }
        StepRecord {
            index: at.index,
            time_s: at.time_s,
            commands: self
                .scene
                .fingers
                .iter()
                .zip(commands)
                .map(|(f, command)| FingerCommand {
                    name: f.name.clone(),
                    command,
                })
                .collect(),
            solution,
            // The margins' search is reported on its own (`margin.time_s`).
            wall_time_s: start.elapsed().as_secs_f64() - margin.as_ref().map_or(0.0, |m| m.time_s),
            reused_program: reused,
            external_force_n,
            external_torque_nm,
            margin,
            sensitivities,
            sensors,
        }
    }
}

impl Iterator for Stepper<'_> {
    type Item = Result<StepRecord, TransferError>;

    /// The next step, until the schedule ends (or a step fails without `keep_going`).
    fn next(&mut self) -> Option<Self::Item> {
        if self.stopped || self.next >= self.schedule.times.len() {
            return None;
        }
        let k = self.next;
        self.next += 1;
        if let Some(e) = (k == 0)
            .then(|| schedule_against_scene(self.scene, self.schedule))
            .flatten()
        {
            self.stopped = true;
            return Some(Err(e));
        }
        let r = self.solve_step(k);
        match &r {
            Ok(rec) if !rec.solution.status.has_forces() && !self.options.keep_going => {
                self.stopped = true
            }
            Err(_) => self.stopped = true,
            _ => {}
        }
        Some(r)
    }
}

/// `x` rounded to nine significant digits: the steps of a schedule's span (`start + i step`)
/// differ in their last bits, and equal steps must share one model (its compliance over the
/// step is built once per step length); the rounding moves a step by 1e-9 of itself at most.
fn nine_digits(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let scale = 10f64.powi(8 - x.log10().floor() as i32);
    (x * scale).round() / scale
}

/// The outcome of a step at which no finger is active.
fn empty_grasp_solution(scene: &Scene) -> Solution {
    Solution::without_forces(
        grasp_model::SolveStatus::NoEquilibrium,
        "no equilibrium: every finger is released, nothing holds the object".into(),
        scene.object.weight.max(1.0),
        SolverStats::no_solve(),
        0.0,
    )
}
