//! Why a constraint binds: what the planner knows of the constraint a checked schedule does
//! not keep, from the check's run and the search's last linearisation, with the fix where
//! there is one (options named as [`crate::plan::option_names`] spells them).

use grasp_model::LOADED_FRACTION;

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::plan::option_names;
use crate::plan::plan_options::PlanOptions;
use crate::plan::plan_report::{Binding, CheckedAt, FINE_STEPS, MARGIN_TOLERANCE};
use crate::slip_margin::{slip_margin, CARRYING_FRACTION};
use crate::stepper::StepRecord;

/// What the reasons are read from.
pub struct Evidence<'a> {
    /// The search's last accepted rows (its linearisation).
    pub rows: &'a [MarginRow],
    /// Its path.
    pub path: &'a KeyframePath,
    /// The run in which the constraint binds.
    pub records: &'a [StepRecord],
    /// Why the search stopped.
    pub stopped: &'a str,
    /// The question.
    pub options: &'a PlanOptions,
}

/// Why the search stopped short of a binding constraint: the first step's loads fixed, fingers
/// the plan leaves alone at their friction limit ([`held_at_limit`]), a margin whose
/// derivative with respect to every keyframe load is 0 (a finger sliding at the friction
/// limit: no nearby change of the loads lifts it off), a planned finger too light for any
/// ramp to lift its margin ([`light_finger`]), a margin that grows only with a shorter hand-off when the rates or
/// [`PlanOptions::min_duration_s`] allow none ([`duration_bound`]), a linearised program with
/// no better step within the bounds and rates, or the runs ran out.
pub fn explain(b: &Binding, e: &Evidence<'_>) -> String {
    let disturbance = b.constraint == "disturbance margin";
    let row = e.rows.iter().find(|r| {
        let same_row = match r.kind {
            RowKind::Disturbance => disturbance,
            RowKind::Slip => !disturbance && Some(&r.finger) == b.finger.as_ref(),
        };
        same_row && (r.time_s - b.time_s).abs() < 1e-9
    });
    if b.time_s == 0.0 && !by_approach(e.path) {
        return "at the first step every planned load is fixed (the releasing fingers' loads \
                in the template or the scene, the receiving ones' 0 N), so no schedule changes \
                it"
        .into();
    }
    if b.time_s == 0.0 {
        return "at the first step every planned command is fixed (the releasing fingers' loads \
                or approaches in the template or the scene, the receiving ones' 0 N or their \
                starting approaches), so no schedule changes it"
            .into();
    }
    if b.constraint == "load rate" || b.constraint == "approach speed" {
        return format!(
            "the search stopped before its ramps kept the rate: {}",
            e.stopped
        );
    }
    if let Some(why) = held_at_limit(b, e.records, e.options) {
        return why;
    }
    let flat = row.is_some_and(|r| r.gradient.iter().all(|g| *g == 0.0) && r.per_duration == 0.0);
    if flat && disturbance {
        return "its difference quotient in every keyframe load is 0 there: raising the \
                planned loads does not move the grasp's weakest direction"
            .into();
    }
    if flat {
        return "its derivative with respect to every keyframe load is 0 there: the finger \
                slides at the friction limit, and no nearby change of the loads lifts it off"
            .into();
    }
    if let Some(why) = light_finger(b, e) {
        return why;
    }
    if let Some(why) = row.and_then(|r| duration_bound(r, e.path, e.options)) {
        return why;
    }
    if e.stopped.contains("converged") {
        return "the linearised program finds no step that raises it within the bounds, rates \
                and duration"
            .into();
    }
    format!("the search stopped before it was met: {}", e.stopped)
}

/// Why a constraint the schedule keeps at its own steps breaks in the check's finer run
/// (`e.records`): between them, where the search, run at the schedule's steps, does not look;
/// the fix: a reason no resolution lifts ([`held_at_limit`], [`light_finger`]), else planning
/// at the finer steps.
pub fn between_steps(b: &Binding, checked: &CheckedAt, e: &Evidence<'_>) -> String {
    let base = format!(
        "it breaks between the schedule's own steps ({} steps, {} s apart), where the search, \
         run at those steps, does not look (the check runs the same ramps at {} steps, {} s \
         apart)",
        checked.schedule_steps,
        three_digits(checked.schedule_step_s),
        checked.fine_steps.unwrap_or_default(),
        three_digits(checked.fine_step_s.unwrap_or_default()),
    );
    if let Some(why) = held_at_limit(b, e.records, e.options).or_else(|| light_finger(b, e)) {
        return format!("{base}; {why}");
    }
    let margins = if e.options.min_margin_n.is_some() {
        ", each step's disturbance margin then searched too"
    } else {
        ""
    };
    format!(
        "{base}; fix: plan at that resolution (`{}` {FINE_STEPS}{margins})",
        option_names::STEPS
    )
}

/// The step of `records` at `time_s`.
fn step_at(records: &[StepRecord], time_s: f64) -> Option<&StepRecord> {
    records
        .iter()
        .find(|r| (r.time_s - time_s).abs() <= 1e-9 * time_s.abs().max(1.0))
}

