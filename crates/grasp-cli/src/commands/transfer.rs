//! `grasp transfer`: validated inputs, sinks writing temporary files, a progress bar, and the
//! closing summary. Outputs are moved into place only when the run completes (see `output`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use grasp_model::LoadedScene;
use grasp_transfer::{
    McapProfile, OutputFiles, OutputPaths, RerunSink, Schedule, Sink, SqueezeOutcome, StepRecord,
    TransferOptions, TransferSummary,
};

use crate::mcap_profile_flags::McapProfileFlags;
use crate::output::{self, ForceArg, Outputs as Claimed};
use crate::pictures::force_history::ForceHistory;
use crate::pictures::picture;
use crate::report::count;
use crate::solve_flags::SolveFlags;

/// Replay a hand-off: step a load schedule, log every step to MCAP / Rerun / CSV.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// Schedule file (JSON; see `grasp schema --schedule`).
    #[arg(long, value_name = "SCHEDULE.json")]
    pub schedule: PathBuf,
    /// Write an MCAP log (per-finger resultants and per-element fields, JSON with schemas;
    /// patches above 64x64 elements as compact base64 maps on /grasp/patch_maps; the tactile
    /// sensors' readings, each step, on /grasp/tactile).
    #[arg(long, value_name = "F.mcap")]
    pub mcap: Option<PathBuf>,
    #[command(flatten)]
    pub mcap_profile: McapProfileFlags,
    /// Write a Rerun recording (.rrd) to replay in the Rerun viewer.
    #[arg(long, value_name = "F.rrd")]
    pub rrd: Option<PathBuf>,
    /// Stream every step, as it is computed, to a running Rerun viewer or server (`rerun`,
    /// or headless `rerun --save F.rrd`); default address rerun+http://127.0.0.1:9876/proxy.
    #[arg(long, value_name = "URL", num_args = 0..=1, default_missing_value = "rerun+http://127.0.0.1:9876/proxy")]
    pub rerun_connect: Option<String>,
    /// Start a Rerun viewer (`rerun` on the PATH) and stream every step to it.
    #[arg(long, conflicts_with = "rerun_connect")]
    pub rerun_spawn: bool,
    /// Write the force histories as CSV.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Write every step's element fields (forces, pressures, gaps, slips, states, centres) as
    /// NumPy arrays to this `.npz` file: `step_<k>/<finger>/<field>` (`step_00012/f3/pressure_pa`),
    /// float64 as solved, with `times_s` (each step's time, s).
    #[arg(long, value_name = "F.npz")]
    pub npz: Option<PathBuf>,
    /// Write a force-history plot (.svg or .png), like thesis figures 15 and 17.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Continue past a step without equilibrium (default: stop there).
    #[arg(long)]
    pub keep_going: bool,
    /// Rebuild the program at every step and start every sequential solve from an
    /// energy-model solve instead of the previous step, and with --margins search every
    /// step's margins from scratch instead of from the previous step's (for comparison).
    #[arg(long)]
    pub cold: bool,
    /// After the run, find the smallest load of the receiving (force-controlled) fingers
    /// at which the releasing fingers can let go without any finger sliding as a whole.
    #[arg(long)]
    pub min_squeeze: bool,
    /// At every solved step, find the smallest disturbance margin over the axis directions
    /// of force and couple (logged to MCAP and Rerun; the summary names the least safe
    /// step).
    #[arg(long)]
    pub margins: bool,
    /// With --margins, also say when the smallest disturbance margin first fell below this
    /// many newtons (a viscoelastic grasp's margin falls as its pads relax).
    #[arg(long, value_name = "NEWTONS", requires = "margins")]
    pub margin_threshold: Option<f64>,
    /// With --margins under the coulomb law, probe every margin's failing end for a second
    /// equilibrium (the search's solver started cold, and the other solver) and report where
    /// one holds: about 4 to 20 times the margins' cost.
    #[arg(long, requires = "margins")]
    pub probe_equilibria: bool,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// `grasp transfer`: the flags as given, turned into outputs and switches.
