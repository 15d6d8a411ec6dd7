//! `grasp plan`: the load ramps of a hand-off planned to keep every step's slip margin, its
//! schedule file written only once checked, a summary beside the template's.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use grasp_transfer::{
    Objective, PlanOptions, PlanReport, Schedule, ScheduleSpec, Template, DISTURBANCE_TOLERANCE,
    MARGIN_TOLERANCE,
};

use crate::mcap_profile_flags::McapProfileFlags;
use crate::output::{self, ForceArg};
use crate::pictures::picture;
use crate::pictures::plan_margins::{approach_curves, load_curves, PlanMargins};
use crate::solve_flags::SolveFlags;

/// Plan a hand-off: the releasing and receiving fingers' load ramps that keep every step's
/// slip margin, within load and rate limits, in the shortest duration.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (JSON); the releasing fingers start from their loads in it.
    pub scene: PathBuf,
    /// Fingers that let go (force-controlled), comma-separated.
    #[arg(long, value_delimiter = ',', required = true, value_name = "A,B")]
    pub releasing: Vec<String>,
    /// Fingers that take over (force-controlled, starting from 0 N), comma-separated.
    #[arg(long, value_delimiter = ',', value_name = "C,D")]
    pub receiving: Vec<String>,
    /// Write the planned schedule here (JSON; `grasp transfer --schedule` runs it).
    #[arg(long, value_name = "PLAN.schedule.json")]
    pub out: PathBuf,
    /// Start from this schedule (and compare with it); its other fingers' phases are kept.
    #[arg(long, value_name = "SCHEDULE.json")]
    pub template: Option<PathBuf>,
    /// Smallest slip margin 1 - |Q|/(mu P) at every step, over the fingers carrying at least
    /// 5 % of the load scale.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "X",
        allow_negative_numbers = true
    )]
    pub min_slip_margin: f64,
    /// Smallest disturbance margin at every step, N: the smallest, over the axis directions of
    /// force and couple, of the extra wrench the grasp resists (as `grasp transfer --margins`
    /// finds it; several times the planning's cost) [default: not constrained].
    #[arg(long, value_name = "NEWTONS", allow_negative_numbers = true)]
    pub min_margin: Option<f64>,
    /// Smallest load of a planned finger between its ends, N.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "N",
        allow_negative_numbers = true
    )]
    pub min_load: f64,
    /// Largest load of a planned finger, N [default: no limit].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub max_load: Option<f64>,
    /// Largest load rate of a planned force-controlled finger, N/s (the shortest duration
    /// needs it or --max-speed).
    #[arg(long, value_name = "N_PER_S", allow_negative_numbers = true)]
    pub max_rate: Option<f64>,
    /// Largest approach speed of a planned position-controlled finger (a jaw opening or
    /// closing), m/s.
    #[arg(long, value_name = "M_PER_S", allow_negative_numbers = true)]
    pub max_speed: Option<f64>,
    /// Where the releasing position-controlled fingers end, m of approach (negative: opened
    /// short of first touch) [default: where the template ends them].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub open_to: Option<f64>,
    /// Where the receiving position-controlled fingers close to in the starting path, m of
    /// approach (the plan moves it within the bounds) [default: where the template ends them].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub close_to: Option<f64>,
    /// Smallest approach of a planned position-controlled finger, m [default: the smallest
    /// the starting path commands].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub min_approach: Option<f64>,
    /// Largest approach of a planned position-controlled finger, m [default: the largest the
    /// starting path commands].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub max_approach: Option<f64>,
    /// Shortest duration allowed, s.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "S",
        allow_negative_numbers = true
    )]
    pub min_duration: f64,
    /// Longest duration allowed, s [default: no limit].
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub max_duration: Option<f64>,
    /// Duration, s: fixed with `--objective margin`, the first guess otherwise [default: the
    /// template's].
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// What to optimise: the shortest duration, or the largest smallest slip margin.
    #[arg(long, value_enum, default_value = "duration")]
    pub objective: ObjectiveArg,
    /// Steps after the first [default: the template's, or 60].
    #[arg(
        long,
        value_name = "K",
        allow_negative_numbers = true,
        value_parser = whole_number
    )]
    pub steps: Option<usize>,
    /// Keyframes per finger, the ends included (2 to 20).
    #[arg(
        long,
        default_value_t = 5,
        value_name = "K",
        allow_negative_numbers = true,
        value_parser = whole_number
    )]
    pub keyframes: usize,
    /// Most hand-off runs the planner may make, the final check included.
    #[arg(
        long,
        default_value_t = 30,
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = whole_number
    )]
    pub max_runs: usize,
    /// Write the report (margins along the plan and the template, keyframes, cost) as JSON;
    /// written also when no schedule keeps every constraint (exit code 2), to say why.
    #[arg(long, value_name = "F.json")]
    pub report: Option<PathBuf>,
    /// Plot the smallest slip margin along the plan beside the template's (.svg or .png); with
    /// --min-margin, the smallest disturbance margin too; below, the planned loads.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Replay the planned hand-off and write its MCAP log (as `grasp transfer --mcap`).
    #[arg(long, value_name = "F.mcap")]
    pub mcap: Option<PathBuf>,
    #[command(flatten)]
    pub mcap_profile: McapProfileFlags,
    /// Replay the planned hand-off and write its Rerun recording (as `grasp transfer --rrd`).
    #[arg(long, value_name = "F.rrd")]
    pub rrd: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// A count option's value (`--steps`, `--keyframes`, `--max-runs`): a whole number, else a
