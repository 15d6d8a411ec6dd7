//! The closing summary of a hand-off: when the receiving fingers take half and all of the
//! load, the peak squeeze, the smallest slip margin, failed steps, cost, and the warnings of
//! its solves (each once, with the steps that gave it).

use serde::Serialize;

use crate::schedule::Command;
use crate::slip_margin::{step_slip_margins, FingerSlipMargin, SLIP_MARGIN_RULE};
use crate::stepper::StepRecord;
use grasp_model::{CompliancePath, SolveAt, TalliedWarning, WarningTally};

// A finger carries load when its normal force exceeds this fraction of the load scale (the
// model's one meaning of "loaded").
use grasp_model::LOADED_FRACTION;

/// The summary of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransferSummary {
    /// Steps recorded.
    pub steps: usize,
    /// Failed steps, the first [`MAX_LISTED_FAILED_STEPS`].
    pub failed_steps: Vec<FailedStep>,
    /// Number of failed steps.
    pub failed_step_count: usize,
    /// Fingers loaded at the first successful step and unloaded at the last.
    pub releasing: Vec<String>,
    /// Fingers loaded at the last successful step (those holding the object at the end,
    /// touching it from the start or not).
    pub receiving: Vec<String>,
    /// First time the receiving fingers carry at least as much normal force as the releasing
    /// ones, s.
    pub half_transfer_time_s: Option<f64>,
    /// First time the releasing fingers carry no load, s.
    pub full_transfer_time_s: Option<f64>,
    /// Largest total normal force of all fingers, N, and when, s.
    pub peak_squeeze_n: f64,
    /// Time of the peak squeeze, s.
    pub peak_squeeze_time_s: f64,
    /// Smallest slip margin `1 - |Q|/(mu P)` over the fingers the rule counts
    /// ([`Self::slip_margin_rule`]: frictional, carrying at least 5 % of the load scale), the
    /// figure `grasp plan` keeps at its threshold.
    pub smallest_slip_margin: Option<SlipMargin>,
    /// Smallest slip margin of the loaded frictional fingers the rule leaves out (carrying less
    /// than 5 % of the load scale: letting go, or just touching).
    pub smallest_slip_margin_not_counted: Option<SlipMargin>,
    /// Which fingers [`Self::smallest_slip_margin`] counts, in words.
    pub slip_margin_rule: &'static str,
    /// Largest relative equilibrium residual over the steps.
    pub worst_equilibrium_residual: f64,
    /// Sum of step wall times, s.
    pub total_wall_time_s: f64,
    /// Sum of iterations (Newton steps of the native solver, interior-point iterations of
    /// Clarabel).
    pub total_iterations: u64,
    /// Sum of reduced matrices factorised by the native solver.
    pub total_factorizations: u64,
    /// Sum of conjugate-gradient iterations of the FFT compliance path (0 on the dense path).
    pub total_inner_iterations: u64,
    /// The form of the patch compliances over the run's steps (`mixed` when some steps'
    /// active fingers were dense and others' FFT, or both within a step).
    pub compliance: grasp_model::CompliancePath,
    /// Steps answered by the native solver and by Clarabel.
    pub answered_by_native: usize,
    /// Steps answered by Clarabel (`--solver clarabel`, or a fallback).
    pub answered_by_clarabel: usize,
    /// Steps where the native solver handed over to Clarabel, and the first reason.
    pub fallbacks: Fallbacks,
    /// Steps that started from the previous step's solution.
    pub warm_steps: usize,
    /// Sequential solves (coulomb model, load-dependent mu): totals over the steps.
    pub sequential: Option<SequentialTotals>,
    /// The least safe step, when margins were computed.
    pub least_safe_step: Option<LeastSafeStep>,
    /// Solves and wall time spent on the margins.
    pub margin_cost: MarginCost,
    /// Steps whose margins' failing ends the coulomb law gives a second equilibrium, and the
    /// first (absent when none).
    #[serde(skip_serializing_if = "OtherEquilibria::is_empty")]
    pub other_equilibria: OtherEquilibria,
    /// Per held or position-controlled finger whose normal force fell while its command stayed
    /// the same (a viscoelastic pad relaxing; also load taken over by other fingers), the
    /// largest such fall, by finger in scene order.
    pub held_relaxation: Vec<HeldRelaxation>,
    /// The first step whose smallest disturbance margin fell below the threshold asked for
    /// (`TransferOptions::margin_threshold_n`), when margins were computed.
    pub margin_below_threshold: Option<MarginCrossing>,
    /// The warnings of the steps' solves (the scene's, carried by every solve, among them),
    /// each once with the steps that gave it and how many ([`grasp_model::WarningTally`]),
    /// in the order they first came.
    pub warnings: Vec<TalliedWarning>,
    /// Distinct warnings beyond [`grasp_model::MAX_TALLIED_WARNINGS`], not listed.
    #[serde(skip_serializing_if = "is_zero")]
    pub warnings_not_listed: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// The largest fall of a held (or position-controlled) finger's normal force under one
