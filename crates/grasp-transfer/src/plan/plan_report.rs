//! What the planner answers: the checked schedule, whether it keeps every constraint (else
//! the one that binds: which, where, by how much), the slip margins (and the disturbance
//! margins, when constrained) along it beside the template's, and what the planning cost.

use serde::Serialize;

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::plan_options::PlanOptions;
use crate::schedule_spec::ScheduleSpec;
use crate::slip_margin::step_slip_margins;
use crate::stepper::StepRecord;
use crate::summary::SlipMargin;

/// A planned schedule counts as keeping the slip-margin threshold when its smallest margin is
/// at least the threshold minus this: the linearisation's error over the last step, which the
/// planner's tolerance bounds (a margin is dimensionless, of order 1).
pub const MARGIN_TOLERANCE: f64 = 1e-3;

/// A planned schedule counts as keeping the disturbance-margin threshold `N` when its smallest
/// disturbance margin is at least `N (1 - DISTURBANCE_TOLERANCE)`: the margin read is the
/// lower end of a bisection bracket 1e-3 of it wide (`grasp transfer --margins`), and the
/// linearisation's error over the last step is bounded as the slip margin's is
/// ([`MARGIN_TOLERANCE`], here relative to the threshold).
pub const DISTURBANCE_TOLERANCE: f64 = 2e-3;

/// A planned schedule of fewer steps than this is also run with its ramps sampled at this many
/// steps, and its slip margins and equilibrium checked there too: a margin can dip between the
/// schedule's own steps (a finger letting go is counted until it carries 5 % of the load
/// scale, whenever that falls), and a run at coarse steps steps over it.
pub const FINE_STEPS: usize = 600;

/// A releasing position-controlled finger counts as let go at the last step when its normal
/// force is at most this fraction of the load scale (round-off of the separated elements').
pub const RELEASED_FRACTION: f64 = 1e-9;

/// The smallest slip margin of a step under the slip-margin rule ([`crate::slip_margin`]), and
/// its smallest disturbance margin when that is constrained.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarginsAtStep {
    /// Schedule time, s.
    pub time_s: f64,
    /// `1 - |Q| / (mu P)`, smallest over the fingers carrying at least 5 % of the load scale
    /// (the rule of `grasp transfer`'s summary too); `None` when none does (or the step found
    /// no equilibrium).
    pub smallest: Option<f64>,
    /// The finger it belongs to.
    pub finger: Option<String>,
    /// The smallest disturbance margin over the axis directions, N (as a run with
    /// `TransferOptions::margins` finds it), when [`PlanOptions::min_margin_n`] is given and
    /// the step solved: infinite when unbounded (JSON null), the lower bound `held_to_n` when
    /// undetermined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub disturbance_n: Option<f64>,
}

/// The resolutions the planned schedule was checked at.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckedAt {
    /// Steps of the schedule's own run, the first included (its `time.step`, as `grasp
    /// transfer` runs it): every constraint checked at every one.
    pub schedule_steps: usize,
    /// The schedule's step, s.
    pub schedule_step_s: f64,
    /// When the schedule has fewer than [`FINE_STEPS`] steps: the steps of the second run of
    /// its ramps (the first included), at which the slip margins and equilibrium were checked too (the disturbance
    /// margins only at the schedule's own steps: each step's search costs many solves).
    pub fine_steps: Option<usize>,
    /// Its step, s.
    pub fine_step_s: Option<f64>,
    /// The smallest slip margin of that run (the rule's), with its time and finger.
    pub fine_smallest: Option<SlipMargin>,
}

/// A constraint the checked schedule does not keep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Binding {
    /// `slip margin`, `disturbance margin`, `equilibrium`, `load rate`, `approach speed` or
    /// `release` (a releasing finger still loaded at the last step).
    pub constraint: String,
    /// The finger, where one is concerned.
    pub finger: Option<String>,
    /// Schedule time, s.
    pub time_s: f64,
    /// The value reached (a slip margin, a disturbance margin in N, N/s, m/s, or the load a
    /// releasing finger still carries, N).
    pub value: f64,
    /// The limit it should keep.
    pub limit: f64,
    /// How far short of the limit it falls.
    pub short_by: f64,
    /// Why the planner could not do better, as far as it knows.
    pub why: String,
}

