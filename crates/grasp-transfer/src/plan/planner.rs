//! The planner's loop: run the hand-off along the current keyframe path with the steps'
//! load sensitivities, linearise the slip margins, take the trust-region program's step
//! ([`crate::plan::trust_region_qp`]), run it, keep it if the merit fell as predicted
//! (ratio test), else shrink the region; stop when the predicted gain is below the tolerance,
//! the region collapses or the runs run out. The answer is re-run from its schedule file's
//! text, as `grasp transfer` reads it, and checked before it is reported.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use grasp_model::{GraspModel, LoadDirection, LoadedScene, MarginOptions, Scene};

use crate::plan::binding_reason::{between_steps, explain, Evidence};
use crate::plan::disturbance_rows::{difference_options, disturbance_rows, load_step_n, raised};
use crate::plan::keyframe_path::KeyframePath;
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::plan::option_names;
use crate::plan::plan_error::PlanError;
use crate::plan::plan_options::{Objective, PlanOptions};
use crate::plan::plan_report::{
    binding_row, run_warnings, smallest_margins, smallest_of_run, Binding, CheckedAt, PlanReport,
    FINE_STEPS,
};
use crate::plan::slip_rows::{load_directions, slip_rows};
use crate::plan::start_diagnosis::no_equilibrium;
use crate::plan::starting_path::{starting_path, Template};
use crate::plan::trust_region_qp::{qp_step, Pinned, VIOLATION_WEIGHT};
use crate::schedule::Schedule;
use crate::schedule_spec::{PhaseSpec, ScheduleSpec};
use crate::slip_margin::SLIP_MARGIN_RULE;
use crate::stepper::{StepRecord, Stepper, TransferOptions};

/// Relative change of the duration for the difference quotient of the margins with respect
/// to it (viscoelastic pads only).
const DURATION_STEP: f64 = 1e-2;

/// The state of the search: the path, its run's rows, and the merit.
struct Iterate {
    path: KeyframePath,
    rows: Vec<MarginRow>,
    merit: f64,
}

/// Where the search ended: its last accepted iterate, the iterations it made and why it
/// stopped.
struct SearchEnd {
    /// The last accepted iterate.
    best: Iterate,
    /// Trust-region iterations made.
    iterations: usize,
    /// Why it stopped (options named as [`option_names`] spells them).
    stopped: String,
}

/// The runs of one planning: the scene, its model, what the planned schedules keep.
struct Runner<'a> {
    scene: &'a Scene,
    model: GraspModel,
    others: BTreeMap<String, Vec<PhaseSpec>>,
    options: &'a PlanOptions,
    runs: usize,
    notes: Vec<String>,
    /// The plan started from a template.
    template: bool,
}

/// Plans the hand-off of `scene` (see the module); `template`: the user's schedule, the
/// starting point and the comparison.
pub fn plan(
    scene: &LoadedScene,
    template: Option<Template<'_>>,
    options: &PlanOptions,
) -> Result<PlanReport, PlanError> {
    let clock = Instant::now();
    let names = scene.finger_names();
    let problems = options.problems(&names);
    if !problems.is_empty() {
        return Err(PlanError::Options(problems));
    }
    let model =
        GraspModel::from_loaded_with(scene, options.solve.compliance).map_err(PlanError::Scene)?;
    let mut runner = Runner {
        scene,
        model,
        others: BTreeMap::new(),
        options,
        runs: 0,
        notes: Vec::new(),
        template: template.is_some(),
    };
    let template_margins = match &template {
        Some(t) => {
            runner.others = t.others(options);
            Some(runner.run_schedule(t.schedule, None, runner.check_margins())?)
        }
        None => None,
    };
    let (path, pinned) = starting_path(
        scene,
        template.as_ref(),
        template_margins.as_deref(),
        options,
    )?;
    let end = runner.search(path, &pinned)?;
    runner.verify(end, template_margins, clock)
}