/// unchanged command.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldRelaxation {
    /// The finger.
    pub finger: String,
    /// The force the fall started from (its largest under the command), N, and when, s.
    pub from_n: f64,
    /// When the fall started, s.
    pub from_time_s: f64,
    /// The force it fell to, N.
    pub to_n: f64,
    /// When, s.
    pub to_time_s: f64,
    /// `1 - to / from`.
    pub fraction: f64,
    /// The unchanged command was an approach (a position-controlled finger pressed in by a
    /// fixed depth), not a hold.
    pub position_controlled: bool,
}

/// When the smallest disturbance margin first fell below a threshold.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarginCrossing {
    /// The threshold, N.
    pub threshold_n: f64,
    /// Step index.
    pub step: usize,
    /// Schedule time, s.
    pub time_s: f64,
    /// The step's smallest margin, N (`None` when undetermined: then `held_to_n`, the largest
    /// push known to hold, is below the threshold).
    pub margin_n: Option<f64>,
    /// The largest push known to hold along the smallest direction, N.
    pub held_to_n: f64,
}

/// A step that found no forces.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FailedStep {
    /// Step index.
    pub step: usize,
    /// Schedule time, s.
    pub time_s: f64,
    /// Why the step failed (the solution's reason).
    pub reason: String,
}

/// Where a loaded frictional finger came closest to sliding.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlipMargin {
    /// `1 - |Q|/(mu P)`: 0 at the friction limit, 1 with no friction force.
    pub margin: f64,
    /// Schedule time, s.
    pub time_s: f64,
    /// The finger.
    pub finger: String,
}

/// Steps that the native solver handed over to Clarabel.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Fallbacks {
    /// How many steps.
    pub steps: usize,
    /// The first step's reason.
    pub first_reason: Option<String>,
}

/// Steps whose margin search found a second coulomb equilibrium at a failing end
/// ([`crate::StepMargin::other_equilibrium`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct OtherEquilibria {
    /// Whether the margins' failing ends were probed: `None` when no coulomb margins were
    /// searched (no `--margins`, or the energy law, whose program is convex).
    pub probed: Option<bool>,
    /// How many steps.
    pub steps: usize,
    /// The first: step index, schedule time (s) and what was found.
    pub first: Option<(usize, f64, crate::step_margin::OtherEquilibrium)>,
}

impl OtherEquilibria {
    /// True when nothing is to be said: no step found one, and no coulomb margins went
    /// unprobed.
    pub fn is_empty(&self) -> bool {
        self.steps == 0 && self.probed != Some(false)
    }
}

/// What the disturbance margins cost over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct MarginCost {
    /// Solves spent on the margins.
    pub solves: u64,
    /// Wall time spent on them, s.
    pub wall_time_s: f64,
}

/// The step with the smallest disturbance margin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeastSafeStep {
    /// Step index.
    pub step: usize,
    /// Schedule time, s.
    pub time_s: f64,
    /// The margin, N (see [`crate::StepMargin`]); `None` when unbounded (every direction held
    /// to the search's cap) or undetermined.
    pub margin_n: Option<f64>,
    /// The largest push known to hold along `direction`, N (the cap when unbounded).
    pub held_to_n: f64,
    /// Why the margin is not known above `held_to_n`, when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub undetermined: Option<String>,
    /// Its direction: force part and couple part (unit vector of the scaled wrench space).
    pub direction: grasp_model::WrenchDirection,
    /// The finger that fails first.
    pub failing_finger: Option<String>,
    /// False when the margin reached the search's cap (the grasp held up to it).
    pub bounded: bool,
}