/// The planner's answer (forces N, times s).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanReport {
    /// True when the checked schedule keeps every constraint at every step.
    pub met: bool,
    /// Otherwise the constraint that binds.
    pub binding: Option<Binding>,
    /// The planned duration, s.
    pub duration_s: f64,
    /// The template's, s.
    pub template_duration_s: Option<f64>,
    /// The slip margins along the plan, re-run from its schedule file's text.
    pub margins: Vec<MarginsAtStep>,
    /// Which fingers the slip margins count, in words (the rule of `grasp transfer`'s summary
    /// too).
    pub slip_margin_rule: &'static str,
    /// The smallest slip margin along the plan of the loaded frictional fingers the rule leaves
    /// out (carrying less than 5 % of the load scale), with its time and finger.
    pub smallest_not_counted: Option<SlipMargin>,
    /// The resolutions the schedule was checked at.
    pub checked: CheckedAt,
    /// Along the template.
    pub template_margins: Option<Vec<MarginsAtStep>>,
    /// Keyframe times, s.
    pub keyframes_s: Vec<f64>,
    /// Per planned force-controlled finger, its loads at the keyframes, N.
    pub loads_n: Vec<(String, Vec<f64>)>,
    /// Per planned position-controlled finger, its approaches at the keyframes, m.
    pub approaches_m: Vec<(String, Vec<f64>)>,
    /// Hand-off runs made (the check included).
    pub runs: usize,
    /// Trust-region iterations.
    pub iterations: usize,
    /// Why the iteration stopped.
    pub stopped: String,
    /// What the user should know (derivatives missing at some steps, say).
    pub notes: Vec<String>,
    /// The warnings of the checked run's solves (as `grasp transfer` of the planned schedule
    /// gives them), each once with its steps ([`grasp_model::WarningTally`]); empty when it
    /// gave none.
    pub warnings: Vec<grasp_model::TalliedWarning>,
    /// Wall time of the planning, s.
    pub time_s: f64,
    /// The planned schedule file (`grasp transfer --schedule` runs it unchanged).
    pub schedule: ScheduleSpec,
}

impl PlanReport {
    /// The smallest slip margin along the plan, with its time and finger.
    pub fn smallest(&self) -> Option<&MarginsAtStep> {
        smallest_of(&self.margins)
    }

    /// Along the template.
    pub fn template_smallest(&self) -> Option<&MarginsAtStep> {
        self.template_margins.as_deref().and_then(smallest_of)
    }

    /// The report's texts (why the search stopped, why a constraint binds, the notes) with
    /// the option names ([`crate::plan_option_names`]) in a front end's spelling: `respell`
    /// rewrites one text.
    pub fn respell_options(&mut self, respell: impl Fn(&str) -> String) {
        self.stopped = respell(&self.stopped);
        if let Some(b) = self.binding.as_mut() {
            b.why = respell(&b.why);
        }
        self.notes.iter_mut().for_each(|n| *n = respell(n));
        for w in &mut self.warnings {
            w.message = respell(&w.message);
        }
    }
}

fn smallest_of(margins: &[MarginsAtStep]) -> Option<&MarginsAtStep> {
    margins
        .iter()
        .filter(|m| m.smallest.is_some())
        .min_by(|a, b| a.smallest.partial_cmp(&b.smallest).expect("finite margins"))
}

/// The warnings of a run's steps, each once with its steps.
pub fn run_warnings(records: &[StepRecord]) -> Vec<grasp_model::TalliedWarning> {
    let mut tally = grasp_model::WarningTally::new();
    for r in records {
        let at = grasp_model::SolveAt {
            index: r.index,
            time_s: Some(r.time_s),
        };
        tally.add(at, &r.solution.warnings);
    }
    tally.warnings()
}

/// The smallest slip margin of every step of a run.
pub fn smallest_margins(records: &[StepRecord]) -> Vec<MarginsAtStep> {
    records
        .iter()
        .map(|r| {
            let least = step_slip_margins(&r.solution).counted;
            MarginsAtStep {
                time_s: r.time_s,
                smallest: least.map(|l| l.margin),
                finger: least.map(|l| l.finger.to_string()),
                disturbance_n: r.margin.as_ref().map(|m| m.margin_or_bound_n()),
            }
        })
        .collect()
}

/// The smallest slip margin of a run: of the fingers the rule counts (`counted`), or of those
/// it leaves out.
pub fn smallest_of_run(records: &[StepRecord], counted: bool) -> Option<SlipMargin> {
    let mut least: Option<SlipMargin> = None;
    for r in records {
        let step = step_slip_margins(&r.solution);
        let which = if counted {
            step.counted
        } else {
            step.not_counted
        };
        let Some(step) = which else {
            continue;
        };
        if least.as_ref().is_none_or(|l| step.margin < l.margin) {
            least = Some(SlipMargin {
                margin: step.margin,
                time_s: r.time_s,
                finger: step.finger.to_string(),
            });
        }
    }
    least
}