pub fn execute(args: Args) -> Result<ExitCode> {
    let live = match (args.rerun_connect, args.rerun_spawn) {
        (Some(url), _) => Some(Live::Connect(url)),
        (None, true) => Some(Live::Spawn),
        (None, false) => None,
    };
    let outputs = Outputs {
        mcap: args.mcap,
        mcap_profile: args.mcap_profile.profile()?,
        rrd: args.rrd,
        csv: args.csv,
        npz: args.npz,
        plot: args.plot,
        force: args.force.force,
        live,
    };
    if let Some(n) = args.margin_threshold {
        if !(n.is_finite() && n > 0.0) {
            anyhow::bail!(
                "--margin-threshold {n}: give the margin in newtons below which the summary \
                 reports the first step, > 0"
            );
        }
    }
    let flags = Flags {
        keep_going: args.keep_going,
        cold: args.cold,
        min_squeeze: args.min_squeeze,
        margins: args.margins,
        margin_threshold: args.margin_threshold,
        probe_equilibria: args.probe_equilibria,
        solve: args.solve,
    };
    run(&args.scene, &args.schedule, &outputs, flags)
}

/// Output files of a transfer.
#[derive(Clone)]
pub struct Outputs {
    pub mcap: Option<PathBuf>,
    /// What the MCAP log holds.
    pub mcap_profile: McapProfile,
    pub rrd: Option<PathBuf>,
    pub csv: Option<PathBuf>,
    pub npz: Option<PathBuf>,
    pub plot: Option<PathBuf>,
    pub force: bool,
    /// A live Rerun stream besides the files.
    pub live: Option<Live>,
}

/// How to open each output (`{}` stands for its path, quoted for the shell when needed).
const OPEN_RRD: &str = "rerun {}   (the Rerun viewer: pip install rerun-sdk==0.36.3)";
const OPEN_MCAP: &str = "Foxglove (https://app.foxglove.dev or the desktop app), Open local file; \
                         topics /grasp/fingers, /grasp/patches, /grasp/scene \
                         (and /grasp/patch_maps with patches above 64 x 64 elements, \
                         /grasp/tactile with a finger's sensor, \
                         /grasp/tactile/<finger>/gel with a gel image)";
const OPEN_ROS2_MCAP: &str = "ros2 bag info {} (ROS 2 Iron or later; Humble: ros2 bag info -s mcap {}), \
                              ros2 bag play the same way with rviz2, PlotJuggler or Foxglove; topics \
                              /tf, /tf_static, /grasp/step, /grasp/scene, /grasp/force_arrows, /grasp/<finger>/wrench, \
                              /grasp/<finger>/pressure, /grasp/<finger>/contact_state";
const OPEN_CSV: &str = "one row per step, a column per quantity: any spreadsheet, or Python's \
                        pandas.read_csv";
const OPEN_NPZ: &str = "Python: numpy.load(path)[\"step_00000/<finger>/pressure_pa\"] (its \
                        keys: .files)";
const OPEN_PLOT: &str = "any web browser or image viewer";

/// `word` as one shell word: as it is when it holds only characters the shell leaves alone,
/// else in single quotes.
fn shell_word(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./+,:@%=".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        return word.to_string();
    }
    format!("'{}'", word.replace('\'', "'\\''"))
}

/// Where a live Rerun stream goes.
#[derive(Clone)]
pub enum Live {
    /// A running viewer or server at this gRPC proxy address.
    Connect(String),
    /// A viewer started for the run.
    Spawn,
}