/// message saying so (clap names the flag before it); the planner checks its range.
fn whole_number(s: &str) -> Result<usize, String> {
    s.trim().parse::<usize>().map_err(|_| {
        format!(
            "{s} is not a whole number of 0 or more: give one, such as 60 (the planner then \
             checks its range)"
        )
    })
}

/// `--objective`.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum ObjectiveArg {
    /// The shortest duration.
    Duration,
    /// The largest smallest slip margin.
    Margin,
}

/// `grasp plan`.
/// The finger names of `scene` can name the replay's ROS 2 topics (when it writes them):
/// refused before the planning rather than after it.
fn check_replay_names(
    args: &Args,
    profile: grasp_transfer::McapProfile,
    scene: &grasp_model::LoadedScene,
) -> Result<()> {
    if args.mcap.is_none() || profile == grasp_transfer::McapProfile::Json {
        return Ok(());
    }
    let names = scene.finger_names();
    match names
        .iter()
        .find_map(|n| grasp_transfer::ros_name_problem(n))
    {
        Some(problem) => anyhow::bail!("--mcap-profile ros2: {problem}"),
        None => Ok(()),
    }
}

pub fn execute(args: Args) -> Result<ExitCode> {
    // A bad profile is refused before the planning, not after it.
    let profile = args.mcap_profile.profile()?;
    let targets: Vec<&Path> = [Some(&args.out), args.report.as_ref(), args.plot.as_ref()]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .collect();
    let mut inputs = vec![args.scene.as_path()];
    inputs.extend(args.template.as_deref());
    let outs = output::claim(&targets, &inputs, args.force.force)?;
    let plot_format = args
        .plot
        .as_deref()
        .map(|p| picture::Format::of(p, "--plot"))
        .transpose()?;
    let scene = crate::load_scene::load_scene(&args.scene)?;
    args.solve.check_memory(&scene, &args.scene)?;
    check_replay_names(&args, profile, &scene)?;
    let template = args
        .template
        .as_deref()
        .map(|p| read_template(p, &scene.finger_names()))
        .transpose()?;
    let options = options(&args);
    let mut report = grasp_transfer::plan(
        &scene,
        template
            .as_ref()
            .map(|(spec, schedule)| Template { spec, schedule }),
        &options,
    )?;
    report.respell_options(crate::flag_names::in_flags);
    print!(
        "{}",
        crate::flag_names::in_flags(&summary(&report, &options))
    );
    if let Some(path) = &args.report {
        outs.write(path, &serde_json::to_vec_pretty(&report)?)?;
        println!("wrote report: {}", path.display());
    }
    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        let title = args.scene.display().to_string();
        let threshold = options.min_slip_margin;
        let by_approach: Vec<String> = report.approaches_m.iter().map(|a| a.0.clone()).collect();
        let planned: Vec<String> = options
            .releasing
            .iter()
            .chain(&options.receiving)
            .filter(|n| !by_approach.contains(n))
            .cloned()
            .collect();
        let names = scene.finger_names();
        let schedule = Schedule::from_spec(&report.schedule, &names, Path::new("."))
            .context("the planned schedule cannot be evaluated for its plot")?;
        let plot = PlanMargins {
            report: &report,
            threshold,
            min_margin_n: options.min_margin_n,
            title: &title,
            loads: load_curves(&schedule, &scene, &planned),
            template_loads: template
                .as_ref()
                .map_or_else(Vec::new, |(_, t)| load_curves(t, &scene, &planned)),
            approaches: approach_curves(&schedule, &scene, &by_approach),
            template_approaches: template
                .as_ref()
                .map_or_else(Vec::new, |(_, t)| approach_curves(t, &scene, &by_approach)),
        };
        outs.write(path, &picture::render(&plot, format)?)?;
        println!("wrote plot: {}", path.display());
    }
    if !report.met {
        // The schedule is not written; the report and the plot asked for are: they say why.
        println!("no schedule written: the best one found does not keep every constraint");
        return Ok(ExitCode::from(2));
    }
    let mut text = serde_json::to_string_pretty(&report.schedule)?;
    text.push('\n');
    outs.write(&args.out, text.as_bytes())?;
    println!(
        "wrote schedule: {}\n  run it: {} transfer {} --schedule {}",
        args.out.display(),
        program_as_run(std::env::var_os("CARGO").is_some()),
        args.scene.display(),
        args.out.display()
    );
    if args.mcap.is_none() && args.rrd.is_none() {
        return Ok(ExitCode::SUCCESS);
    }
    println!("replaying the planned hand-off:");
    replay(&args)
}

