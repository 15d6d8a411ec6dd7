//! `grasp plot`: the force diagram of one solve, as SVG or PNG.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use grasp_model::{
    ComplianceChoice, GraspModel, GraspSolver, SolveOptions, SolverChoice, StepInputs,
};

use crate::limits::MemoryArg;
use crate::load_scene::load_scene;
use crate::output::{self, ForceArg};
use crate::pictures::{force_diagram, picture};

/// Force diagram of one solve (SVG or PNG): two orthographic views with the object's
/// outline, each finger's normal and friction force, its friction cone, and the weight.
#[derive(clap::Args, Debug)]
#[command(mut_arg("force", |a| a.help(crate::output::FORCE_OUT_HELP)))]
pub struct Args {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// The picture to write: .svg or .png (by the extension).
    #[arg(long, value_name = "F.svg|F.png")]
    pub out: PathBuf,
    #[command(flatten)]
    pub force: ForceArg,
    /// Solver: `auto`, `native` or `clarabel`.
    // Not `SolveFlags`: a plot takes the automatic compliance (no `--compliance`).
    #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
    pub solver: SolverChoice,
    #[command(flatten)]
    pub memory: MemoryArg,
}

/// `grasp plot`.
pub fn execute(args: Args) -> Result<ExitCode> {
    plot_command(
        &args.scene,
        &args.out,
        args.force.force,
        args.solver,
        args.memory,
    )
}

/// `grasp plot`: solves the scene and writes its force diagram.
fn plot_command(
    scene_path: &Path,
    out: &Path,
    force: bool,
    solver: SolverChoice,
    memory: MemoryArg,
) -> Result<ExitCode> {
    let format = picture::Format::of(out, "--out")?;
    let outs = output::claim(&[out], &[scene_path], force)?;
    let scene = load_scene(scene_path)?;
    memory.check(&scene, scene_path, ComplianceChoice::Auto)?;
    let model = GraspModel::from_loaded(&scene)
        .with_context(|| format!("{} is not a usable scene", scene_path.display()))?;
    let options = SolveOptions {
        solver,
        ..SolveOptions::default()
    };
    let inputs = StepInputs::of_scene(&model);
    let model = std::sync::Arc::new(model);
    let mut solution = GraspSolver::new(std::sync::Arc::clone(&model), options).solve(&inputs)?;
    crate::flag_names::respell_solution(&mut solution);
    let title = scene_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let diagram = force_diagram::ForceDiagram {
        scene: &scene,
        model: &model,
        solution: &solution,
        title: &title,
    };
    outs.write(out, &picture::render(&diagram, format)?)?;
    println!(
        "{}: {}; wrote {}",
        title,
        solution.status.as_str(),
        out.display()
    );
    // The solve's warnings, as `grasp solve` prints them.
    for w in &solution.warnings {
        println!("warning: {w}");
    }
    Ok(if solution.status.has_forces() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}