impl Outputs {
    /// "wrote ..." lines of the outputs given, each with how to open it.
    fn wrote(&self) -> String {
        let mut o = String::new();
        for (p, what, open) in [
            (&self.mcap, "MCAP", self.open_mcap()),
            (&self.rrd, "Rerun recording", OPEN_RRD),
            (&self.csv, "CSV", OPEN_CSV),
            (&self.npz, "element fields", OPEN_NPZ),
            (&self.plot, "plot", OPEN_PLOT),
        ] {
            if let Some(p) = p {
                let shown = p.display().to_string();
                let open = open.replace("{}", &shell_word(&shown));
                let _ = writeln!(o, "wrote {what}: {shown}\n  open: {open}");
            }
        }
        match &self.live {
            Some(Live::Connect(url)) => {
                let _ = writeln!(o, "streamed every step to the Rerun viewer at {url}");
            }
            Some(Live::Spawn) => {
                let _ = writeln!(o, "streamed every step to a Rerun viewer");
            }
            None => {}
        }
        o
    }

    /// How to open the MCAP log of this profile.
    fn open_mcap(&self) -> &'static str {
        match self.mcap_profile {
            McapProfile::Json => OPEN_MCAP,
            McapProfile::Ros2 { .. } => OPEN_ROS2_MCAP,
        }
    }

    fn targets(&self) -> Vec<&Path> {
        [&self.mcap, &self.rrd, &self.csv, &self.npz, &self.plot]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .collect()
    }
}

/// Switches of a transfer.
pub struct Flags {
    pub keep_going: bool,
    pub cold: bool,
    pub min_squeeze: bool,
    pub margins: bool,
    pub margin_threshold: Option<f64>,
    pub probe_equilibria: bool,
    pub solve: SolveFlags,
}

/// The sinks of a run: its files and a live stream.
struct OpenSinks {
    files: OutputFiles,
    live: Option<RerunSink>,
}

impl OpenSinks {
    /// The sinks of `out`, the recordings named `name` (the scene's file stem).
    fn create(out: &Outputs, outs: &Claimed, name: &str) -> Result<OpenSinks> {
        let paths = OutputPaths {
            mcap: out.mcap.as_deref(),
            mcap_profile: out.mcap_profile,
            rrd: out.rrd.as_deref(),
            csv: out.csv.as_deref(),
            npz: out.npz.as_deref(),
        };
        let mut files = OutputFiles::open(outs.set(), paths)?;
        files.name_recording(name);
        files.respell_options(crate::flag_names::in_flags);
        let mut live = match &out.live {
            Some(Live::Connect(url)) => Some(RerunSink::connect(url)?),
            Some(Live::Spawn) => Some(RerunSink::spawn()?),
            None => None,
        };
        if let Some(l) = live.as_mut() {
            l.set_recording_name(name);
        }
        Ok(OpenSinks { files, live })
    }

    fn sinks(&mut self) -> Vec<&mut dyn Sink> {
        self.files.sinks(self.live.as_mut())
    }
}

