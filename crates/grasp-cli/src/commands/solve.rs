//! `grasp solve`: one grasp solved and reported (table, JSON, sensitivities, frames).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Result};
use grasp_model::{solve_at_reporting, TimePoint, TimedSolution};
use grasp_model::{ComplianceChoice, LoadedScene, Scene, Sensitivities, Solution};
use grasp_model::{GraspModel, GraspSolver, SolveOptions, StepInputs};

use crate::load_scene::load_scene;
use crate::output::{self, ForceArg, Outputs};
use crate::pictures::contact_maps::{ContactMaps, FingerPatch};
use crate::pictures::picture;
use crate::report;
use crate::solve_display::SolveDisplay;
use crate::solve_flags::SolveFlags;

/// Solve one grasp: normal and friction forces of every finger, element by element.
#[derive(clap::Args, Debug)]
#[command(mut_arg("solver", |a| a.help(SOLVER_HELP)))]
#[command(mut_arg("compliance", |a| a.help(COMPLIANCE_HELP)))]
pub struct Args {
    /// Scene file (JSON; see `grasp schema`).
    pub scene: PathBuf,
    /// Write the whole solution (elements, residuals, timing) as JSON to this file (a finger
    /// of more than 64x64 elements: one array per field, `element_fields`); the tactile
    /// sensors' readings (taxels, markers, gel images) under `sensors` when the scene has one.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// Write every finger's element fields (forces, pressures, gaps, slips, states, centres)
    /// as NumPy arrays to this `.npz` file, one array per field and finger (`<finger>/<field>`:
    /// `numpy.load(path)["f1/pressure_pa"]`), float64 as solved; a finger's taxel sensor as
    /// `<finger>/taxels/force_n` (nx, ny, 3), its markers as `<finger>/markers/displacement_m`
    /// (nx, ny, 3), its gel image as `<finger>/gel/height_m` (nx, ny) and `<finger>/gel/rgb8`
    /// (nx, ny, 3).
    #[arg(long, value_name = "OUT.npz")]
    pub npz: Option<PathBuf>,
    /// Draw every finger's contact pressure and stick / slip map over its patch (.svg or
    /// .png; a patch finer than 64 elements a side is drawn in blocks, each at its largest
    /// pressure and its most frequent state).
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Write the gel images of the fingers whose sensor has one (`sensor.gel`) as one PNG:
    /// each shaded image, one PNG pixel a gel pixel, side by side in scene order.
    #[arg(long, value_name = "F.png")]
    pub gel_png: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    /// Solver tolerance on the scaled program (feasibility and gap), in [1e-14, 1e-2]: below
    /// 1e-14 round-off exceeds it, above 1e-2 an answer is no solution.
    #[arg(long, default_value = grasp_model::DEFAULT_TOLERANCE_TEXT, value_name = "TOL")]
    pub tolerance: f64,
    /// Also estimate the discretisation error from a solve on grids half as fine
    /// (Richardson, order 1) and report its extra cost.
    #[arg(long)]
    pub error_estimate: bool,
    /// Grow curved patches whose boundary carries load until it does not (thesis 2.2.1).
    #[arg(long)]
    pub auto_patch: bool,
    #[command(flatten)]
    pub solve: SolveFlags,
    /// Also compute the derivatives of every finger's and element's forces with respect to
    /// an extra force and couple on the object, to each commanded load and approach and to
    /// each mount's, hand's and servo's stiffness (from the KKT system at the active set); printed per finger and
    /// written into the JSON.
    #[arg(long)]
    pub sensitivities: bool,
    /// Print what the object's shape gave each finger (contact point, inward normal,
    /// tangent, principal curvatures and the radii written into the scene), the shape's
    /// volume and mass, and the shape checks' warnings.
    #[arg(long)]
    pub explain_frames: bool,
    /// A viscoelastic scene's state this many seconds after its loads and approaches were
    /// applied as a step at t = 0 (the history stepped: 50 steps a decade), instead of the
    /// instantaneous response; in (0, 1e9].
    #[arg(long, value_name = "SECONDS", conflicts_with_all = ["long_term", "auto_patch", "sensitivities"])]
    pub at_time: Option<f64>,
    /// A viscoelastic scene's fully relaxed state (every viscoelastic body at its long-term
    /// modulus), instead of the instantaneous response.
    #[arg(long, conflicts_with_all = ["auto_patch", "sensitivities"])]
    pub long_term: bool,
}