impl Runner<'_> {
    /// Runs `schedule` (sensitivities and margins on request), every step kept.
    fn run_schedule(
        &mut self,
        schedule: &Schedule,
        directions: Option<Vec<LoadDirection>>,
        margins: Option<MarginOptions>,
    ) -> Result<Vec<StepRecord>, PlanError> {
        self.runs += 1;
        let options = TransferOptions {
            keep_going: true,
            sensitivities: directions.is_some(),
            margins: margins.is_some(),
            margin_options: margins.unwrap_or_default(),
            solve: self.options.solve,
            ..TransferOptions::default()
        };
        Stepper::with_model(self.scene, &self.model, schedule, options)
            .with_load_directions(directions.unwrap_or_default())
            .collect::<Result<Vec<_>, _>>()
            .map_err(PlanError::Transfer)
    }

    /// The schedule file of `path`.
    fn spec(&self, path: &KeyframePath) -> ScheduleSpec {
        let receiving = match self.options.receiving.as_slice() {
            [] => String::new(),
            r => format!(", {} take over", r.join(", ")),
        };
        let what = format!(
            "Planned hand-off (grasp plan): {} let go{receiving}; linear ramps through {} \
             keyframes over {:.3} s.",
            self.options.releasing.join(", "),
            path.fractions.len(),
            path.duration_s
        );
        path.to_spec(what, &self.others)
    }

    /// Runs `path` and linearises its margins (with the duration's quotient for viscoelastic
    /// pads): the iterate, or the first step that found no equilibrium.
    fn evaluate(
        &mut self,
        path: KeyframePath,
        reference_s: f64,
    ) -> Result<Result<Iterate, Box<StepRecord>>, PlanError> {
        let margins = self.options.min_margin_n.map(|_| difference_options());
        let records = self.run_path(&path, true, margins)?;
        if let Some(r) = records.iter().find(|r| !r.solution.status.has_forces()) {
            return Ok(Err(Box::new(r.clone())));
        }
        let mut rows = slip_rows(&path, &records, &mut self.notes);
        if let Some(threshold_n) = self.options.min_margin_n {
            let step_n = load_step_n(&path);
            let raised_runs = (0..path.groups.len())
                .map(|g| self.run_path(&raised(&path, g, step_n), false, margins))
                .collect::<Result<Vec<_>, _>>()?;
            rows.extend(disturbance_rows(
                &path,
                &records,
                &raised_runs,
                step_n,
                threshold_n,
                &mut self.notes,
            ));
        }
        if self.model.is_viscoelastic() {
            self.add_per_duration(&path, &mut rows, margins)?;
        }
        let merit = merit(&rows, &path, path.duration_s / reference_s, self.options);
        Ok(Ok(Iterate { path, rows, merit }))
    }

    /// Each row's derivative in the duration, from a run of `path` stretched by
    /// [`DURATION_STEP`] (viscoelastic pads relax with time).
    fn add_per_duration(
        &mut self,
        path: &KeyframePath,
        rows: &mut [MarginRow],
        margins: Option<MarginOptions>,
    ) -> Result<(), PlanError> {
        let mut longer = path.clone();
        longer.duration_s *= 1.0 + DURATION_STEP;
        let shifted = self.run_path(&longer, false, margins)?;
        let dt = longer.duration_s - path.duration_s;
        for row in rows {
            let Some(step) = shifted.get(row.step) else {
                continue;
            };
            let other = match row.kind {
                RowKind::Slip => step
                    .solution
                    .finger(&row.finger)
                    .map(|f| 1.0 - f.friction_utilization),
                RowKind::Disturbance => step
                    .margin
                    .as_ref()
                    .zip(self.options.min_margin_n)
                    .map(|(m, n)| m.known_to_hold_n() / n),
            };
            if let Some(m) = other {
                row.per_duration = (m - row.margin) / dt;
            }
        }
        Ok(())
    }

    /// The runs one evaluation makes: the path, one raised run per group with a
    /// disturbance-margin threshold, one stretched run with viscoelastic pads.
    fn runs_per_evaluation(&self, groups: usize) -> usize {
        let raised = if self.options.min_margin_n.is_some() {
            groups
        } else {
            0
        };
        1 + raised + usize::from(self.model.is_viscoelastic())
    }

    /// The margin options of a checking run: those of `grasp transfer --margins` when a
    /// disturbance margin is constrained, else none.
    fn check_margins(&self) -> Option<MarginOptions> {
        let transfer = crate::TransferOptions::default().margin_options;
        self.options.min_margin_n.map(|_| transfer)
    }

    fn run_path(
        &mut self,
        path: &KeyframePath,
        sensitivities: bool,
        margins: Option<MarginOptions>,
    ) -> Result<Vec<StepRecord>, PlanError> {
        let spec = self.spec(path);
        let schedule = Schedule::from_spec(&spec, &self.scene.finger_names(), Path::new("."))
            .map_err(PlanError::Schedule)?;
        let directions = sensitivities.then(|| load_directions(path));
        self.run_schedule(&schedule, directions, margins)
    }
}