impl LeastSafeStep {
    /// The margin for ordering, N: infinite when unbounded, `held_to_n` when undetermined.
    pub fn margin_or_bound_n(&self) -> f64 {
        grasp_model::margin_for_ordering_n(
            self.margin_n,
            self.held_to_n,
            self.undetermined.is_some(),
        )
    }
}

/// Totals of the sequential (fixed-point) solves of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SequentialTotals {
    /// Convex solves over all steps.
    pub convex_solves: u64,
    /// Most convex solves in one step.
    pub most_in_a_step: u32,
    /// Steps that started from the previous step's forces.
    pub warm_started_steps: usize,
    /// Warm starts that proved infeasible and restarted cold.
    pub cold_restarts: u32,
}

impl TransferSummary {
    /// Summarises the recorded steps (the same as feeding them to a [`SummaryAccumulator`]).
    pub fn from_records(records: &[StepRecord], names: &[String]) -> TransferSummary {
        let mut acc = SummaryAccumulator::new(names);
        for r in records {
            acc.add(r);
        }
        acc.finish()
    }
}

/// Most failed steps listed in a summary (all are counted in `failed_step_count`).
pub const MAX_LISTED_FAILED_STEPS: usize = 100;

/// Most fingers for which the hand-off times are folded step by step (`2^n` candidate sets);
/// beyond, the accumulator keeps each successful step's normal forces (`n + 1` numbers a step).
pub const MAX_FOLDED_FINGERS: usize = 12;

/// Folds step records into a [`TransferSummary`] one at a time, in memory independent of the
/// number of steps (for up to [`MAX_FOLDED_FINGERS`] fingers).
///
/// Which fingers release and receive depends on the LAST successful step, which is known only
/// at the end; so the half and full transfer times are kept for every candidate set of fingers
/// loaded at the last step (a bit mask), and the one that turns out true is reported.
pub struct SummaryAccumulator {
    names: Vec<String>,
    steps: usize,
    failed_steps: Vec<FailedStep>,
    failed_step_count: usize,
    /// Loaded fingers at the first successful step.
    first_loaded: Option<Vec<bool>>,
    /// Loaded fingers at the latest successful step.
    last_loaded: Option<Vec<bool>>,
    /// Per candidate mask of fingers loaded at the end: its hand-off times.
    candidates: Vec<TransferTimes>,
    /// Beyond [`MAX_FOLDED_FINGERS`]: (time, forces, loaded) of every successful step.
    history: Vec<(f64, Vec<f64>, Vec<bool>)>,
    peak: (f64, f64),
    margin: Option<SlipMargin>,
    margin_not_counted: Option<SlipMargin>,
    worst: f64,
    total_wall_time_s: f64,
    total_iterations: u64,
    total_factorizations: u64,
    total_inner_iterations: u64,
    compliance: Option<grasp_model::CompliancePath>,
    answered: (usize, usize),
    fallbacks: Fallbacks,
    warm_steps: usize,
    sequential: Option<SequentialTotals>,
    least_safe: Option<LeastSafeStep>,
    margin_cost: MarginCost,
    other_equilibria: OtherEquilibria,
    /// Per finger: its command and the largest force under it (N, time s) while unchanged.
    held_peak: Vec<Option<(Command, f64, f64)>>,
    held_relaxation: Vec<Option<HeldRelaxation>>,
    threshold_n: Option<f64>,
    crossing: Option<MarginCrossing>,
    warnings: WarningTally,
}

impl SummaryAccumulator {
    /// An empty summary of a scene with these finger names (scene order).
    pub fn new(names: &[String]) -> Self {
        Self::with_folded_fingers(names, MAX_FOLDED_FINGERS)
    }

    /// [`SummaryAccumulator::new`] folding the hand-off times for at most `max` fingers (the
    /// same summary either way; for checking both ways).
    pub fn with_folded_fingers(names: &[String], max: usize) -> Self {
        let folded = names.len() <= max;
        SummaryAccumulator {
            names: names.to_vec(),
            steps: 0,
            failed_steps: Vec::new(),
            failed_step_count: 0,
            first_loaded: None,
            last_loaded: None,
            candidates: if folded {
                vec![TransferTimes::default(); 1 << names.len()]
            } else {
                Vec::new()
            },
            history: Vec::new(),
            peak: (0.0, 0.0),
            margin: None,
            margin_not_counted: None,
            worst: 0.0,
            total_wall_time_s: 0.0,
            total_iterations: 0,
            total_factorizations: 0,
            total_inner_iterations: 0,
            compliance: None,
            answered: (0, 0),
            fallbacks: Fallbacks::default(),
            warm_steps: 0,
            sequential: None,
            least_safe: None,
            margin_cost: MarginCost::default(),
            other_equilibria: OtherEquilibria::default(),
            held_peak: vec![None; names.len()],
            held_relaxation: vec![None; names.len()],
            threshold_n: None,
            crossing: None,
            warnings: WarningTally::new(),
        }
    }