/// The reason of a slip margin (or a step without equilibrium) where fingers the plan leaves
/// alone are at their friction limit (loaded, slip margin within [`MARGIN_TOLERANCE`] of 0):
/// the object slides in them whatever the planned loads do; the fix, when they hold the object
/// at the run's end: plan them as receiving fingers. `None` when none is.
fn held_at_limit(b: &Binding, records: &[StepRecord], options: &PlanOptions) -> Option<String> {
    if b.constraint == "disturbance margin" {
        return None;
    }
    let step = step_at(records, b.time_s)?;
    let sol = &step.solution;
    let planned = |n: &String| options.releasing.contains(n) || options.receiving.contains(n);
    let loaded = |f: &grasp_model::FingerSolution| {
        f.friction_coefficient > 0.0 && f.normal_force_n > LOADED_FRACTION * sol.load_scale_n
    };
    let at_limit: Vec<&str> = sol
        .fingers
        .iter()
        .filter(|f| !planned(&f.name) && loaded(f) && slip_margin(f) <= MARGIN_TOLERANCE)
        .map(|f| f.name.as_str())
        .collect();
    if at_limit.is_empty() {
        return None;
    }
    let names = at_limit.join(", ");
    let (them, are) = match at_limit.len() {
        1 => ("it", "is"),
        _ => ("them", "are"),
    };
    let holds_at_end = records.last().is_some_and(|last| {
        let s = &last.solution;
        at_limit.iter().all(|n| {
            s.finger(n)
                .is_some_and(|f| f.normal_force_n > LOADED_FRACTION * s.load_scale_n)
        })
    });
    let fix = if holds_at_end {
        format!(
            "; fix: plan their loads too (`{}` {names}), so the plan can press {them} harder",
            option_names::RECEIVING
        )
    } else {
        String::new()
    };
    Some(format!(
        "{names}, which the plan leaves alone (as the template or the scene commands {them}), \
         {are} at the friction limit there (|Q| = mu P): the object slides in {them}, and no \
         planned load lifts {them} off{fix}"
    ))
}

/// The reason of a slip margin of a planned finger that carries less than twice the 5 % of
/// the load scale below which the rule stops counting it: a finger letting go, or taking over
/// from 0 N, is near sliding while its load is small (its friction limit `mu P` shrinks with
/// its load faster than the friction the grip leaves it), and the margin it has as it passes
/// the rule's 5 % moves little with the planned loads (on the bundled hand-offs: with the
/// duration, through relaxing pads, more than with the ramps' shape); the fix: a lower
/// threshold. `None` otherwise, and at the friction limit (no
/// threshold is kept there).
fn light_finger(b: &Binding, e: &Evidence<'_>) -> Option<String> {
    let finger = b.finger.as_ref()?;
    let doing = if e.options.releasing.contains(finger) {
        "letting go"
    } else if e.options.receiving.contains(finger) {
        "taking over"
    } else {
        return None;
    };
    // At the friction limit no threshold is kept: the other reasons say why it slides.
    if b.constraint != "slip margin" || b.value <= MARGIN_TOLERANCE {
        return None;
    }
    let sol = &step_at(e.records, b.time_s)?.solution;
    let f = sol.finger(finger)?;
    let q = f.tangential_force_n;
    let force = (f.normal_force_n.powi(2) + q.iter().map(|c| c * c).sum::<f64>()).sqrt();
    let share = force / sol.load_scale_n;
    (share < 2.0 * CARRYING_FRACTION).then(|| {
        format!(
            "{finger} is {doing} and carries only {} % of the load scale there, just above the \
             {} % below which the slip margin stops counting a finger: a finger this light is \
             near sliding (its friction limit shrinks with its load), and the planned loads \
             move little the margin it has as it passes 5 %; fix: a threshold it keeps (`{}` \
             below {})",
            three_digits(100.0 * share),
            100.0 * CARRYING_FRACTION,
            option_names::MIN_SLIP_MARGIN,
            three_digits(b.value)
        )
    })
}

/// The reason of a margin that only a shorter hand-off raises (`dm/dT < 0`: viscoelastic pads
/// relax while it lasts) at a duration already the shortest the load rates allow at these
/// keyframe loads, or [`PlanOptions::min_duration_s`] (to 1e-4 of it, the program's bounds
/// being met to its own tolerance); `None` otherwise.
fn duration_bound(row: &MarginRow, path: &KeyframePath, options: &PlanOptions) -> Option<String> {
    if row.per_duration >= 0.0 {
        return None;
    }
    let by_rate_s = path.shortest_duration_s(&options.rate_limits());
    let (shortest_s, what) = if options.min_duration_s >= by_rate_s {
        let what = format!("`{}` allows", option_names::MIN_DURATION);
        (options.min_duration_s, what)
    } else {
        let what = match by_approach(path) {
            false => "at these keyframe loads the load rates allow",
            true => "at these keyframe commands the rates and speeds allow",
        }
        .to_string();
        (by_rate_s, what)
    };
    (path.duration_s <= shortest_s * (1.0 + 1e-4)).then(|| {
        format!(
            "it grows only as the hand-off gets shorter ({} per s there: the pads relax while \
             it lasts), and {what} none shorter than {} s",
            three_digits(row.per_duration),
            three_digits(shortest_s)
        )
    })
}

/// True when some planned group is driven by approaches (its reasons speak of commands, not
/// loads).
fn by_approach(path: &KeyframePath) -> bool {
    path.groups.iter().any(|g| g.is_approach())
}

/// `x` to three significant digits, as [`grasp_model::Readable`] writes it (`-0.0421`, `3`).
pub fn three_digits(x: f64) -> grasp_model::Readable {
    grasp_model::Readable(format!("{x:.2e}").parse().unwrap_or(x))
}