/// The planned hand-off run by `grasp transfer` with the recordings asked for.
fn replay(args: &Args) -> Result<ExitCode> {
    let outputs = crate::commands::transfer::Outputs {
        mcap: args.mcap.clone(),
        mcap_profile: args.mcap_profile.profile()?,
        rrd: args.rrd.clone(),
        csv: None,
        npz: None,
        plot: None,
        force: args.force.force,
        live: None,
    };
    let flags = crate::commands::transfer::Flags {
        keep_going: false,
        cold: false,
        min_squeeze: false,
        margins: args.min_margin.is_some(),
        margin_threshold: args.min_margin,
        probe_equilibria: false,
        solve: args.solve,
    };
    crate::commands::transfer::run(&args.scene, &args.out, &outputs, flags)
}

fn options(args: &Args) -> PlanOptions {
    PlanOptions {
        releasing: args.releasing.clone(),
        receiving: args.receiving.clone(),
        min_slip_margin: args.min_slip_margin,
        min_margin_n: args.min_margin,
        min_load_n: args.min_load,
        max_load_n: args.max_load.unwrap_or(f64::INFINITY),
        max_rate_n_per_s: args.max_rate,
        max_speed_m_per_s: args.max_speed,
        open_to_m: args.open_to,
        close_to_m: args.close_to,
        min_approach_m: args.min_approach,
        max_approach_m: args.max_approach,
        min_duration_s: args.min_duration,
        max_duration_s: args.max_duration.unwrap_or(f64::INFINITY),
        objective: match args.objective {
            ObjectiveArg::Duration => Objective::Duration,
            ObjectiveArg::Margin => Objective::Margin,
        },
        duration_s: args.duration,
        steps: args.steps,
        keyframes: args.keyframes,
        max_runs: args.max_runs,
        solve: args.solve.options(),
        ..PlanOptions::default()
    }
}