    /// Also reports the first step whose smallest disturbance margin falls below
    /// `threshold_n` (N).
    pub fn with_margin_threshold(mut self, threshold_n: Option<f64>) -> Self {
        self.threshold_n = threshold_n;
        self
    }

    /// Says whether coulomb margins are probed for second equilibria (`None`: no coulomb
    /// margins are searched).
    pub fn with_equilibrium_probe(mut self, probed: Option<bool>) -> Self {
        self.other_equilibria.probed = probed;
        self
    }

    /// A held or position-controlled finger's force under an unchanged command: its peak, and
    /// the largest fall from it.
    fn add_held(&mut self, r: &StepRecord) {
        for (i, c) in r.commands.iter().enumerate() {
            if !matches!(c.command, Command::Held | Command::Approach(_)) {
                self.held_peak[i] = None;
                continue;
            }
            let p = pressing_force_n(r.normal_force_n(&c.name));
            let peak = match self.held_peak[i] {
                Some((cmd, f, t)) if cmd == c.command && f > p => (cmd, f, t),
                _ => (c.command, p, r.time_s),
            };
            self.held_peak[i] = Some(peak);
            let fraction = if peak.1 > 0.0 { 1.0 - p / peak.1 } else { 0.0 };
            if fraction > 1e-9
                && self.held_relaxation[i]
                    .as_ref()
                    .is_none_or(|h| fraction > h.fraction)
            {
                self.held_relaxation[i] = Some(HeldRelaxation {
                    finger: c.name.clone(),
                    from_n: peak.1,
                    from_time_s: peak.2,
                    to_n: p,
                    to_time_s: r.time_s,
                    fraction,
                    position_controlled: matches!(c.command, Command::Approach(_)),
                });
            }
        }
    }

    /// Adds the next step.
    pub fn add(&mut self, r: &StepRecord) {
        self.steps += 1;
        let at = SolveAt {
            index: r.index,
            time_s: Some(r.time_s),
        };
        self.warnings.add(at, &r.solution.warnings);
        self.add_margin(r);
        self.total_wall_time_s += r.wall_time_s;
        self.total_iterations += r.solution.solver.iterations as u64;
        self.add_solver(r);
        if let Some(s) = r.solution.sequential {
            let t = self.sequential.get_or_insert(SequentialTotals {
                convex_solves: 0,
                most_in_a_step: 0,
                warm_started_steps: 0,
                cold_restarts: 0,
            });
            t.convex_solves += s.iterations as u64;
            t.most_in_a_step = t.most_in_a_step.max(s.iterations);
            t.warm_started_steps += usize::from(s.warm_started);
            t.cold_restarts += s.cold_restarts;
        }
        if !r.solution.status.has_forces() {
            self.failed_step_count += 1;
            if self.failed_steps.len() < MAX_LISTED_FAILED_STEPS {
                let why = r.solution.reason.clone().unwrap_or_default();
                self.failed_steps.push(FailedStep {
                    step: r.index,
                    time_s: r.time_s,
                    reason: why,
                });
            }
            return;
        }
        self.add_solved(r);
    }

    /// The step's disturbance margin, if computed.
    fn add_margin(&mut self, r: &StepRecord) {
        let Some(m) = &r.margin else { return };
        self.margin_cost.solves += m.solves as u64;
        self.margin_cost.wall_time_s += m.time_s;
        if let Some(o) = &m.other_equilibrium {
            self.other_equilibria.steps += 1;
            let first = &mut self.other_equilibria.first;
            first.get_or_insert_with(|| (r.index, r.time_s, o.clone()));
        }
        if let Some(threshold_n) = self.threshold_n {
            if self.crossing.is_none() && m.known_to_hold_n() < threshold_n {
                self.crossing = Some(MarginCrossing {
                    threshold_n,
                    step: r.index,
                    time_s: r.time_s,
                    margin_n: m.smallest_n,
                    held_to_n: m.held_to_n,
                });
            }
        }
        if self
            .least_safe
            .as_ref()
            .is_none_or(|l| m.margin_or_bound_n() < l.margin_or_bound_n())
        {
            self.least_safe = Some(LeastSafeStep {
                step: r.index,
                time_s: r.time_s,
                margin_n: m.smallest_n,
                held_to_n: m.held_to_n,
                undetermined: m.undetermined.clone(),
                direction: m.direction,
                failing_finger: m.failing_finger.clone(),
                bounded: m.bounded,
            });
        }
    }