/// The merit of rows along `path` at a duration `relative` to the reference: see
/// [`PlanOptions::tolerance`], plus 100 times the largest violation of the disturbance rows
/// (each kept at least 1) and of the load-rate limit ([`rate_violation`]).
fn merit(rows: &[MarginRow], path: &KeyframePath, relative: f64, options: &PlanOptions) -> f64 {
    let least = |kind: RowKind| {
        let of_kind = rows.iter().filter(|r| r.kind == kind);
        of_kind.map(|r| r.margin).fold(f64::INFINITY, f64::min)
    };
    let slip = least(RowKind::Slip).min(1.0);
    let disturbance = VIOLATION_WEIGHT * (1.0 - least(RowKind::Disturbance)).max(0.0);
    let rate = VIOLATION_WEIGHT * rate_violation(path, options);
    disturbance
        + rate
        + match options.objective {
            Objective::Duration => {
                relative + VIOLATION_WEIGHT * (options.min_slip_margin - slip).max(0.0)
            }
            Objective::Margin => -slip,
        }
}

/// How far the steepest keyframe span of `path` exceeds the load-rate limit, relative to it,
/// beyond 1e-6 of it (the program's own accuracy, as the check counts it): 0 within. A
/// path starts above it when the template's ramps are steeper than the limit at a duration
/// the plan cannot stretch (the margin objective's); the program's steps keep the limit, and
/// this term lets the merit see the gain.
fn rate_violation(path: &KeyframePath, options: &PlanOptions) -> f64 {
    let shortest_s = path.shortest_duration_s(&options.rate_limits());
    let excess = shortest_s / path.duration_s - 1.0;
    if excess > 1e-6 {
        excess
    } else {
        0.0
    }
}