/// Runs a transfer: its inputs and outputs checked before any work, every step stepped and
/// logged to the sinks, the summary printed; the outputs moved into place when the run
/// completes (or reaches its end past failed steps with `--keep-going`).
pub(crate) fn run(
    scene_path: &Path,
    schedule_path: &Path,
    out: &Outputs,
    flags: Flags,
) -> Result<ExitCode> {
    // Validate everything before any work: outputs, scene, memory, schedule.
    let plot_format = out
        .plot
        .as_deref()
        .map(|p| picture::Format::of(p, "--plot"))
        .transpose()?;
    let outs = output::claim(&out.targets(), &[scene_path, schedule_path], out.force)?;
    let (scene, schedule) = load_inputs(scene_path, schedule_path, &flags.solve)?;
    outs.refuse_inputs_read()?;
    let names = scene.finger_names();
    let stem = scene_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned());
    let mut open = OpenSinks::create(out, &outs, stem.as_deref().unwrap_or("scene"))?;
    let bar = crate::progress::bar(schedule.times.len(), "steps");
    let options = transfer_options(&flags);
    let mut history = out.plot.as_ref().map(|_| ForceHistory::new(&names));
    let started = std::time::Instant::now();
    let (summary, last) =
        grasp_transfer::run(&scene, &schedule, options, &mut open.sinks(), |r| {
            bar.set_message(format!("t = {:.3} s", r.time_s));
            bar.inc(1);
            if let Some(h) = history.as_mut() {
                h.push(r);
            }
        })?;
    bar.finish_and_clear();
    let planned = schedule.times.len();
    let run_s = started.elapsed().as_secs_f64();
    let summary_text = summary_text(&summary, summary.steps, planned, run_s);
    print!("{}", crate::flag_names::in_flags(&summary_text));
    if summary.failed_step_count > 0 && !flags.keep_going {
        drop(open); // removes the temporary files
        if !out.targets().is_empty() {
            println!(
                "no output written: the run stopped at a failed step, so its logs are incomplete; \
                 existing files are untouched (even with --force); pass --keep-going to log past \
                 failed steps"
            );
        }
        return Ok(ExitCode::from(2));
    }
    let mut unplotted = None;
    if let (Some(p), Some(h), Some(format)) = (&out.plot, &history, plot_format) {
        let title = scene_path.display().to_string();
        // A picture that cannot be drawn costs the run no other output.
        match picture::render(&h.picture(&title), format) {
            Ok(bytes) => {
                let mut o = outs.create(p)?;
                o.write_all(&bytes)?;
                open.files.add_pending(o);
            }
            Err(e) => unplotted = Some(format!("{e:#}")),
        }
    }
    if flags.min_squeeze {
        print_minimum_squeeze(&scene, last.as_ref(), options.solve)?;
    }
    outs.commit(open.files.take_pending())?;
    print_written(out, unplotted);
    Ok(match summary.failed_step_count {
        0 => ExitCode::SUCCESS,
        _ => ExitCode::from(2),
    })
}

/// The stepping's options from the switches.
fn transfer_options(flags: &Flags) -> TransferOptions {
    TransferOptions {
        keep_going: flags.keep_going,
        warm_start: !flags.cold,
        solve: flags.solve.options(),
        margins: flags.margins,
        margins_from_scratch: flags.cold,
        margin_threshold_n: flags.margin_threshold,
        sensitivities: false,
        margin_options: grasp_model::MarginOptions {
            probe_equilibria: flags.probe_equilibria,
            ..TransferOptions::default().margin_options
        },
    }
}

/// `--min-squeeze`: the smallest load of the receiving fingers at which the releasing ones can
/// let go, searched from the last solved step.
fn print_minimum_squeeze(
    scene: &LoadedScene,
    last: Option<&StepRecord>,
    solve: grasp_model::SolveOptions,
) -> Result<()> {
    match last {
        Some(last) => {
            let outcome = grasp_transfer::minimum_squeeze(scene, last, solve)?;
            print!("{}", squeeze_text(&outcome));
        }
        None => println!("minimum squeeze: no step was solved"),
    }
    Ok(())
}

/// The "wrote ..." lines of the outputs written; the plot left out with a warning when it
/// could not be drawn (`unplotted`: why).
fn print_written(out: &Outputs, unplotted: Option<String>) {
    match unplotted {
        None => print!("{}", out.wrote()),
        Some(why) => {
            let mut written = out.clone();
            written.plot = None;
            print!("{}", written.wrote());
            eprintln!("warning: the plot was not written: {why}");
        }
    }
}

/// The scene (within the memory limit) and the schedule resolved against it.
fn load_inputs(
    scene_path: &Path,
    schedule_path: &Path,
    solve: &SolveFlags,
) -> Result<(LoadedScene, Schedule)> {
    let scene = crate::load_scene::load_scene(scene_path)?;
    solve.check_memory(&scene, scene_path)?;
    let text = crate::limits::read_input(schedule_path, "schedule file")?;
    let names = scene.finger_names();
    let base = schedule_path
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    let schedule = Schedule::from_json_str(&text, &names, &base)
        .with_context(|| format!("{} is not a usable schedule", schedule_path.display()))?;
    crate::limits::note_inputs(&schedule.input_files);
    Ok((scene, schedule))
}