    /// Who answered the step, at what cost, and from where it started.
    fn add_solver(&mut self, r: &StepRecord) {
        let st = &r.solution.solver;
        self.total_factorizations += st.factorizations as u64;
        self.total_inner_iterations += st.inner_iterations as u64;
        self.compliance = Some(match self.compliance {
            Some(c) if c != st.compliance => CompliancePath::Mixed,
            _ => st.compliance,
        });
        match st.solver {
            grasp_model::SolverKind::Native => self.answered.0 += 1,
            grasp_model::SolverKind::Clarabel => self.answered.1 += 1,
        }
        if let Some(why) = &st.fallback {
            self.fallbacks.steps += 1;
            self.fallbacks
                .first_reason
                .get_or_insert_with(|| why.clone());
        }
        self.warm_steps += usize::from(r.reused_program);
    }

    fn add_solved(&mut self, r: &StepRecord) {
        self.add_held(r);
        let forces: Vec<f64> = self.names.iter().map(|n| r.normal_force_n(n)).collect();
        let loaded: Vec<bool> = forces
            .iter()
            .map(|f| *f > LOADED_FRACTION * r.solution.load_scale_n)
            .collect();
        let first = self.first_loaded.get_or_insert_with(|| loaded.clone());
        if self.candidates.is_empty() {
            self.history.push((r.time_s, forces, loaded.clone()));
        } else {
            let first = first.clone();
            let (mut rel, mut rec) = (Vec::new(), Vec::new());
            for (mask, c) in self.candidates.iter_mut().enumerate() {
                split_mask(&first, mask, &mut rel, &mut rec);
                update(c, r.time_s, &forces, &loaded, &rel, &rec);
            }
        }
        self.last_loaded = Some(loaded);
        let total: f64 = r.solution.fingers.iter().map(|f| f.normal_force_n).sum();
        if total > self.peak.0 {
            self.peak = (total, r.time_s);
        }
        let least = step_slip_margins(&r.solution);
        lower(&mut self.margin, least.counted, r.time_s);
        lower(&mut self.margin_not_counted, least.not_counted, r.time_s);
        if let Some(res) = &r.solution.residuals {
            self.worst = self.worst.max(res.equilibrium_relative);
        }
    }

    /// The summary of the steps added.
    pub fn finish(self) -> TransferSummary {
        let (mut releasing, mut receiving, mut half, mut full) = (vec![], vec![], None, None);
        if let (Some(first), Some(last)) = (&self.first_loaded, &self.last_loaded) {
            let (rel, rec) = split(first, last);
            releasing = rel.iter().map(|&i| self.names[i].clone()).collect();
            receiving = rec.iter().map(|&i| self.names[i].clone()).collect();
            let mask = last
                .iter()
                .enumerate()
                .fold(0usize, |m, (i, &l)| m | (usize::from(l) << i));
            let mut c = self.candidates.get(mask).copied().unwrap_or_default();
            for (t, forces, loaded) in &self.history {
                update(&mut c, *t, forces, loaded, &rel, &rec);
            }
            (half, full) = (c.half_s, c.full_s);
        }
        TransferSummary {
            steps: self.steps,
            failed_steps: self.failed_steps,
            failed_step_count: self.failed_step_count,
            releasing,
            receiving,
            half_transfer_time_s: half,
            full_transfer_time_s: full,
            peak_squeeze_n: self.peak.0,
            peak_squeeze_time_s: self.peak.1,
            smallest_slip_margin: self.margin,
            smallest_slip_margin_not_counted: self.margin_not_counted,
            slip_margin_rule: SLIP_MARGIN_RULE,
            worst_equilibrium_residual: self.worst,
            total_wall_time_s: self.total_wall_time_s,
            total_iterations: self.total_iterations,
            total_factorizations: self.total_factorizations,
            total_inner_iterations: self.total_inner_iterations,
            compliance: self.compliance.unwrap_or_default(),
            answered_by_native: self.answered.0,
            answered_by_clarabel: self.answered.1,
            fallbacks: self.fallbacks.clone(),
            warm_steps: self.warm_steps,
            sequential: self.sequential,
            least_safe_step: self.least_safe,
            margin_cost: self.margin_cost,
            other_equilibria: self.other_equilibria,
            held_relaxation: self.held_relaxation.into_iter().flatten().collect(),
            margin_below_threshold: self.crossing,
            warnings: self.warnings.warnings(),
            warnings_not_listed: self.warnings.dropped(),
        }
    }
}