/// The template as written and resolved against the scene's fingers.
fn read_template(path: &Path, names: &[String]) -> Result<(ScheduleSpec, Schedule)> {
    let text = crate::limits::read_input(path, "template schedule")?;
    let base = path.parent().map(PathBuf::from).unwrap_or_default();
    let bad = || format!("{} is not a usable schedule", path.display());
    let spec: ScheduleSpec = grasp_model::strict_json::from_str_strict(&text)
        .map_err(|e| anyhow::anyhow!("{}: {}", e.path, e.message))
        .with_context(bad)?;
    let schedule = Schedule::from_spec(&spec, names, &base).with_context(bad)?;
    Ok((spec, schedule))
}

/// `x` to four significant digits, round-off of 0 (below 1e-9) as 0, a million or more in
/// exponent form (`1.000e300`, not 301 digits).
fn g4(x: f64) -> String {
    if x.abs() < 1e-9 {
        return "0".into();
    }
    if x.abs() >= 1e6 {
        return format!("{x:.3e}");
    }
    let digits = (3 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{x:.digits$}")
}

/// The closing summary.
fn summary(r: &PlanReport, o: &PlanOptions) -> String {
    let mut s = String::new();
    let receiving = match o.receiving.as_slice() {
        [] => String::new(),
        names => format!(", {} take over", names.join(", ")),
    };
    let (keys, steps) = (r.keyframes_s.len(), r.margins.len());
    let who = o.releasing.join(", ");
    let _ = writeln!(
        s,
        "planned: {who} let go{receiving}; {keys} keyframes, {steps} steps"
    );
    let _ = write!(s, "duration: {} s", g4(r.duration_s));
    if let Some(t) = r.template_duration_s {
        let change = 100.0 * (t - r.duration_s) / t;
        let word = if change >= 0.0 { "shorter" } else { "longer" };
        let _ = write!(s, " (template {} s: {} % {word})", g4(t), g4(change.abs()));
    }
    let at = |m: Option<&grasp_transfer::MarginsAtStep>| match m {
        Some(m) => format!(
            "{} ({} at t = {} s)",
            g4(m.smallest.unwrap_or(f64::NAN)),
            m.finger.as_deref().unwrap_or("-"),
            g4(m.time_s)
        ),
        None => "no finger carries 5 % of the load scale".into(),
    };
    let _ = write!(s, "\nsmallest slip margin: {}", at(r.smallest()));
    if r.template_margins.is_some() {
        let _ = write!(s, "; template: {}", at(r.template_smallest()));
    }
    let _ = writeln!(s);
    let counted = r.smallest().and_then(|m| m.smallest);
    s.push_str(&crate::report::slip_rule_line(
        counted,
        r.smallest_not_counted.as_ref(),
    ));
    if o.min_margin_n.is_some() {
        let _ = write!(
            s,
            "smallest disturbance margin: {}",
            disturbance_at(&r.margins)
        );
        if let Some(t) = &r.template_margins {
            let _ = write!(s, "; template: {}", disturbance_at(t));
        }
        let _ = writeln!(s);
    }
    s.push_str(&constraints_line(r, o));
    s.push_str(&checked_line(&r.checked));
    let _ = writeln!(
        s,
        "planning: {}, {}, {} s; it stopped because {}",
        crate::report::count(r.runs as u64, "run", "runs"),
        crate::report::count(r.iterations as u64, "iteration", "iterations"),
        g4(r.time_s),
        r.stopped.trim_start_matches("it ")
    );
    for n in &r.notes {
        let _ = writeln!(s, "note: {n}");
    }
    let label = |k: usize| k.to_string();
    let steps = crate::report::Solves {
        total: r.margins.len(),
        singular: "step",
        plural: "steps",
        label: &label,
    };
    s.push_str(&crate::report::tallied_warning_lines(&r.warnings, &steps));
    s
}

/// The resolutions the schedule was checked at: its own steps (as `grasp transfer` runs it),
/// and the finer run of its ramps when it has fewer than `FINE_STEPS`.
fn checked_line(c: &grasp_transfer::CheckedAt) -> String {
    let mut s = format!(
        "checked: at the schedule's {} steps ({} s apart), as grasp transfer runs it",
        c.schedule_steps,
        g4(c.schedule_step_s)
    );
    if let (Some(n), Some(step)) = (c.fine_steps, c.fine_step_s) {
        let _ = write!(
            s,
            ", and its ramps at {n} steps ({} s apart) for the slip margin and equilibrium",
            g4(step)
        );
        if let Some(m) = &c.fine_smallest {
            let _ = write!(
                s,
                " (smallest slip margin there {}, {} at t = {} s)",
                g4(m.margin),
                m.finger,
                g4(m.time_s)
            );
        }
    }
    s.push('\n');
    s
}

/// The smallest disturbance margin along a run, with its time: "2.5 N at t = 1.2 s".
fn disturbance_at(margins: &[grasp_transfer::MarginsAtStep]) -> String {
    let least = margins
        .iter()
        .filter_map(|m| Some((m.disturbance_n?, m.time_s)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    match least {
        Some((n, t)) => format!("{} N at t = {} s", g4(n), g4(t)),
        None => "none (no step solved)".into(),
    }
}

/// "constraints: kept ..." or the binding one, with why.
fn constraints_line(r: &PlanReport, o: &PlanOptions) -> String {
    let Some(b) = &r.binding else {
        let mut rate = o
            .max_rate_n_per_s
            .map_or(String::new(), |q| format!(", load rates <= {} N/s", g4(q)));
        if let Some(v) = o.max_speed_m_per_s.filter(|_| !r.approaches_m.is_empty()) {
            rate.push_str(&format!(", approach speeds <= {} m/s", g4(v)));
        }
        let disturbance = o.min_margin_n.map_or(String::new(), |n| {
            let within = 100.0 * DISTURBANCE_TOLERANCE;
            format!(", disturbance margin >= {} N to within {within} %", g4(n))
        });
        return format!(
            "constraints: kept at every step (slip margin >= {} to within {}{disturbance}{rate})\n",
            g4(o.min_slip_margin),
            MARGIN_TOLERANCE
        );
    };
    let disturbance = b.constraint == "disturbance margin";
    let who = b
        .finger
        .as_deref()
        .map_or(String::new(), |f| match disturbance {
            true => format!(" (first to fail: {f})"),
            false => format!(" of {f}"),
        });
    let unit = match b.constraint.as_str() {
        "disturbance margin" | "release" => " N",
        "load rate" => " N/s",
        "approach speed" => " m/s",
        _ => "",
    };
    format!(
        "binding constraint: {}{who} at t = {} s is {}{unit} against {}{unit} (short by {}{unit}): {}\n",
        b.constraint,
        g4(b.time_s),
        g4(b.value),
        g4(b.limit),
        g4(b.short_by),
        b.why
    )
}

/// The command a user types to run this program again, for a command line to copy: `cargo run
/// --release --` when `cargo` started it (`cargo run` sets `CARGO` for the program it runs),
/// `grasp` otherwise.
fn program_as_run(started_by_cargo: bool) -> &'static str {
    match started_by_cargo {
        true => "cargo run --release --",
        false => "grasp",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hint to run the planned schedule names the program as the user ran it: `cargo run
    /// --release --` under cargo, not a `grasp` that may not be on the path.
    #[test]
    fn the_run_it_hint_names_cargo_run_when_cargo_ran_the_plan() {
        assert_eq!(program_as_run(true), "cargo run --release --");
        assert_eq!(program_as_run(false), "grasp");
    }
}