/// A slip margin `1 - |Q|/(mu P)` this close to 0 is a finger at the friction limit: the
/// ratio is computed from two forces each known to about 1e-12 of the load (the solver's
/// residuals), so a few 1e-16 either side of 0 is round-off.
const SLIP_MARGIN_ROUND_OFF: f64 = 1e-9;

/// The closing summary of a run of `done` of `planned` steps that took `run_s` seconds
/// (stepping, margins and writing the outputs).
fn summary_text(s: &TransferSummary, done: usize, planned: usize, run_s: f64) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "steps: {done} of {planned}");
    hand_off_lines(s, &mut o);
    let _ = writeln!(
        o,
        "peak squeeze (sum of normal forces): {:.4} N at t = {:.3} s",
        s.peak_squeeze_n, s.peak_squeeze_time_s
    );
    slip_margin_line(s, &mut o);
    disturbance_margin_lines(s, &mut o);
    held_lines(s, &mut o);
    failed_step_lines(s, &mut o);
    warning_lines(s, done, &mut o);
    solver_lines(s, done, &mut o);
    let _ = writeln!(
        o,
        "residuals: worst equilibrium residual {:.1e} of the load",
        s.worst_equilibrium_residual
    );
    time_line(s, done, run_s, &mut o);
    o
}

/// Who lets go and who takes over, and when the receiving fingers carry half and all the
/// load; a run in which no finger lets go says so.
fn hand_off_lines(s: &TransferSummary, o: &mut String) {
    if s.releasing.is_empty() {
        // A hold, or a run in which no finger lets go: no hand-off to time.
        let _ = writeln!(o, "hand-off: none (no finger lets go during the run)");
        return;
    }
    let _ = writeln!(o, "releasing fingers: {}", list(&s.releasing));
    let _ = writeln!(o, "receiving fingers: {}", list(&s.receiving));
    let t = |x: Option<f64>| x.map_or("never".to_string(), |v| format!("t = {v:.3} s"));
    let _ = writeln!(
        o,
        "receiving fingers carry half the load: {}",
        t(s.half_transfer_time_s)
    );
    let _ = writeln!(
        o,
        "receiving fingers carry all the load:  {}",
        t(s.full_transfer_time_s)
    );
}

/// The smallest slip margin of the run, with its finger and time, under the rule it follows.
fn slip_margin_line(s: &TransferSummary, o: &mut String) {
    match &s.smallest_slip_margin {
        // Within round-off of 0: the finger is at the friction limit (|Q| = mu P).
        Some(m) if m.margin.abs() <= SLIP_MARGIN_ROUND_OFF => {
            let _ = writeln!(
                o,
                "smallest slip margin 1 - |Q|/(mu P): 0 ({} at t = {:.3} s: |Q| = mu P to \
                 round-off, the finger is at the friction limit)",
                m.finger, m.time_s
            );
        }
        Some(m) => {
            let _ = writeln!(
                o,
                "smallest slip margin 1 - |Q|/(mu P): {} ({} at t = {:.3} s)",
                crate::report::significant(m.margin, 3),
                m.finger,
                m.time_s
            );
        }
        None => {
            let _ = writeln!(o, "smallest slip margin: no frictional finger counted");
        }
    }
    let counted = s.smallest_slip_margin.as_ref().map(|m| m.margin);
    let lighter = s.smallest_slip_margin_not_counted.as_ref();
    o.push_str(&crate::report::slip_rule_line(counted, lighter));
}

