//! `grasp margin`: disturbance margins of one grasp ([`grasp_model::disturbance_margins`]) as a table, JSON,
//! a picture ([`crate::pictures::margin_plot`]) and a Rerun recording of the wrench surface.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_model::{
    axis_directions, disturbance_margins_reporting, plane_directions, spread_directions,
    DirectionMargin, Failure, MarginOptions, MarginReport, SolveAt, WarningTally, WrenchDirection,
};
use grasp_model::{ContactState, GraspModel, StepInputs};
use grasp_model::{LoadedScene, ModelKind};
use grasp_transfer::{RerunSink, RunInfo, Sink};
use serde::Deserialize;

use crate::limits;
use crate::load_scene::load_scene;
use crate::output::{self, ForceArg};
use crate::pictures::margin_plot::{label, MarginPlot};
use crate::pictures::picture;
use crate::solve_flags::SolveFlags;

/// Disturbance margins: per direction of an extra wrench on the object, the largest
/// magnitude the grasp takes before it fails (no equilibrium, or coulomb: a finger slides as
/// a whole), with the finger that fails first.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// Directions: a number N (the axis directions, then combined ones spread over the
    /// sphere), `planes:K` (K force directions around each coordinate plane, for the polar
    /// plot, and the couple axes) or a JSON file with a list of `{"force": [N], "torque":
    /// [N m]}`. Default: the axis directions.
    #[arg(long, value_name = "N|planes:K|FILE")]
    pub directions: Option<String>,
    /// Contact law to judge the grasp with (default: the scene's).
    #[arg(long, value_parser = ["energy", "coulomb"])]
    pub model: Option<String>,
    /// Characteristic length L, m, in [1e-9, 1e3] (the scene's lengths): a magnitude s means
    /// a force s N and a couple s L N m. Default: the grasp's reach from the centroid of the
    /// contacts.
    #[arg(long, value_name = "M")]
    pub length: Option<f64>,
    /// Relative width of the final bracket of each margin, in [1e-9, 0.5] (the solves balance
    /// the load to about 1e-10 of it).
    #[arg(long, default_value_t = 1e-3, value_name = "REL")]
    pub tolerance: f64,
    /// Write the report as JSON.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// Write a picture of the margins (.svg or .png): polar plots of the force directions
    /// in each coordinate plane and a bar per direction.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Write a Rerun recording of the grasp with its wrench surface.
    #[arg(long, value_name = "F.rrd")]
    pub rrd: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// `grasp margin`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let flags = Flags {
        directions: args.directions,
        model: args.model,
        length_m: args.length,
        tolerance: args.tolerance,
        solve: args.solve,
    };
    let outputs = Outputs {
        json: args.json,
        plot: args.plot,
        rrd: args.rrd,
        force: args.force.force,
    };
    run(&args.scene, flags, &outputs)
}

/// What to compute.
pub struct Flags {
    /// `N` or a JSON file of directions.
    pub directions: Option<String>,
    /// Contact law override.
    pub model: Option<String>,
    /// Characteristic length, m.
    pub length_m: Option<f64>,
    /// Relative bracket width.
    pub tolerance: f64,
    /// Solver, form of the patch compliances, memory limit.
    pub solve: SolveFlags,
}

/// Where to write.
pub struct Outputs {
    pub json: Option<PathBuf>,
    pub plot: Option<PathBuf>,
    pub rrd: Option<PathBuf>,
    pub force: bool,
}

/// Most directions of one run, given as a count or listed in a file (each is a search of its
/// own: about 30 solves).
const MAX_DIRECTIONS: usize = 10_000;

/// One direction as written in a directions file: a force (N) and a couple (N m), either
/// may be omitted.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionSpec {
    #[serde(default)]
    force: [f64; 3],
    #[serde(default)]
    torque: [f64; 3],
}

