//! `grasp`: the command-line front end. Flags become a validated configuration before any work
//! starts; the physics lives in `grasp-model`, the hand-off in `grasp-transfer`.

mod batch_run;
mod bench;
mod force_diagram;
mod limits;
mod load_scene;
mod margin;
mod margin_plot;
mod output;
mod picture;
mod plot;
mod report;
mod study;
mod transfer;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use grasp_model::{GraspModel, GraspSolver, SolveOptions, SolverChoice};
use load_scene::load_scene;

/// Elastic grasp contact forces and object hand-offs (Sinha 1989 contact-stress model).
#[derive(Parser, Debug)]
#[command(name = "grasp", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Solve one grasp: normal and friction forces of every finger, element by element.
    Solve {
        /// Scene file (JSON; see `grasp schema`).
        scene: PathBuf,
        /// Write the whole solution (elements, residuals, timing) as JSON to this file.
        #[arg(long, value_name = "OUT.json")]
        json: Option<PathBuf>,
        /// Overwrite output files that already exist.
        #[arg(long)]
        force: bool,
        /// Solver tolerance on the scaled program (feasibility and gap).
        #[arg(long, default_value_t = 1e-10, value_name = "TOL")]
        tolerance: f64,
        /// Also estimate the discretisation error from a solve on grids half as fine
        /// (Richardson, order 1) and report its extra cost.
        #[arg(long)]
        error_estimate: bool,
        /// Grow curved patches whose boundary carries load until it does not (thesis 2.2.1).
        #[arg(long)]
        auto_patch: bool,
        /// Solver: `auto` (native, falling back to Clarabel when it does not converge),
        /// `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        /// Also compute the derivatives of every finger's and element's forces with respect to
        /// an extra force and couple on the object and to each commanded load (from the KKT
        /// system at the active set); printed per finger and written into the JSON.
        #[arg(long)]
        sensitivities: bool,
        /// Print what the object's shape gave each finger (contact point, inward normal,
        /// tangent, principal curvatures and the radii written into the scene), the shape's
        /// volume and mass, and the shape checks' warnings.
        #[arg(long)]
        explain_frames: bool,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Force diagram of one solve (SVG or PNG): two orthographic views with the object's
    /// outline, each finger's normal and friction force, its friction cone, and the weight.
    Plot {
        /// Scene file (JSON).
        scene: PathBuf,
        /// The picture to write: .svg or .png (by the extension).
        #[arg(long, value_name = "F.svg|F.png")]
        out: PathBuf,
        /// Overwrite OUT if it exists.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Disturbance margins: per direction of an extra wrench on the object, the largest
    /// magnitude the grasp takes before it fails (no equilibrium, or coulomb: a finger slides as
    /// a whole), with the finger that fails first.
    Margin {
        /// Scene file (JSON).
        scene: PathBuf,
        /// Directions: a number N (the axis directions, then combined ones spread over the
        /// sphere), `planes:K` (K force directions around each coordinate plane, for the polar
        /// plot, and the couple axes) or a JSON file with a list of {"force": [N], "torque":
        /// [N m]}. Default: the axis directions.
        #[arg(long, value_name = "N|planes:K|FILE")]
        directions: Option<String>,
        /// Contact law to judge the grasp with (default: the scene's).
        #[arg(long, value_parser = ["energy", "coulomb"])]
        model: Option<String>,
        /// Characteristic length L, m: a magnitude s means a force s N and a couple s L N m.
        /// Default: the grasp's reach from the centroid of the contacts.
        #[arg(long, value_name = "M")]
        length: Option<f64>,
        /// Relative width of the final bracket of each margin.
        #[arg(long, default_value_t = 1e-3, value_name = "REL")]
        tolerance: f64,
        /// Write the report as JSON.
        #[arg(long, value_name = "OUT.json")]
        json: Option<PathBuf>,
        /// Write a picture of the margins (.svg or .png): polar plots of the force directions
        /// in each coordinate plane and a bar per direction.
        #[arg(long, value_name = "F.svg|F.png")]
        plot: Option<PathBuf>,
        /// Write a Rerun recording of the grasp with its wrench surface.
        #[arg(long, value_name = "F.rrd")]
        rrd: Option<PathBuf>,
        /// Overwrite output files that already exist.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Solve many scenes: one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare
    /// scene) or one per file of a folder; one result line each, in input order, on all cores.
    Batch {
        /// JSONL file or folder of scene files (omit with --merge).
        input: Option<PathBuf>,
        /// Result lines (JSONL).
        #[arg(long, value_name = "RESULTS.jsonl")]
        out: PathBuf,
        /// Append to OUT, skipping the scenes whose id is already in it.
        #[arg(long)]
        resume: bool,
        /// Take every N-th scene from the I-th (0-based). Default: Slurm's
        /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT, or Kubernetes' JOB_COMPLETION_INDEX with
        /// GRASP_SHARD_COUNT, else everything.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Worker threads (default: one per core).
        #[arg(long, value_name = "J")]
        jobs: Option<usize>,
        /// Join these shard outputs into OUT (checked complete) instead of solving.
        #[arg(long, num_args = 1.., value_name = "SHARD.jsonl", conflicts_with_all = ["input", "resume", "shard"])]
        merge: Vec<PathBuf>,
        /// Overwrite OUT if it exists.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Expand a grid of variants of one scene (`--vary PATH=START:END:COUNT` or
    /// `PATH=V1,V2,...`, e.g. `fingers[*].friction.mu=0.2:1.0:9`) into JSONL for `batch`, or
    /// run them (`--run`).
    Sweep {
        /// Scene file (JSON).
        scene: PathBuf,
        /// One axis of the grid (repeat; the last varies fastest).
        #[arg(long = "vary", value_name = "PATH=RANGE", required = true)]
        vary: Vec<String>,
        /// The variants (JSONL), or with --run their results.
        #[arg(long, value_name = "OUT.jsonl")]
        out: PathBuf,
        /// Solve the variants now (as `grasp batch` would) and write their results.
        #[arg(long)]
        run: bool,
        /// Worker threads for --run (default: one per core).
        #[arg(long, value_name = "J")]
        jobs: Option<usize>,
        /// Overwrite OUT if it exists.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Grid-refinement study: error, unknowns, wall time and peak memory per grid.
    Study {
        /// Scene file (JSON).
        scene: PathBuf,
        /// Elements along the first side of every patch, one solve each (aspect ratio kept).
        #[arg(long, value_delimiter = ',', default_value = "5,9,17")]
        grids: Vec<usize>,
        /// Error reference: `hertz` (closed form; one spherical tip on a flat) or `finest`
        /// (the finest grid of the study).
        #[arg(long, default_value = "finest", value_parser = ["hertz", "finest"])]
        reference: String,
        /// Write the table as CSV.
        #[arg(long, value_name = "F.csv")]
        csv: Option<PathBuf>,
        /// Write an error-versus-time plot (.svg or .png).
        #[arg(long, value_name = "F.svg|F.png")]
        plot: Option<PathBuf>,
        /// Overwrite output files that already exist.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Replay a hand-off: step a load schedule, log every step to MCAP / Rerun / CSV.
    Transfer {
        /// Scene file (JSON).
        scene: PathBuf,
        /// Schedule file (JSON; see `grasp schema --schedule`).
        #[arg(long, value_name = "SCHEDULE.json")]
        schedule: PathBuf,
        /// Write an MCAP log (per-finger resultants and per-element fields, JSON with schemas).
        #[arg(long, value_name = "F.mcap")]
        mcap: Option<PathBuf>,
        /// Write a Rerun recording (.rrd) to replay in the Rerun viewer.
        #[arg(long, value_name = "F.rrd")]
        rrd: Option<PathBuf>,
        /// Stream every step, as it is computed, to a running Rerun viewer or server (`rerun`,
        /// or headless `rerun --save F.rrd`); default address rerun+http://127.0.0.1:9876/proxy.
        #[arg(long, value_name = "URL", num_args = 0..=1, default_missing_value = "rerun+http://127.0.0.1:9876/proxy")]
        rerun_connect: Option<String>,
        /// Start a Rerun viewer (`rerun` on the PATH) and stream every step to it.
        #[arg(long, conflicts_with = "rerun_connect")]
        rerun_spawn: bool,
        /// Write the force histories as CSV.
        #[arg(long, value_name = "F.csv")]
        csv: Option<PathBuf>,
        /// Write a force-history plot (.svg or .png), like thesis figures 15 and 17.
        #[arg(long, value_name = "F.svg|F.png")]
        plot: Option<PathBuf>,
        /// Continue past a step without equilibrium (default: stop there).
        #[arg(long)]
        keep_going: bool,
        /// Rebuild the program at every step and start every sequential solve from an
        /// energy-model solve instead of the previous step (for comparison).
        #[arg(long)]
        cold: bool,
        /// After the run, find the smallest load of the receiving (force-controlled) fingers
        /// at which the releasing fingers can let go without any finger sliding as a whole.
        #[arg(long)]
        min_squeeze: bool,
        /// At every solved step, find the smallest disturbance margin over the axis directions
        /// of force and couple (logged to MCAP and Rerun; the summary names the least safe
        /// step).
        #[arg(long)]
        margins: bool,
        /// Overwrite output files that already exist.
        #[arg(long)]
        force: bool,
        /// Solver: `auto`, `native` or `clarabel`.
        #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
        solver: SolverChoice,
        #[command(flatten)]
        memory: MemoryArg,
    },
    /// Benchmark table: the cases of issue 9 (cube A grids, Hertz 41x41, both hand-offs warm
    /// and cold, the whole transfer command) with each solver, medians against targets.
    Bench {
        /// Only the cases that take well under a second, one timing run each.
        #[arg(long)]
        quick: bool,
        /// Print the table as Markdown.
        #[arg(long)]
        markdown: bool,
        /// Solvers to compare (comma-separated).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "native,clarabel",
            value_name = "auto|native|clarabel"
        )]
        solver: Vec<SolverChoice>,
        /// Run only these cases (comma-separated names from the table).
        #[arg(long = "case", value_delimiter = ',', value_name = "NAME")]
        cases: Vec<String>,
        /// Keep timing a case until this many seconds have passed (at least 2 runs, at most
        /// 50).
        #[arg(long, default_value_t = 1.0, value_name = "SECONDS")]
        min_time: f64,
    },
    /// Print the JSON Schema of the scene format (or of the schedule format).
    Schema {
        /// Print the schedule format's schema instead.
        #[arg(long)]
        schedule: bool,
    },
}

/// The memory limit of a command.
#[derive(clap::Args, Debug)]
struct MemoryArg {
    /// Refuse scenes whose estimated memory exceeds this many bytes (suffixes K, M, G, T:
    /// 512M, 4G); default: a quarter of the machine's memory (MemTotal in /proc/meminfo).
    #[arg(long, value_name = "BYTES", value_parser = limits::parse_bytes)]
    max_memory: Option<u64>,
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
    if let Err(e) = output::install_signal_cleanup() {
        eprintln!("error: {e:#}");
        return ExitCode::from(1);
    }
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Schema { schedule } => {
            let schema = if schedule {
                serde_json::to_value(schemars::schema_for!(grasp_transfer::ScheduleSpec))?
            } else {
                serde_json::to_value(grasp_model::scene_json_schema())?
            };
            println!("{}", serde_json::to_string_pretty(&schema)?);
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench {
            quick,
            markdown,
            solver,
            cases,
            min_time,
        } => {
            if !(min_time.is_finite() && min_time >= 0.0) {
                anyhow::bail!("--min-time {min_time}: give a number of seconds >= 0, e.g. 1");
            }
            bench::run(bench::Flags {
                quick,
                markdown,
                solvers: solver,
                cases,
                min_time_s: min_time,
            })
        }
        Command::Transfer {
            scene,
            schedule,
            mcap,
            rrd,
            rerun_connect,
            rerun_spawn,
            csv,
            plot,
            keep_going,
            cold,
            min_squeeze,
            margins,
            force,
            solver,
            memory,
        } => {
            let live = match (rerun_connect, rerun_spawn) {
                (Some(url), _) => Some(transfer::Live::Connect(url)),
                (None, true) => Some(transfer::Live::Spawn),
                (None, false) => None,
            };
            let outputs = transfer::Outputs {
                mcap,
                rrd,
                csv,
                plot,
                force,
                live,
            };
            let flags = transfer::Flags {
                keep_going,
                cold,
                min_squeeze,
                margins,
                solver,
                max_memory: memory.max_memory,
            };
            transfer::run(&scene, &schedule, &outputs, flags)
        }
        Command::Study {
            scene,
            grids,
            reference,
            csv,
            plot,
            force,
            solver,
            memory,
        } => study::run(
            &scene,
            &grids,
            &reference,
            study::Outputs {
                csv: csv.as_deref(),
                plot: plot.as_deref(),
                force,
            },
            memory.max_memory,
            solver,
        ),
        Command::Batch {
            input,
            out,
            resume,
            shard,
            jobs,
            merge,
            force,
            solver,
            memory,
        } => {
            if !merge.is_empty() {
                return batch_run::merge(&merge, &out, force);
            }
            let Some(input) = input else {
                anyhow::bail!("give a JSONL file or a folder of scenes (or --merge SHARDS...)");
            };
            let flags = batch_run::Flags {
                out,
                resume,
                force,
                shard,
                jobs,
                solver,
                max_memory: memory.max_memory,
            };
            let source = grasp_batch::BatchInput::open(&input)?;
            batch_run::run(&source, Some(&input), &flags)
        }
        Command::Sweep {
            scene,
            vary,
            out,
            run,
            jobs,
            force,
            solver,
            memory,
        } => {
            let flags = batch_run::Flags {
                out,
                resume: false,
                force,
                shard: None,
                jobs,
                solver,
                max_memory: memory.max_memory,
            };
            batch_run::sweep(&scene, &vary, run, &flags)
        }
        Command::Plot {
            scene,
            out,
            force,
            solver,
            memory,
        } => plot_command(&scene, &out, force, solver, memory.max_memory),
        Command::Margin {
            scene,
            directions,
            model,
            length,
            tolerance,
            json,
            plot,
            rrd,
            force,
            solver,
            memory,
        } => margin::run(
            &scene,
            margin::Flags {
                directions,
                model,
                length_m: length,
                tolerance,
                solver,
                max_memory: memory.max_memory,
            },
            &margin::Outputs {
                json,
                plot,
                rrd,
                force,
            },
        ),
        Command::Solve {
            scene,
            json,
            force,
            tolerance,
            error_estimate,
            auto_patch,
            solver,
            sensitivities,
            explain_frames,
            memory,
        } => {
            if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1e-2) {
                anyhow::bail!("--tolerance is {tolerance}; give a value in (0, 1e-2), e.g. 1e-10");
            }
            let outputs: Vec<&Path> = json.iter().map(PathBuf::as_path).collect();
            output::check_targets(&outputs, &[&scene], force)?;
            let scene_obj = load_scene(&scene)?;
            let (limit, what) = limits::memory_limit(memory.max_memory);
            limits::check_memory(&scene_obj, &scene, (limit, &what))?;
            if explain_frames {
                print!("{}", report::hertz_table(&scene_obj)?);
            }
            if let Some(r) = &scene_obj.shape_report {
                if explain_frames {
                    print!("{}", report::frames_table(r));
                }
                for w in &r.warnings {
                    println!("warning: {w}");
                }
            } else if explain_frames {
                println!("frames: the scene has no object.shape; every frame is as written");
            }
            let options = SolveOptions {
                tolerance,
                solver,
                ..SolveOptions::default()
            };
            let t0 = Instant::now();
            let (scene_obj, model, solution, build_s, sens) = if auto_patch {
                let a = grasp_model::patch_sizing::auto_patch(&scene_obj, options, 6)?;
                for line in &a.log {
                    println!("auto-patch: {line}");
                }
                // The derivative is taken at a solver's own answer: solve the final patch again.
                let mut solver = GraspSolver::new(&a.model, options);
                let sens = match sensitivities {
                    true => {
                        let again = solver.solve(&a.model, &a.model.scene_loads_n())?;
                        sensitivities_of(&mut solver, &a.model, &again)?
                    }
                    false => None,
                };
                (a.scene, a.model, a.solution, 0.0, sens)
            } else {
                let model = GraspModel::from_scene(&scene_obj)
                    .with_context(|| format!("{} is not a usable scene", scene.display()))?;
                let build_s = t0.elapsed().as_secs_f64();
                // The solve's time covers the program assembly (GraspSolver::new) too.
                let mut solver = GraspSolver::new(&model, options);
                let solution = solver.solve(&model, &model.scene_loads_n())?;
                let sens = match sensitivities {
                    true => sensitivities_of(&mut solver, &model, &solution)?,
                    false => None,
                };
                (scene_obj, model, solution, build_s, sens)
            };
            print!(
                "{}",
                report::solution_table(&scene, &model, &solution, build_s)
            );
            if error_estimate && solution.status.has_forces() {
                println!(
                    "{}",
                    report::error_estimate_line(&scene_obj, &solution, options)?
                );
            }
            if let Some((sens, time_s)) = &sens {
                print!("{}", report::sensitivity_table(sens, *time_s));
            }
            if let Some(out) = &json {
                // Every outcome is written, "no equilibrium" (exit 2) included: it is the result.
                let mut value = serde_json::to_value(&solution)?;
                if let Some((sens, _)) = &sens {
                    value["sensitivities"] = serde_json::to_value(sens)?;
                }
                let text = serde_json::to_string_pretty(&value)?;
                output::write_new(out, text.as_bytes(), force)?;
                println!("wrote {}", out.display());
            }
            Ok(if solution.status.has_forces() {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(2)
            })
        }
    }
}

/// `grasp plot`: solves the scene and writes its force diagram.
fn plot_command(
    scene_path: &Path,
    out: &Path,
    force: bool,
    solver: SolverChoice,
    max_memory: Option<u64>,
) -> Result<ExitCode> {
    let format = picture::Format::of(out, "--out")?;
    output::check_targets(&[out], &[scene_path], force)?;
    let scene = load_scene(scene_path)?;
    let (limit, what) = limits::memory_limit(max_memory);
    limits::check_memory(&scene, scene_path, (limit, &what))?;
    let model = GraspModel::from_scene(&scene)
        .with_context(|| format!("{} is not a usable scene", scene_path.display()))?;
    let options = SolveOptions {
        solver,
        ..SolveOptions::default()
    };
    let solution = GraspSolver::new(&model, options).solve(&model, &model.scene_loads_n())?;
    let title = scene_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let diagram = force_diagram::ForceDiagram {
        scene: &scene,
        model: &model,
        solution: &solution,
        title: &title,
    };
    output::write_new(out, &picture::render(&diagram, format)?, force)?;
    println!(
        "{}: {}; wrote {}",
        title,
        solution.status.as_str(),
        out.display()
    );
    Ok(if solution.status.has_forces() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

/// The sensitivities of `solution` (this solver's last answer) with their time, s; `None`
/// without forces.
fn sensitivities_of(
    solver: &mut GraspSolver,
    model: &GraspModel,
    solution: &grasp_model::Solution,
) -> Result<Option<(grasp_model::Sensitivities, f64)>> {
    if !solution.status.has_forces() {
        return Ok(None);
    }
    let t = Instant::now();
    let sens = solver.sensitivities(model, solution)?;
    Ok(Some((sens, t.elapsed().as_secs_f64())))
}