/// With `--margins`: the least safe step, and when the smallest disturbance margin first fell
/// below `--margin-threshold`.
fn disturbance_margin_lines(s: &TransferSummary, o: &mut String) {
    if let Some(l) = &s.least_safe_step {
        let _ = writeln!(
            o,
            "least safe step: {} (t = {:.3} s), smallest disturbance margin {} N along {} \
             (first to fail: {}){}",
            l.step,
            l.time_s,
            match l.margin_n {
                Some(v) => crate::report::significant(v, 5),
                None if l.undetermined.is_none() =>
                    format!("unbounded, >{}", crate::report::significant(l.held_to_n, 4)),
                None => format!(
                    "undetermined, >={}",
                    crate::report::significant(l.held_to_n, 4)
                ),
            },
            crate::pictures::margin_plot::label(&l.direction),
            l.failing_finger.as_deref().unwrap_or("-"),
            l.undetermined
                .as_ref()
                .map_or(String::new(), |why| format!(": {why}")),
        );
    }
    if s.other_equilibria.probed == Some(false) {
        let _ = writeln!(
            o,
            "second coulomb equilibria at the margins' failing ends: not probed \
             (--probe-equilibria)"
        );
    }
    if let Some((step, time_s, e)) = &s.other_equilibria.first {
        let _ = writeln!(
            o,
            "another coulomb equilibrium at a margin's failing end in {}: first at step {step} \
             (t = {time_s:.3} s) along {}: {} (the margins follow the searches' path)",
            crate::report::count(s.other_equilibria.steps as u64, "step", "steps"),
            crate::pictures::margin_plot::label(&e.direction),
            e.found
        );
    }
    if let Some(c) = &s.margin_below_threshold {
        let _ = writeln!(
            o,
            "smallest disturbance margin below {} N: first at step {} (t = {:.3} s), {} N",
            crate::report::significant(c.threshold_n, 5),
            c.step,
            c.time_s,
            match c.margin_n {
                Some(v) => crate::report::significant(v, 5),
                None => format!(
                    "undetermined, >={}",
                    crate::report::significant(c.held_to_n, 4)
                ),
            }
        );
    }
}

/// The failed steps' count and the first five, each with its reason.
fn failed_step_lines(s: &TransferSummary, o: &mut String) {
    if s.failed_step_count == 0 {
        let _ = writeln!(o, "failed steps: none");
        return;
    }
    let _ = writeln!(o, "failed steps: {}", s.failed_step_count);
    for f in s.failed_steps.iter().take(5) {
        let _ = writeln!(o, "  step {} (t = {:.3} s): {}", f.step, f.time_s, f.reason);
    }
}

/// The warnings of the `done` steps' solves, each once with the steps it applies to.
fn warning_lines(s: &TransferSummary, done: usize, o: &mut String) {
    let label = |k: usize| k.to_string();
    let steps = crate::report::Solves {
        total: done,
        singular: "step",
        plural: "steps",
        label: &label,
    };
    o.push_str(&crate::report::tallied_warning_lines(&s.warnings, &steps));
    if s.warnings_not_listed > 0 {
        let _ = writeln!(
            o,
            "warning: {} more distinct warnings, not listed",
            s.warnings_not_listed
        );
    }
}

/// How the `done` steps were solved: the sequential solves, which solver answered, warm
/// starts, iterations and factorisations per step, the FFT patches' conjugate-gradient
/// iterations, and the fallbacks to Clarabel.
fn solver_lines(s: &TransferSummary, done: usize, o: &mut String) {
    if let Some(q) = &s.sequential {
        let _ = writeln!(
            o,
            "sequential solves: {}, at most {} in a step, {} of {} warm-started, {}",
            count(q.convex_solves, "convex solve", "convex solves"),
            q.most_in_a_step,
            q.warm_started_steps,
            count(done as u64, "step", "steps"),
            count(q.cold_restarts as u64, "cold restart", "cold restarts")
        );
    }
    let steps = done.max(1) as f64;
    let _ = writeln!(
        o,
        "solver: native answered {}, Clarabel {}; {} (started from the previous one); {:.2} \
         iterations and {:.2} factorizations per step",
        count(s.answered_by_native as u64, "step", "steps"),
        s.answered_by_clarabel,
        count(s.warm_steps as u64, "warm step", "warm steps"),
        s.total_iterations as f64 / steps,
        s.total_factorizations as f64 / steps
    );
    if s.total_inner_iterations > 0 {
        let _ = writeln!(
            o,
            "patch compliance: {}; {:.1} conjugate-gradient iterations per step",
            s.compliance,
            s.total_inner_iterations as f64 / steps
        );
    }
    if let Some(why) = &s.fallbacks.first_reason {
        let _ = writeln!(
            o,
            "solver fallbacks: {} handed to Clarabel; first: {why}",
            count(s.fallbacks.steps as u64, "step", "steps")
        );
    }
}

