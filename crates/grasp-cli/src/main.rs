//! `grasp`: the command-line front end. Flags become a validated configuration before any work
//! starts; the physics lives in `grasp-model`, the hand-off in `grasp-transfer`.

// Every module prints through these (declared before the modules, so they replace the
// standard macros there): a closed standard output (`grasp schema | head`) ends the run quietly
// with exit 141 instead of a panic, and a closed standard error is ignored (see `stdout`).
macro_rules! print {
    ($($arg:tt)*) => { $crate::stdout::write(format_args!($($arg)*)) };
}
macro_rules! println {
    () => { $crate::stdout::write(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::stdout::write(format_args!("{}\n", format_args!($($arg)*))) };
}
macro_rules! eprint {
    ($($arg:tt)*) => { $crate::stdout::write_err(format_args!($($arg)*)) };
}
macro_rules! eprintln {
    () => { $crate::stdout::write_err(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::stdout::write_err(format_args!("{}\n", format_args!($($arg)*))) };
}

mod commands;
mod flag_names;
mod limits;
mod load_scene;
mod mcap_profile_flags;
mod output;
mod pictures;
mod progress;
mod report;
mod solution_files;
mod solve_display;
mod solve_flags;
mod stdout;

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

/// Elastic grasp contact forces and object hand-offs (Sinha 1989 contact-stress model).
#[derive(Parser, Debug)]
#[command(name = "grasp", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No progress bars (they are drawn on a terminal's standard error only, for the runs
    /// that take long: hand-offs, batches, margins, a viscoelastic history, studies).
    #[arg(long, global = true)]
    quiet: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Solve one grasp: normal and friction forces of every finger, element by element.
    Solve(commands::solve::Args),
    /// Force diagram of one solve (SVG or PNG): two orthographic views with the object's
    /// outline, each finger's normal and friction force, its friction cone, and the weight.
    Plot(commands::plot::Args),
    /// Disturbance margins: per direction of an extra wrench on the object, the largest
    /// magnitude the grasp takes before it fails (no equilibrium, or coulomb: a finger slides as
    /// a whole), with the finger that fails first.
    Margin(commands::margin::Args),
    /// Solve many scenes: one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare
    /// scene) or one per file of a folder; one result line each, in input order, on all cores.
    Batch(commands::batch::Args),
    /// Expand a grid of variants of one scene (`--vary PATH=START:END:COUNT` or
    /// `PATH=V1,V2,...`, e.g. `fingers[*].friction.mu=0.2:1.0:9`) into JSONL for `batch`, or
    /// run them (`--run`).
    Sweep(commands::sweep::Args),
    /// Grid-refinement study: error, unknowns, wall time and peak memory per grid.
    Study(commands::study::Args),
    /// Replay a hand-off: step a load schedule, log every step to MCAP / Rerun / CSV.
    Transfer(commands::transfer::Args),
    /// Plan a hand-off: the releasing and receiving fingers' load ramps that keep every
    /// step's slip margin above a threshold, within load and rate limits, in the shortest
    /// duration (or with the largest smallest margin); the schedule is written once checked.
    Plan(Box<commands::plan::Args>),
    /// Benchmark table: the solver's cases (cube A grids, Hertz 41x41, both hand-offs warm
    /// and cold, the whole transfer command) with each solver, medians against targets.
    Bench(commands::bench::Args),
    /// Print the JSON Schema of the scene format (or of the schedule format).
    Schema(commands::schema::Args),
}

fn main() -> ExitCode {
    // A usage error is bad input: exit 1 (clap's own code, 2, means an outcome here).
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 1 } else { 0 });
        }
    };
    progress::set_quiet(cli.quiet);
    // The solves' worker threads, started here so that a process too small for their stacks
    // (an address-space limit) is told so, rather than panicking at the first parallel loop.
    if let Err(e) = rayon::ThreadPoolBuilder::new().build_global() {
        eprintln!(
            "error: cannot start the worker threads ({e}); fix: free memory or raise the \
             memory limit (ulimit -v)"
        );
        return ExitCode::from(1);
    }
    if let Err(e) = output::install_signal_cleanup() {
        eprintln!("error: {e:#}");
        return ExitCode::from(1);
    }
    let code = match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", flag_names::in_flags(&format!("{e:#}")));
            ExitCode::from(1)
        }
    };
    // A last line without its newline is still buffered: a closed pipe shows here.
    stdout::flush();
    code
}

/// Runs the command given.
fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Solve(args) => commands::solve::execute(args),
        Command::Plot(args) => commands::plot::execute(args),
        Command::Margin(args) => commands::margin::execute(args),
        Command::Batch(args) => commands::batch::execute(args),
        Command::Sweep(args) => commands::sweep::execute(args),
        Command::Study(args) => commands::study::execute(args),
        Command::Transfer(args) => commands::transfer::execute(args),
        Command::Plan(args) => commands::plan::execute(*args),
        Command::Bench(args) => commands::bench::execute(args),
        Command::Schema(args) => commands::schema::execute(args),
    }
}
