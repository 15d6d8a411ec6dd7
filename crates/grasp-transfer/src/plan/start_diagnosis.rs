//! Why the planner's starting schedule has a step without equilibrium, and the fix: a jaw
//! planned without the jaw that presses against it, no finger left to hold the object, a
//! template that never loads the receiving fingers, receiving loads held down by the load
//! bound; else the solver's reason with the general fix.

use grasp_model::{GraspModel, Readable as N};

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::option_names;
use crate::plan::plan_error::{rounded, PlanError};
use crate::plan::plan_options::PlanOptions;
use crate::schedule::Command;
use crate::stepper::StepRecord;

/// Two contact normals at least this anti-parallel (cosine below its negative) are the two
/// jaws of a pinch.
const OPPOSED_COSINE: f64 = 0.9;

/// The refusal of a starting path whose step `record` found no equilibrium (`template`: the
/// path was sampled from one).
pub fn no_equilibrium(
    record: &StepRecord,
    path: &KeyframePath,
    model: &GraspModel,
    options: &PlanOptions,
    template: bool,
) -> PlanError {
    let fix = opposed_jaw(record, model, options)
        .or_else(|| nothing_holds(record, path, options, template))
        .or_else(|| receiving_at_bound(record, options))
        .unwrap_or_else(|| {
            format!(
                "start from a template that holds (`{}`), or raise the loads",
                option_names::TEMPLATE
            )
        });
    PlanError::StartHasNoEquilibrium {
        time_s: record.time_s,
        loads: planned_loads(record, options),
        reason: record
            .solution
            .reason
            .clone()
            .unwrap_or_else(|| "no equilibrium".into()),
        fix,
    }
}

/// The planned fingers' commands at the step: `f1 4 N, f2 released`.
fn planned_loads(record: &StepRecord, options: &PlanOptions) -> String {
    let planned = |n: &String| options.releasing.contains(n) || options.receiving.contains(n);
    let words: Vec<String> = record
        .commands
        .iter()
        .filter(|c| planned(&c.name))
        .map(|c| match c.command {
            Command::Load(p) => format!("{} {} N", c.name, rounded(p)),
            Command::Released => format!("{} released", c.name),
            Command::Held => format!("{} held", c.name),
            Command::Approach(a) => format!("{} pressed in {} m", c.name, rounded(a)),
        })
        .collect();
    words.join(", ")
}

/// A planned finger facing an unplanned, commanded one across the object (a pinch's other
/// jaw): the planned load changes, its opposite's does not, and nothing balances the
/// difference. The fix names both in the planned finger's list.
fn opposed_jaw(record: &StepRecord, model: &GraspModel, options: &PlanOptions) -> Option<String> {
    let normal = |name: &str| model.finger(name).map(|(_, f)| f.frame().normal);
    let lists = [
        (option_names::RELEASING, &options.releasing),
        (option_names::RECEIVING, &options.receiving),
    ];
    for (option, list) in lists {
        for planned in list.iter() {
            let Some(n) = normal(planned) else { continue };
            let Some(other) = record.commands.iter().find(|c| {
                let unplanned =
                    !options.releasing.contains(&c.name) && !options.receiving.contains(&c.name);
                let commanded = !matches!(c.command, Command::Released);
                unplanned
                    && commanded
                    && normal(&c.name).is_some_and(|m| n.dot(&m) < -OPPOSED_COSINE)
            }) else {
                continue;
            };
            let mut both = list.clone();
            both.push(other.name.clone());
            return Some(format!(
                "{planned} and {} press on the object from opposite sides (a pinch's jaws), but \
                 only {planned} is planned: its load changes while {}'s does not; plan them \
                 together (`{option}` {})",
                other.name,
                other.name,
                both.join(", ")
            ));
        }
    }
    None
}

/// No finger left to hold the object at the step: the releasing fingers let go and no
/// receiving finger is named, or the template never loads the receiving ones.
fn nothing_holds(
    record: &StepRecord,
    path: &KeyframePath,
    options: &PlanOptions,
    template: bool,
) -> Option<String> {
    let releasing_gone = options.releasing.iter().all(|n| {
        record
            .commands
            .iter()
            .any(|c| &c.name == n && matches!(c.command, Command::Released))
    });
    if options.receiving.is_empty() {
        return releasing_gone.then(|| {
            format!(
                "once the releasing fingers let go nothing the plan loads holds the object: \
                 name the fingers that take over (`{}`)",
                option_names::RECEIVING
            )
        });
    }
    let receiving_unloaded = path
        .values
        .get(1)
        .zip(path.groups.get(1))
        .is_some_and(|(l, g)| !g.is_approach() && l.iter().all(|x| *x == 0.0));
    (template && receiving_unloaded).then(|| {
        format!(
            "the template (`{}`) never loads the receiving fingers ({}: their loads sampled \
             from it are 0 N at every keyframe), so nothing takes over: give them a ramp up in \
             it, or plan without a template (the receiving fingers then ramp up to the \
             releasing fingers' mean load)",
            option_names::TEMPLATE,
            options.receiving.join(", ")
        )
    })
}

/// The receiving fingers held at the load bound at the step, too little to hold the object.
fn receiving_at_bound(record: &StepRecord, options: &PlanOptions) -> Option<String> {
    let max = options.max_load_n;
    let at_bound = options.receiving.iter().any(|n| {
        record.commands.iter().any(|c| {
            &c.name == n && matches!(c.command, Command::Load(p) if p >= max * (1.0 - 1e-9))
        })
    });
    at_bound.then(|| {
        format!(
            "the receiving fingers are at `{}` ({} N) there: raise it",
            option_names::MAX_LOAD,
            N(max)
        )
    })
}