/// Where the time went: the stepping (per step, its iterations), the margins' searches, and
/// the whole run of `run_s` seconds.
fn time_line(s: &TransferSummary, done: usize, run_s: f64, o: &mut String) {
    let margins = match s.least_safe_step {
        Some(_) => format!(
            "; margins {:.3} s ({})",
            s.margin_cost.wall_time_s,
            count(s.margin_cost.solves, "solve", "solves")
        ),
        None => String::new(),
    };
    let _ = writeln!(
        o,
        "time: stepping {:.3} s ({:.2} ms per step, {}){margins}; the whole run {:.3} s",
        s.total_wall_time_s,
        1e3 * s.total_wall_time_s / done.max(1) as f64,
        count(s.total_iterations, "iteration", "iterations"),
        run_s
    );
}

/// Per held or position-controlled finger whose force fell under one command, a line.
fn held_lines(s: &TransferSummary, o: &mut String) {
    for h in &s.held_relaxation {
        let _ = writeln!(
            o,
            "{} {}: normal force fell {:.2} % under one command, {} N (t = {:.3} s) \
             -> {} N (t = {:.3} s)",
            match h.position_controlled {
                true => "position-controlled finger",
                false => "held finger",
            },
            h.finger,
            100.0 * h.fraction,
            force_text(h.from_n),
            h.from_time_s,
            force_text(h.to_n),
            h.to_time_s
        );
    }
}

/// A force, N, to five decimals (`2.50000`); one too small to show there (a finger barely
/// touching) with four significant digits (`1.2000e-6`) instead of as `0.00000`.
fn force_text(force_n: f64) -> String {
    if force_n == 0.0 || force_n.abs() >= 1e-3 || !force_n.is_finite() {
        format!("{:.5}", force_n + 0.0)
    } else {
        format!("{force_n:.4e}")
    }
}

fn squeeze_text(o: &SqueezeOutcome) -> String {
    match o {
        SqueezeOutcome::NotFound(why) => format!("minimum squeeze: not found: {why}\n"),
        SqueezeOutcome::Found(m) => {
            let fingers: Vec<String> = m
                .fingers
                .iter()
                .map(|f| {
                    format!(
                        "{} {:.4} N (scheduled {:.4} N)",
                        f.name, f.minimum_n, f.scheduled_n
                    )
                })
                .collect();
            format!(
                "minimum squeeze to let go: {}; margin {:.3}x; just below it: {}\n",
                fingers.join(", "),
                m.margin,
                m.limiting
            )
        }
    }
}

fn list(v: &[String]) -> String {
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A held finger's fall from a force too small for five decimals shows its digits, never
    /// `0.00000 N -> -0.00000 N`.
    #[test]
    fn a_tiny_held_force_is_shown_with_its_digits_not_as_zero() {
        assert_eq!(force_text(1.2e-6), "1.2000e-6");
        assert_eq!(force_text(0.0), "0.00000");
        assert_eq!(force_text(-0.0), "0.00000");
        assert_eq!(force_text(2.5), "2.50000");
        assert_eq!(force_text(0.001), "0.00100");
    }
}