/// The directions the user asked for.
fn directions(
    model: &GraspModel,
    arg: Option<&str>,
    length_m: f64,
) -> Result<Vec<WrenchDirection>> {
    let Some(arg) = arg else {
        return Ok(axis_directions(model));
    };
    if let Some(k) = arg.strip_prefix("planes:") {
        return match k.parse::<usize>() {
            Ok(k) if (4..=360).contains(&k) => Ok(plane_directions(model, k)),
            _ => bail!("--directions planes:{k}: give between 4 and 360 directions per plane, e.g. planes:24"),
        };
    }
    if let Ok(n) = arg.parse::<usize>() {
        if !(1..=MAX_DIRECTIONS).contains(&n) {
            bail!(
                "--directions {n}: give between 1 and {MAX_DIRECTIONS} directions, or a JSON file"
            );
        }
        return Ok(spread_directions(model, n));
    }
    let path = Path::new(arg);
    let text = limits::read_input(path, "directions file").with_context(|| {
        format!("--directions {arg}: not a count N, planes:K or a readable JSON file of directions")
    })?;
    let specs: Vec<DirectionSpec> = serde_json::from_str(&text).with_context(|| {
        format!(
            "--directions {arg} is not a list of directions; write [{{\"force\": [0, 0, -1]}}, \
             {{\"torque\": [1, 0, 0]}}] (force in N, couple in N m)"
        )
    })?;
    if specs.is_empty() {
        bail!("--directions {arg} lists no direction; give at least one");
    }
    if specs.len() > MAX_DIRECTIONS {
        bail!(
            "--directions {arg} lists {} directions; give at most {MAX_DIRECTIONS} (each is a \
             search of its own)",
            specs.len()
        );
    }
    specs
        .iter()
        .enumerate()
        .map(|(i, d)| {
            WrenchDirection::of_wrench(d.force, d.torque, length_m).with_context(|| {
                format!("{arg}: directions[{i}] has no finite nonzero force or torque; give one")
            })
        })
        .collect()
}

/// Runs the command.
fn run(scene_path: &Path, flags: Flags, outputs: &Outputs) -> Result<ExitCode> {
    let options = MarginOptions {
        length_m: flags.length_m,
        relative_tolerance: flags.tolerance,
        ..MarginOptions::default()
    };
    options.validate()?;
    let solve = flags.solve.options();
    let plot_format = outputs
        .plot
        .as_deref()
        .map(|p| picture::Format::of(p, "--plot"))
        .transpose()?;
    let outs = output::claim(&outputs.targets(), &[scene_path], outputs.force)?;
    let (scene, model) = load_model(scene_path, &flags)?;
    let model = std::sync::Arc::new(model);
    let length_m = flags.length_m.unwrap_or(model.scales().length_m);
    let dirs = directions(&model, flags.directions.as_deref(), length_m)?;
    let options = MarginOptions {
        length_m: Some(length_m),
        ..options
    };
    let inputs = StepInputs::of_scene(&model);
    let state = ContactState::new(&model);
    let bar = crate::progress::bar(dirs.len(), "directions");
    let done = |k: usize| bar.set_position(k as u64);
    let mut report =
        disturbance_margins_reporting(&model, &inputs, &state, solve, &dirs, &options, &done)?;
    bar.finish_and_clear();
    respell_warnings(&mut report);
    print!(
        "{}",
        crate::flag_names::in_flags(&table(scene_path, &report))
    );
    if let Some(out) = &outputs.json {
        let text = serde_json::to_string_pretty(&report)?;
        outs.write(out, text.as_bytes())?;
        println!("wrote {}", out.display());
    }
    if let (Some(out), Some(format)) = (&outputs.plot, plot_format) {
        let plot = MarginPlot {
            model: &model,
            report: &report,
        };
        outs.write(out, &picture::render(&plot, format)?)?;
        println!("wrote {}", out.display());
    }
    if let Some(out) = &outputs.rrd {
        let run = RunInfo {
            scene: &scene,
            model: &model,
            margins: false,
        };
        write_wrench_surface(out, &outs, scene_path, &run, &report)?;
        println!("wrote {}", out.display());
    }
    Ok(match holds_undisturbed(&report) {
        true => ExitCode::SUCCESS,
        false => ExitCode::from(2),
    })
}

impl Outputs {
    /// The files to write.
    fn targets(&self) -> Vec<&Path> {
        [&self.json, &self.plot, &self.rrd]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .collect()
    }
}

/// The scene (its contact law overridden by `--model`), within the memory limit, and its
/// model.
fn load_model(scene_path: &Path, flags: &Flags) -> Result<(LoadedScene, GraspModel)> {
    let mut scene = load_scene(scene_path)?;
    match flags.model.as_deref() {
        Some("coulomb") => scene.model = ModelKind::Coulomb,
        Some("energy") => scene.model = ModelKind::Energy,
        _ => {}
    }
    flags.solve.check_memory(&scene, scene_path)?;
    let model = GraspModel::from_loaded_with(&scene, flags.solve.compliance)
        .with_context(|| format!("{} is not a usable scene", scene_path.display()))?;
    Ok((scene, model))
}

/// The Rerun recording of the grasp with its wrench surface (no steps), named for the scene's
/// file stem, written to `out`.
fn write_wrench_surface(
    out: &Path,
    outs: &output::Outputs,
    scene_path: &Path,
    run: &RunInfo,
    report: &MarginReport,
) -> Result<()> {
    let pending = outs.create(out)?;
    let mut sink = RerunSink::create_as(&pending.write_path(), out)?;
    sink.without_steps();
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy());
    sink.set_recording_name(&format!("{} margins", stem.as_deref().unwrap_or("scene")));
    sink.begin(run)?;
    sink.log_wrench_surface(run, report)?;
    sink.finish()?;
    outs.commit(vec![pending])?;
    Ok(())
}