impl Runner<'_> {
    /// The trust-region iteration from `path`: where it ended.
    fn search(&mut self, path: KeyframePath, pinned: &Pinned) -> Result<SearchEnd, PlanError> {
        let start_s = path.duration_s;
        let mut current = match self.evaluate(path.clone(), start_s)? {
            Ok(iterate) => iterate,
            Err(step) => {
                let template = self.template;
                let diagnosis = no_equilibrium(&step, &path, &self.model, self.options, template);
                return Err(diagnosis);
            }
        };
        let scale = current
            .path
            .values
            .iter()
            .flatten()
            .fold(0.0, |a: f64, &b| a.max(b.abs()));
        let scale = scale.max(f64::MIN_POSITIVE);
        let mut radius = 0.25 * scale;
        let mut iterations = 0;
        let stopped = loop {
            let per_evaluation = self.runs_per_evaluation(current.path.groups.len());
            if self.runs + per_evaluation + 1 > self.options.max_runs {
                break format!("it made the runs allowed (`{}`)", option_names::MAX_RUNS);
            }
            iterations += 1;
            let base = merit(&current.rows, &current.path, 1.0, self.options);
            let step = qp_step(
                &current.path,
                &current.rows,
                pinned,
                self.options,
                radius,
                scale,
            )
            .map_err(PlanError::Program)?;
            let predicted = base - step.predicted_merit;
            if predicted < self.options.tolerance {
                break format!(
                    "it converged: the next step's predicted gain {:.2e} is below the tolerance {}",
                    predicted.max(0.0),
                    grasp_model::Readable(self.options.tolerance)
                );
            }
            let mut trial = current.path.clone();
            trial.values = step.values;
            trial.duration_s = step.duration_s;
            let reference = current.path.duration_s;
            let trial = self.evaluate(trial, reference)?.ok();
            let ratio = trial
                .as_ref()
                .map_or(f64::NEG_INFINITY, |t| (base - t.merit) / predicted);
            match trial {
                Some(t) if ratio > 0.1 => {
                    if ratio > 0.75 {
                        radius = (2.0 * radius).min(scale);
                    }
                    current = t;
                }
                _ => {
                    radius /= 4.0;
                    if radius < 1e-6 * scale {
                        break "the trust region shrank below 1e-6 of the load scale".to_string();
                    }
                }
            }
        };
        Ok(SearchEnd {
            best: current,
            iterations,
            stopped,
        })
    }

    /// Re-runs the search's best iterate from its schedule file's text, as `grasp transfer`
    /// reads it, and at [`FINE_STEPS`] when it has fewer, and reports what it keeps.
    fn verify(
        &mut self,
        end: SearchEnd,
        template: Option<Vec<StepRecord>>,
        clock: Instant,
    ) -> Result<PlanReport, PlanError> {
        let SearchEnd {
            best,
            iterations,
            stopped,
        } = end;
        let spec = self.spec(&best.path);
        let text = serde_json::to_string(&spec).map_err(|e| PlanError::Program(e.to_string()))?;
        let schedule = Schedule::from_json_str(&text, &self.scene.finger_names(), Path::new("."))
            .map_err(PlanError::Schedule)?;
        let records = self.run_schedule(&schedule, None, self.check_margins())?;
        let mut binding = binding_row(&records, &best.path, self.options);
        if let Some(b) = binding.as_mut().filter(|b| b.why.is_empty()) {
            let evidence = Evidence {
                rows: &best.rows,
                path: &best.path,
                records: &records,
                stopped: &stopped,
                options: self.options,
            };
            b.why = explain(b, &evidence);
        }
        let (checked, fine_binding) = self.fine_check(&best.path)?;
        let binding = binding.or(fine_binding);
        let template_duration_s = template
            .as_ref()
            .and_then(|t| Some(t.last()?.time_s - t.first()?.time_s));
        Ok(PlanReport {
            met: binding.is_none(),
            binding,
            duration_s: best.path.duration_s,
            template_duration_s,
            margins: smallest_margins(&records),
            slip_margin_rule: SLIP_MARGIN_RULE,
            smallest_not_counted: smallest_of_run(&records, false),
            checked,
            template_margins: template.as_deref().map(smallest_margins),
            keyframes_s: best
                .path
                .fractions
                .iter()
                .map(|f| f * best.path.duration_s)
                .collect(),
            loads_n: finger_commands(&best.path, false),
            approaches_m: finger_commands(&best.path, true),
            runs: self.runs,
            iterations,
            stopped,
            notes: std::mem::take(&mut self.notes),
            warnings: run_warnings(&records),
            time_s: clock.elapsed().as_secs_f64(),
            schedule: spec,
        })
    }

    /// The check of `path`'s ramps at [`FINE_STEPS`] when its schedule has fewer: the resolutions checked, and the slip margin or equilibrium the finer run
    /// breaks (a run of the check: not counted in [`PlanOptions::max_runs`]).
    fn fine_check(
        &mut self,
        path: &KeyframePath,
    ) -> Result<(CheckedAt, Option<Binding>), PlanError> {
        let mut checked = CheckedAt {
            schedule_steps: path.steps + 1,
            schedule_step_s: path.step_s(),
            fine_steps: None,
            fine_step_s: None,
            fine_smallest: None,
        };
        if path.steps >= FINE_STEPS {
            return Ok((checked, None));
        }
        let mut fine = path.clone();
        fine.steps = FINE_STEPS;
        let records = self.run_path(&fine, false, None)?;
        self.runs -= 1;
        checked.fine_steps = Some(FINE_STEPS + 1);
        checked.fine_step_s = Some(fine.step_s());
        checked.fine_smallest = smallest_of_run(&records, true);
        let mut binding = binding_row(&records, &fine, self.options);
        if let Some(b) = binding.as_mut().filter(|b| b.why.is_empty()) {
            let evidence = Evidence {
                rows: &[],
                path: &fine,
                records: &records,
                stopped: "",
                options: self.options,
            };
            b.why = between_steps(b, &checked, &evidence);
        }
        Ok((checked, binding))
    }
}

/// Each planned finger's loads at the keyframes, N, or (`approach`) its approaches, m.
fn finger_commands(path: &KeyframePath, approach: bool) -> Vec<(String, Vec<f64>)> {
    let groups = path.groups.iter().zip(&path.values);
    groups
        .filter(|(g, _)| g.is_approach() == approach)
        .flat_map(|(g, values)| {
            let member = |(m, (name, _)): (usize, &(String, f64))| {
                let commands = values.iter().map(|x| g.member_value(m, *x)).collect();
                (name.clone(), commands)
            };
            g.members.iter().enumerate().map(member).collect::<Vec<_>>()
        })
        .collect()
}