/// `--solver`'s help here: what `auto` does.
const SOLVER_HELP: &str = "Solver: `auto` (native, falling back to Clarabel when it does not \
                           converge), `native` or `clarabel`";

/// `--compliance`'s help here: each form in full.
const COMPLIANCE_HELP: &str = "Patch compliance: `dense` (a stored matrix, factorised), `fft` (a \
     matrix-free FFT operator, solved by conjugate gradients: for fine grids, native solver \
     only) or `auto` (dense up to 1,024 unknowns a patch: 32x32 frictionless, 22x22 planar, \
     18x18 with friction in 3-D; FFT above)";

/// The time point `--at-time` / `--long-term` ask for.
fn time_point(at_time: Option<f64>, long_term: bool) -> Result<TimePoint> {
    Ok(match (at_time, long_term) {
        (Some(t), _) => {
            if !(t.is_finite() && t > 0.0 && t <= 1e9) {
                bail!("--at-time {t}: give the time after the step in seconds, in (0, 1e9]");
            }
            TimePoint::At { seconds: t }
        }
        (None, true) => TimePoint::LongTerm,
        (None, false) => TimePoint::Instantaneous,
    })
}

/// `grasp solve`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let Args {
        scene,
        json,
        npz,
        plot,
        gel_png,
        force,
        tolerance,
        error_estimate,
        auto_patch,
        solve,
        sensitivities,
        explain_frames,
        at_time,
        long_term,
    } = args;
    let request = Request {
        options: SolveOptions {
            tolerance,
            ..solve.options()
        },
        time: time_point(at_time, long_term)?,
        sensitivities,
    };
    request.options.validate()?;
    let plot_format = plot
        .as_deref()
        .map(|p| picture::Format::of(p, "--plot"))
        .transpose()?;
    let outputs: Vec<&Path> = json
        .iter()
        .chain(&npz)
        .chain(&plot)
        .chain(&gel_png)
        .map(PathBuf::as_path)
        .collect();
    let outs = output::claim(&outputs, &[&scene], force.force)?;
    let scene_obj = load_scene(&scene)?;
    let has_gel = |f: &grasp_model::FingerSpec| f.sensor.as_ref().is_some_and(|s| s.gel.is_some());
    if gel_png.is_some() && !scene_obj.scene.fingers.iter().any(has_gel) {
        anyhow::bail!(crate::pictures::gel_picture::NO_GEL_IMAGE);
    }
    solve.check_memory(&scene_obj, &scene)?;
    if explain_frames {
        print_frames(&scene_obj)?;
    }
    let mut solved = match auto_patch {
        true => solve_auto_patch(&scene_obj, request)?,
        false => solve_scene(scene_obj, &scene, solve.compliance, request)?,
    };
    crate::flag_names::respell_solution(&mut solved.solution);
    print_report(&scene, &solved, request.options, error_estimate)?;
    let solution = &solved.solution;
    // Only a scene with a sensor reads one: any other computes and writes nothing more.
    let sensors = match solution.status.has_forces() {
        true => grasp_model::sensor_readings(&solved.scene, &solved.model, solution)?,
        false => Vec::new(),
    };
    if !sensors.is_empty() {
        print!("{}", report::sensor_table(&sensors));
    }
    print!("{}", report::mount_table(solution));
    print!("{}", report::shared_spring_table(solution));
    if let Some(out) = &json {
        // Every outcome is written, "no equilibrium" (exit 2) included: it is the result.
        let record = grasp_io::SolutionRecord {
            solution,
            time: solved.model.is_viscoelastic().then_some(request.time),
            sensitivities: solved.sensitivities.as_ref().map(|(s, _)| s),
            sensors: (!sensors.is_empty()).then_some(sensors.as_slice()),
        };
        crate::solution_files::write_json(&outs, out, &record)?;
    }
    if let Some(out) = &npz {
        crate::solution_files::write_npz(&outs, out, solution, &sensors)?;
    }
    if let (Some(out), Some(format)) = (&plot, plot_format) {
        write_maps(&outs, out, format, &scene, &solved)?;
    }
    if let Some(out) = &gel_png {
        let clock = Instant::now();
        outs.write(out, &crate::pictures::gel_picture::gel_png(&sensors)?)?;
        crate::solution_files::say_written(out, clock);
    }
    Ok(if solution.status.has_forces() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

/// `--plot`: the contact maps of `solved` (the scene read from `scene_path`, titled by its
/// file's name) written to the claimed `out` as `format`, and said.
fn write_maps(
    outs: &Outputs,
    out: &Path,
    format: picture::Format,
    scene_path: &Path,
    solved: &Solved,
) -> Result<()> {
    let clock = Instant::now();
    let fingers = solved
        .solution
        .fingers
        .iter()
        .filter_map(|f| {
            let spec = solved.scene.fingers.iter().find(|s| s.name == f.name)?;
            Some(FingerPatch {
                size_m: spec.patch.size,
                grid: spec.patch.grid,
                frictionless: spec.friction.is_frictionless(),
                solution: f,
            })
        })
        .collect();
    // The file's name, as `grasp plot` titles its diagram: the picture does not depend on
    // where the scene lies.
    let title = scene_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let maps = ContactMaps {
        solution: &solved.solution,
        model: solved.model.kind(),
        fingers,
        title: &title,
    };
    outs.write(out, &picture::render(&maps, format)?)?;
    crate::solution_files::say_written(out, clock);
    Ok(())
}

/// How to solve: the solver's options, the time point, and whether to take the sensitivities.
#[derive(Clone, Copy)]
struct Request {
    /// The solver's options (`--solver`, `--compliance`, `--tolerance`).
    options: SolveOptions,
    /// The instant (`--at-time`, `--long-term`).
    time: TimePoint,
    /// Also the derivatives of the forces (`--sensitivities`).
    sensitivities: bool,
}

/// A solved scene and what its report needs.
struct Solved {
    /// The scene solved (after `--auto-patch`, with its grown patches).
    scene: LoadedScene,
    /// Its model.
    model: Arc<GraspModel>,
    /// The solution.
    solution: Solution,
    /// The model's build, s (0 after `--auto-patch`, whose log says what it did).
    build_s: f64,
    /// The sensitivities and their time, s, when asked for and the solve has forces.
    sensitivities: Option<(Sensitivities, f64)>,
}

/// `--explain-frames`: each finger's gaps and Hertz estimate, and what the object's shape gave
/// each finger (its warnings are the solution's, printed with it).
fn print_frames(scene: &LoadedScene) -> Result<()> {
    print!("{}", report::hertz_table(scene)?);
    match scene.shape_report() {
        Some(r) => print!("{}", report::frames_table(r)),
        None => println!("frames: the scene has no object.shape; every frame is as written"),
    }
    Ok(())
}

/// `--auto-patch`: curved patches grown until their boundary carries no load, the log
/// printed; the sensitivities taken at a solve of the final patch.
fn solve_auto_patch(scene: &LoadedScene, request: Request) -> Result<Solved> {
    let a = grasp_model::auto_patch(scene, request.options, 6)?;
    for line in &a.log {
        println!("auto-patch: {line}");
    }
    // The derivative is taken at a solver's own answer: solve the final patch again.
    let model = Arc::new(a.model);
    let mut solver = GraspSolver::new(Arc::clone(&model), request.options);
    let sensitivities = match request.sensitivities {
        true => {
            let again = solver.solve(&StepInputs::of_scene(&model))?;
            sensitivities_of(&mut solver, &again)?
        }
        false => None,
    };
    Ok(Solved {
        scene: a.scene,
        model,
        solution: a.solution,
        build_s: 0.0,
        sensitivities,
    })
}

/// The scene's model built (its compliances in the form `compliance` picks) and solved at the
/// request's time point; a viscoelastic scene solved instantaneously says how to ask for a
/// later state.
fn solve_scene(
    scene: LoadedScene,
    scene_path: &Path,
    compliance: ComplianceChoice,
    request: Request,
) -> Result<Solved> {
    let t0 = Instant::now();
    let display = match request.time {
        TimePoint::Instantaneous => long_solve_display(&scene),
        _ => None,
    };
    let model = crate::load_scene::model_of(&scene, compliance, scene_path)?;
    let model = Arc::new(model);
    let build_s = t0.elapsed().as_secs_f64();
    // The solve's time covers the program assembly (GraspSolver::new) too.
    let (solution, sensitivities) = match request.time {
        TimePoint::Instantaneous => solve_now(&model, request, display)?,
        later => (solve_later(&model, request.options, later)?, None),
    };
    if request.time == TimePoint::Instantaneous && model.is_viscoelastic() {
        println!(
            "viscoelastic: {}; --at-time SECONDS or --long-term for a later state",
            request.time
        );
    }
    Ok(Solved {
        scene,
        model,
        solution,
        build_s,
        sensitivities,
    })
}

/// The instantaneous response, shown on `display` while it is solved, and its sensitivities
/// when asked for.
fn solve_now(
    model: &Arc<GraspModel>,
    request: Request,
    mut display: Option<SolveDisplay>,
) -> Result<(Solution, Option<(Sensitivities, f64)>)> {
    let mut solver = GraspSolver::new(Arc::clone(model), request.options);
    if let Some(d) = &mut display {
        solver.set_progress(d.progress());
        d.solving();
    }
    let solution = solver.solve(&StepInputs::of_scene(model));
    drop(display);
    let solution = solution?;
    let sensitivities = match request.sensitivities {
        true => sensitivities_of(&mut solver, &solution)?,
        false => None,
    };
    Ok((solution, sensitivities))
}

/// The state at a `later` time point, its history stepped under a progress bar; the time it
/// took is the solve's time, and a line says what was stepped.
fn solve_later(model: &GraspModel, options: SolveOptions, later: TimePoint) -> Result<Solution> {
    let clock = Instant::now();
    let bar = crate::progress::bar(0, "time steps");
    let mut tick = |k: usize, n: usize| {
        bar.set_length(n as u64);
        bar.set_position(k as u64 + 1);
    };
    let mut timed = solve_at_reporting(model, options, later, &mut tick)?;
    bar.finish_and_clear();
    timed.solution.solve_time_s = clock.elapsed().as_secs_f64();
    println!("{}", time_line(model, &timed));
    Ok(timed.solution)
}

/// The report of a solve: its table, the error estimate (`--error-estimate`, with forces) and
/// the sensitivities.
fn print_report(
    scene_path: &Path,
    solved: &Solved,
    options: SolveOptions,
    error_estimate: bool,
) -> Result<()> {
    let solution = &solved.solution;
    print!(
        "{}",
        report::solution_table(scene_path, &solved.model, solution, solved.build_s)
    );
    if error_estimate && solution.status.has_forces() {
        println!(
            "{}",
            report::error_estimate_line(&solved.scene, solution, options)?
        );
    }
    if let Some((sens, time_s)) = &solved.sensitivities {
        print!("{}", report::sensitivity_table(sens, *time_s));
    }
    Ok(())
}

/// The display of a solve of `scene` when it is long (on a terminal, without `--quiet`): its
/// unknowns and its largest patch's grid.
fn long_solve_display(scene: &Scene) -> Option<SolveDisplay> {
    let unknowns = scene
        .fingers
        .iter()
        .map(|f| grasp_model::finger_unknowns(scene, f))
        .fold(0u64, u64::saturating_add);
    let largest = scene
        .fingers
        .iter()
        .map(|f| f.patch.grid)
        .max_by_key(|g| g[0].saturating_mul(g[1]))?;
    SolveDisplay::start(usize::try_from(unknowns).unwrap_or(usize::MAX), largest)
}

/// The sensitivities of `solution` (this solver's last answer) with their time, s; `None`
/// without forces.
fn sensitivities_of(
    solver: &mut GraspSolver,
    solution: &Solution,
) -> Result<Option<(Sensitivities, f64)>> {
    if !solution.status.has_forces() {
        return Ok(None);
    }
    let t = Instant::now();
    let sens = solver.sensitivities(solution)?;
    Ok(Some((sens, t.elapsed().as_secs_f64())))
}

/// What a solve at a later time answered: the time, and how many programs its history took
/// (or that the scene is elastic, so every time gives the same answer).
fn time_line(model: &GraspModel, timed: &TimedSolution) -> String {
    match model.is_viscoelastic() {
        true => format!(
            "viscoelastic: {} ({} stepped through the history)",
            timed.time,
            crate::report::count(timed.steps as u64, "program", "programs")
        ),
        false => format!(
            "the scene is elastic (no material has a relaxation law): {} is the \
             instantaneous response",
            timed.time
        ),
    }
}