/// Whether the grasp holds undisturbed (some direction was searched); when it does not, says
/// why (the command then exits 2). A direction the grasp does not resist at all (margin 0) is
/// a result like any other.
fn holds_undisturbed(report: &MarginReport) -> bool {
    let holds = report.directions.iter().any(|d| d.solves > 0);
    if !holds {
        let why = report.directions[0].failure.as_ref().map(failure_words_of);
        println!(
            "the grasp does not hold without disturbance: {}",
            why.unwrap_or_default()
        );
    }
    holds
}

/// A failure with its reason.
fn failure_words_of(f: &Failure) -> String {
    match f {
        Failure::Slides { finger } => format!("{finger} slides as a whole"),
        Failure::NoEquilibrium { reason } | Failure::NoConvergence { reason } => reason.clone(),
    }
}

fn failure_words(m: &DirectionMargin) -> String {
    match &m.failure {
        None => "holds up to the cap".into(),
        Some(Failure::Slides { finger }) => format!("{finger} slides"),
        Some(Failure::NoEquilibrium { .. }) => "no equilibrium".into(),
        // Neither solver converged above `held_to_n`: a solver's failure, not the grasp's
        // limit; the margin is only known to be at least that (the table's note says so).
        Some(Failure::NoConvergence { .. }) => "undetermined (solves stall)".into(),
    }
}

/// The note under a table with a direction whose trials stopped converging.
const STALL_NOTE: &str = "undetermined (solves stall): neither solver converged past the \
    magnitude shown, which held; the margin is at least that, not known to be it";

/// The report as a table.
fn table(scene: &Path, r: &MarginReport) -> String {
    let mut s = String::new();
    table_header(scene, r, &mut s);
    for (i, m) in r.directions.iter().enumerate() {
        let torque = m.torque_nm.iter().map(|v| v * v).sum::<f64>().sqrt();
        let margin = crate::pictures::margin_plot::margin_cell(m);
        let _ = writeln!(
            s,
            "{:<4}{:<44}{:>14}{:>14}{:>12}  {:<22}{:>8}",
            i,
            label(&m.direction),
            margin,
            crate::report::significant(torque, 5),
            m.failing_finger.as_deref().unwrap_or("-"),
            failure_words(m),
            m.solves
        );
    }
    table_notes(r, &mut s);
    warning_lines(r, &mut s);
    let w = &r.directions[r.smallest];
    let _ = writeln!(
        s,
        "smallest margin: {} N along #{} {} ({}, first to fail: {})",
        crate::pictures::margin_plot::margin_cell(w),
        r.smallest,
        label(&w.direction),
        failure_words(w),
        w.failing_finger.as_deref().unwrap_or("-")
    );
    let _ = writeln!(
        s,
        "cost: {} in {:.1} ms (directions in parallel; each a warm-started step from the last \
         magnitude that held)",
        crate::report::count(r.solves as u64, "solve", "solves"),
        r.time_s * 1e3
    );
    s
}

/// The table's first line (the scene, the criterion of failure, what a magnitude means) and
/// its column heads.
fn table_header(scene: &Path, r: &MarginReport, s: &mut String) {
    let crit = match r.model {
        ModelKind::Energy => "energy: an equilibrium within the friction cones",
        ModelKind::Coulomb => {
            "coulomb: equilibrium and every loaded finger keeps a sticking element"
        }
    };
    let _ = writeln!(
        s,
        "{}: disturbance margins ({crit}); magnitude s = force s N at the centre of mass plus \
         couple s L N m, L = {:.4} m",
        scene.display(),
        r.length_m
    );
    let _ = writeln!(
        s,
        "{:<4}{:<44}{:>14}{:>14}{:>12}  {:<22}{:>8}",
        "#", "direction", "margin [N]", "torque [N m]", "first", "failure", "solves"
    );
}

/// The warnings of the undisturbed solve, then those of the solves at the margins (each once,
/// with the directions it applies to; one the undisturbed solve gave already is not repeated).
fn warning_lines(r: &MarginReport, s: &mut String) {
    for w in &r.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    let mut tally = WarningTally::new();
    for (index, m) in r.directions.iter().enumerate() {
        let new: Vec<String> = m
            .warnings
            .iter()
            .filter(|w| !r.warnings.contains(w))
            .cloned()
            .collect();
        tally.add(
            SolveAt {
                index,
                time_s: None,
            },
            &new,
        );
    }
    let label = |k: usize| format!("#{k}");
    let directions = crate::report::Solves {
        total: r.directions.len(),
        singular: "direction's margin",
        plural: "directions' margins",
        label: &label,
    };
    s.push_str(&crate::report::tallied_warning_lines(
        &tally.warnings(),
        &directions,
    ));
}