/// The first constraint a checked run breaks: a step without equilibrium, a slip margin
/// below the threshold by more than [`MARGIN_TOLERANCE`], a releasing jaw still pressing at the
/// last step ([`RELEASED_FRACTION`]), a disturbance margin below its threshold by more than
/// [`DISTURBANCE_TOLERANCE`] of it, a load rate or an approach speed above its limit.
pub fn binding_row(
    records: &[StepRecord],
    path: &KeyframePath,
    options: &PlanOptions,
) -> Option<Binding> {
    if let Some(r) = records.iter().find(|r| !r.solution.status.has_forces()) {
        return Some(Binding {
            constraint: "equilibrium".into(),
            finger: None,
            time_s: r.time_s,
            value: 0.0,
            limit: 0.0,
            short_by: 0.0,
            why: "the grasp has no equilibrium at this step".into(),
        });
    }
    let worst = smallest_margins(records)
        .into_iter()
        .filter_map(|m| Some((m.smallest?, m)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((m, at)) = worst.filter(|w| w.0 < options.min_slip_margin - MARGIN_TOLERANCE) {
        return Some(Binding {
            constraint: "slip margin".into(),
            finger: at.finger,
            time_s: at.time_s,
            value: m,
            limit: options.min_slip_margin,
            short_by: options.min_slip_margin - m,
            why: String::new(),
        });
    }
    release_binding(records, path)
        .or_else(|| disturbance_binding(records, options))
        .or_else(|| rate_binding(path, options))
}

/// A releasing position-controlled finger still pressing at the last step by more than
/// [`RELEASED_FRACTION`] of the load scale: its jaw did not open far enough to let go (a
/// releasing force-controlled finger is released by its command of 0 N).
fn release_binding(records: &[StepRecord], path: &KeyframePath) -> Option<Binding> {
    let group = path.groups.first().filter(|g| g.is_approach())?;
    let last = records.last()?;
    let limit = RELEASED_FRACTION * last.solution.load_scale_n;
    let (m, name, load_n) = group
        .members
        .iter()
        .enumerate()
        .map(|(m, (name, _))| (m, name, last.normal_force_n(name)))
        .find(|(_, _, p)| *p > limit)?;
    let end_m = group.member_value(m, *path.values[0].last()?);
    Some(Binding {
        constraint: "release".into(),
        finger: Some(name.clone()),
        time_s: last.time_s,
        value: load_n,
        limit,
        short_by: load_n - limit,
        why: format!(
            "its jaw ends at approach {} m, where it still presses on the object: open it \
             further (`{}` below that)",
            grasp_model::Readable(end_m),
            crate::plan::option_names::OPEN_TO
        ),
    })
}

/// The step with the smallest disturbance margin, when it is below the threshold by more
/// than [`DISTURBANCE_TOLERANCE`] of it.
fn disturbance_binding(records: &[StepRecord], options: &PlanOptions) -> Option<Binding> {
    let limit = options.min_margin_n?;
    let with_margin = records.iter().filter_map(|r| Some((r, r.margin.as_ref()?)));
    let (r, m) =
        with_margin.min_by(|a, b| a.1.known_to_hold_n().total_cmp(&b.1.known_to_hold_n()))?;
    let held_n = m.known_to_hold_n();
    (held_n < limit * (1.0 - DISTURBANCE_TOLERANCE)).then(|| Binding {
        constraint: "disturbance margin".into(),
        finger: m.failing_finger.clone(),
        time_s: r.time_s,
        value: held_n,
        limit,
        short_by: limit - held_n,
        why: String::new(),
    })
}

/// The steepest keyframe span of the path relative to its group's rate limit, when it
/// exceeds it (beyond 1e-6 of it: the program's own accuracy): a `load rate` in N/s, or an
/// `approach speed` in m/s.
fn rate_binding(path: &KeyframePath, options: &PlanOptions) -> Option<Binding> {
    let limits = options.rate_limits();
    let mut worst: Option<(f64, usize, usize, f64)> = None;
    for (i, values) in path.values.iter().enumerate() {
        let Some(limit) = path.groups[i].variable_rate(&limits) else {
            continue;
        };
        for k in 0..values.len() - 1 {
            let dt = (path.fractions[k + 1] - path.fractions[k]) * path.duration_s;
            let relative = (values[k + 1] - values[k]).abs() / dt / limit;
            if worst.is_none_or(|w| relative > w.0) {
                worst = Some((relative, i, k, limit));
            }
        }
    }
    let (relative, i, k, _) = worst.filter(|w| w.0 > 1.0 + 1e-6)?;
    let group = &path.groups[i];
    let (constraint, limit) = if group.is_approach() {
        ("approach speed", options.max_speed_m_per_s?)
    } else {
        ("load rate", options.max_rate_n_per_s?)
    };
    Some(Binding {
        constraint: constraint.into(),
        finger: group
            .members
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|m| m.0.clone()),
        time_s: path.fractions[k] * path.duration_s,
        value: relative * limit,
        limit,
        short_by: (relative - 1.0) * limit,
        why: String::new(),
    })
}