/// Keeps in `slot` the smaller of it and a step's margin `step` at `time_s`.
fn lower(slot: &mut Option<SlipMargin>, step: Option<FingerSlipMargin<'_>>, time_s: f64) {
    let Some(step) = step else { return };
    if slot.as_ref().is_none_or(|x| step.margin < x.margin) {
        *slot = Some(SlipMargin {
            margin: step.margin,
            time_s,
            finger: step.finger.to_string(),
        });
    }
}

/// Releasing (loaded first, unloaded last) and receiving (loaded last: the fingers that hold
/// the object at the end, whether they touched it from the start, as a position-held gripper
/// waiting for the load does, or not) finger indices, scene order.
fn split(first: &[bool], last: &[bool]) -> (Vec<usize>, Vec<usize>) {
    let rel = (0..first.len()).filter(|&i| first[i] && !last[i]).collect();
    let rec = (0..first.len()).filter(|&i| last[i]).collect();
    (rel, rec)
}

/// [`split`] with the last step's loaded fingers given as a bit mask, into reused buffers.
fn split_mask(first: &[bool], mask: usize, rel: &mut Vec<usize>, rec: &mut Vec<usize>) {
    rel.clear();
    rec.clear();
    for (i, &f) in first.iter().enumerate() {
        match (f, mask >> i & 1 == 1) {
            (true, false) => rel.push(i),
            (_, true) => rec.push(i),
            _ => {}
        }
    }
}

/// The hand-off times of one candidate set of receiving fingers (`None`: not reached yet).
#[derive(Debug, Clone, Copy, Default)]
struct TransferTimes {
    /// The first time the receiving fingers carry at least as much as the releasing ones
    /// (half), s.
    half_s: Option<f64>,
    /// The first time no releasing finger is loaded (full), s.
    full_s: Option<f64>,
}

/// Records the first time the receiving fingers carry at least as much as the releasing ones
/// (half) and the first time no releasing finger is loaded (full).
fn update(
    c: &mut TransferTimes,
    t: f64,
    forces: &[f64],
    loaded: &[bool],
    rel: &[usize],
    rec: &[usize],
) {
    if c.half_s.is_none() && !rec.is_empty() && !rel.is_empty() {
        let sum_rec = rec.iter().map(|&i| forces[i]).sum::<f64>();
        let sum_rel = rel.iter().map(|&i| forces[i]).sum::<f64>();
        if sum_rec > 0.0 && sum_rec >= sum_rel {
            c.half_s = Some(t);
        }
    }
    if c.full_s.is_none() && !rel.is_empty() && rel.iter().all(|&i| !loaded[i]) {
        c.full_s = Some(t);
    }
}

/// A finger's normal force as a fall is measured from and to, N: a contact only presses, so a
/// solved force below zero is the solve's rounding (a finger barely touching) and counts as 0,
/// and no fall exceeds 100 %.
fn pressing_force_n(normal_force_n: f64) -> f64 {
    if normal_force_n > 0.0 {
        normal_force_n
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A finger barely touching whose force rounds to just below zero fell to 0 N, 100 %,
    /// never to a negative force by more than 100 % ("fell 113.33 %, 0.00000 N -> -0.00000 N").
    #[test]
    fn a_force_rounded_below_zero_falls_to_zero_not_beyond_100_percent() {
        assert_eq!(pressing_force_n(-1.6e-7), 0.0);
        assert_eq!(pressing_force_n(-0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(pressing_force_n(2.5), 2.5);
        let (peak, now) = (1.2e-6, pressing_force_n(-1.6e-7));
        assert_eq!(1.0 - now / peak, 1.0);
    }
}