/// The report's warnings with flags for option names (its JSON's; the table is respelled
/// whole).
fn respell_warnings(r: &mut MarginReport) {
    let texts = r
        .warnings
        .iter_mut()
        .chain(r.directions.iter_mut().flat_map(|d| d.warnings.iter_mut()));
    for w in texts {
        *w = crate::flag_names::in_flags(w);
    }
}

/// The notes under the rows: searches stopped early, the stall note, fingers already sliding,
/// directions not resisted at all.
fn table_notes(r: &MarginReport, s: &mut String) {
    for (i, m) in r.directions.iter().enumerate() {
        if let Some(note) = &m.stopped_early {
            let _ = writeln!(s, "#{i} stopped early: {note}");
        }
        if let Some(found) = &m.other_equilibrium {
            let _ = writeln!(s, "#{i} another equilibrium: {found}");
        }
    }
    let stalled = |m: &DirectionMargin| matches!(m.failure, Some(Failure::NoConvergence { .. }));
    if r.directions.iter().any(stalled) {
        let _ = writeln!(s, "{STALL_NOTE}");
    }
    if !r.mounted.is_empty() {
        let _ = writeln!(
            s,
            "margins of the compliant grasp: {} on mounts (a push moves their cores on their \
             springs)",
            r.mounted.join(", ")
        );
    }
    if !r.shared_springs.is_empty() {
        let _ = writeln!(
            s,
            "margins of the compliant grasp: its fingers on {} (a push moves the hands' bases \
             and the servos' jaws on their springs)",
            r.shared_springs.join(", ")
        );
    }
    if !r.sliding_undisturbed.is_empty() {
        let _ = writeln!(
            s,
            "already sliding without disturbance (not judged by sliding): {}",
            r.sliding_undisturbed.join(", ")
        );
    }
    if !r.unresisted.is_empty() && r.unresisted.len() < r.directions.len() {
        let _ = writeln!(
            s,
            "not resisted at all (margin 0; the commanded loads cannot react): {}",
            r.unresisted
                .iter()
                .map(|&i| format!("#{i}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report of two directions: the first undetermined where its solves stall (or failing
    /// by sliding), the second failing by sliding.
    fn report(stall: bool) -> MarginReport {
        let direction = |first: bool, force: [f64; 3]| {
            let mut d = serde_json::json!({"direction": {"force": force, "torque": [0.0, 0.0, 0.0]},
                "margin_n": 1.5, "held_to_n": 1.5, "fails_at_n": 1.51, "force_n": force,
                "torque_nm": [0.0, 0.0, 0.0], "bounded": true, "failing_finger": "a",
                "failure": {"kind": "slides", "finger": if first { "a" } else { "b" }},
                "solves": 12, "time_s": 0.01});
            if first && stall {
                d["margin_n"] = serde_json::Value::Null;
                d["fails_at_n"] = serde_json::Value::Null;
                d["bounded"] = false.into();
                d["failing_finger"] = serde_json::Value::Null;
                d["failure"] = serde_json::json!({"kind": "no_convergence", "reason": "stalled"});
                d["undetermined"] = "no answer at 1.51 N: stalled".into();
            }
            d
        };
        serde_json::from_value(serde_json::json!({"model": "energy", "length_m": 0.02,
            "load_scale_n": 10.0, "sliding_undisturbed": [],
            "directions": [direction(true, [1.0, 0.0, 0.0]), direction(false, [0.0, 1.0, 0.0])],
            "smallest": 0, "unresisted": [], "solves": 24, "time_s": 0.02}))
        .expect("a report")
    }

    /// A stall is the solvers', not the grasp's: shown as undetermined above what held
    /// (`>=`), never as a margin or a limit, and explained once under the table.
    #[test]
    fn a_stall_is_shown_undetermined_never_as_a_margin_and_explained_once() {
        let with = table(Path::new("s.json"), &report(true));
        assert!(with.contains("undetermined (solves stall)"), "{with}");
        assert!(with.contains(">=1.5"), "{with}");
        assert!(!with.contains("limit (solves stall)"), "{with}");
        assert!(!with.contains("no convergence"), "{with}");
        assert_eq!(
            with.matches("neither solver converged past").count(),
            1,
            "{with}"
        );
        let without = table(Path::new("s.json"), &report(false));
        assert!(!without.contains("solves stall"), "{without}");
    }
}
