//! `grasp sweep`: a grid of variants of one scene, written as JSONL for `grasp batch` or run
//! at once.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::{bail, Result};
use grasp_batch::BatchInput;
use grasp_batch::{Axis, Sweep};

use crate::commands::batch::{run, Flags};
use crate::limits;
use crate::output::{self, ForceArg};
use crate::solve_flags::SolveFlags;

/// Expand a grid of variants of one scene (`--vary PATH=START:END:COUNT` or
/// `PATH=V1,V2,...`, e.g. `fingers[*].friction.mu=0.2:1.0:9`) into JSONL for `batch`, or
/// run them (`--run`).
#[derive(clap::Args, Debug)]
#[command(mut_arg("force", |a| a.help(crate::output::FORCE_OUT_HELP)))]
pub struct Args {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// One axis of the grid (repeat; the last varies fastest).
    #[arg(long = "vary", value_name = "PATH=RANGE", required = true)]
    pub vary: Vec<String>,
    /// The variants (JSONL), or with --run their results.
    #[arg(long, value_name = "OUT.jsonl")]
    pub out: PathBuf,
    /// Solve the variants now (as `grasp batch` would) and write their results.
    #[arg(long)]
    pub run: bool,
    /// Worker threads for --run, at most 256 (default, or 0: one per core).
    #[arg(long, value_name = "J", value_parser = crate::commands::batch::jobs_in_range)]
    pub jobs: Option<usize>,
    /// With --run, also write a tactile dataset (NumPy .npz) of the variants whose scene has a
    /// sensor: their sensor arrays and labels under `g<index>/` (as `grasp batch --npz`).
    #[arg(long, value_name = "DATASET.npz", requires = "run")]
    pub npz: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// `grasp sweep`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let flags = Flags {
        out: args.out,
        resume: false,
        force: args.force.force,
        shard: None,
        jobs: args.jobs,
        solve: args.solve,
        npz: args.npz,
    };
    sweep(&args.scene, &args.vary, args.run, &flags)
}

/// `grasp sweep SCENE --vary ... --out F`: the variants as JSONL, or (`run`) their results;
/// the variants are made one at a time (a million need no more memory than one).
fn sweep(scene_path: &Path, vary: &[String], run_it: bool, flags: &Flags) -> Result<ExitCode> {
    // The base scene must be valid itself; its variants are checked line by line.
    crate::load_scene::load_scene(scene_path)?;
    let text = limits::read_input(scene_path, "scene file")?;
    let scene: serde_json::Value = serde_json::from_str(&text)?;
    let axes: Vec<Axis> = vary
        .iter()
        .map(|v| Axis::parse(v))
        .collect::<Result<_, _>>()?;
    if axes.is_empty() {
        bail!("--vary: give at least one, e.g. --vary 'fingers[*].friction.mu=0.2:1.0:9'");
    }
    let stem = scene_path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let sweep = Arc::new(Sweep::new(scene, &stem, &axes)?);
    if run_it {
        let input = BatchInput::Sweep {
            sweep,
            base: grasp_io::base_dir_of(scene_path),
        };
        return run(&input, Some(scene_path), flags);
    }
    let outs = output::claim(&[&flags.out], &[scene_path], flags.force)?;
    let pending = outs.create(&flags.out)?;
    let mut w = BufWriter::new(pending.file_handle()?);
    for k in 0..sweep.len() {
        writeln!(w, "{}", sweep.line(k)?)?;
    }
    w.flush()?;
    drop(w);
    outs.commit(vec![pending])?;
    println!(
        "{}; wrote {}",
        crate::report::count(sweep.len() as u64, "variant", "variants"),
        flags.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
