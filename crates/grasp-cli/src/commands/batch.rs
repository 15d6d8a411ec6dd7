//! `grasp batch`: many scenes, one result line each ([`grasp_batch`]), with a
//! progress bar, resume, shards and merge.

use std::collections::HashSet;
use std::fs::OpenOptions;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_batch::{run_batch, BatchInput, BatchOptions, BatchSummary, ResultLine, Shard};
use grasp_model::{SolveOptions, SolverChoice};
use indicatif::{ProgressBar, ProgressStyle};

use crate::limits::MemoryArg;
use crate::{limits, output};

/// Solve many scenes: one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare
/// scene) or one per file of a folder; one result line each, in input order, on all cores.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// JSONL file or folder of scene files (omit with --merge).
    pub input: Option<PathBuf>,
    /// Result lines (JSONL).
    #[arg(long, value_name = "RESULTS.jsonl")]
    pub out: PathBuf,
    /// Append to OUT, skipping the scenes whose id is already in it.
    #[arg(long)]
    pub resume: bool,
    /// Take every N-th scene from the I-th (0-based). Default: Slurm's
    /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT, or Kubernetes' JOB_COMPLETION_INDEX with
    /// GRASP_SHARD_COUNT, else everything.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Worker threads (default: one per core).
    #[arg(long, value_name = "J")]
    pub jobs: Option<usize>,
    /// Join these shard outputs into OUT (checked complete) instead of solving.
    #[arg(long, num_args = 1.., value_name = "SHARD.jsonl", conflicts_with_all = ["input", "resume", "shard"])]
    pub merge: Vec<PathBuf>,
    /// Overwrite OUT if it exists.
    #[arg(long)]
    pub force: bool,
    /// Solver: `auto`, `native` or `clarabel`.
    #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
    pub solver: SolverChoice,
    #[command(flatten)]
    pub memory: MemoryArg,
}

/// `grasp batch`: a run, or with `--merge` the join of shard outputs.
pub fn execute(args: Args) -> Result<ExitCode> {
    if !args.merge.is_empty() {
        return merge(&args.merge, &args.out, args.force);
    }
    let Some(input) = args.input else {
        bail!("give a JSONL file or a folder of scenes (or --merge SHARDS...)");
    };
    let flags = Flags {
        out: args.out,
        resume: args.resume,
        force: args.force,
        shard: args.shard,
        jobs: args.jobs,
        solver: args.solver,
        max_memory: args.memory.max_memory,
    };
    let source = BatchInput::open(&input)?;
    run(&source, Some(&input), &flags)
}

/// Flags of `grasp batch` (and of a sweep's run).
pub struct Flags {
    pub out: PathBuf,
    pub resume: bool,
    pub force: bool,
    pub shard: Option<String>,
    pub jobs: Option<usize>,
    pub solver: SolverChoice,
    pub max_memory: Option<u64>,
}

/// The shard: `--shard`, else the job array's environment, else all.
fn shard(flag: Option<&str>) -> Result<Shard> {
    Ok(match flag {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env(|k| std::env::var(k).ok())?.unwrap_or(Shard::ALL),
    })
}

/// The ids already in `out` (a resumed run), after cutting a last line left unfinished by an
/// interrupted run (the run's own partial write).
fn done_ids(out: &Path) -> Result<HashSet<String>> {
    let text = match std::fs::read_to_string(out) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(HashSet::new()),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", out.display())),
    };
    let complete = text.rfind('\n').map_or(0, |i| i + 1);
    if complete < text.len() {
        let f = OpenOptions::new().write(true).open(out)?;
        f.set_len(complete as u64)
            .with_context(|| format!("cannot cut the unfinished last line of {}", out.display()))?;
    }
    let mut ids = HashSet::new();
    for (n, line) in text[..complete].lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let r: ResultLine = serde_json::from_str(line).with_context(|| {
            format!(
                "{} line {} is not a result of grasp batch: --resume appends only to a batch's \
                 own output",
                out.display(),
                n + 1
            )
        })?;
        ids.insert(r.id);
    }
    Ok(ids)
}

/// Runs a batch of `input` into `flags.out`.
pub(crate) fn run(
    input: &BatchInput,
    input_path: Option<&Path>,
    flags: &Flags,
) -> Result<ExitCode> {
    let inputs: Vec<&Path> = input_path.into_iter().collect();
    // --resume appends to the output: it may exist (but may not be a folder, a link, an input).
    output::check_targets(&[&flags.out], &inputs, flags.force || flags.resume)?;
    let shard = shard(flags.shard.as_deref())?;
    let done = if flags.resume {
        done_ids(&flags.out)?
    } else {
        HashSet::new()
    };
    let file = if flags.resume {
        OpenOptions::new()
            .create(true)
            .append(true)
            .open(&flags.out)
    } else {
        OpenOptions::new()
            .create(true)
            .write(true)
            .truncate(true)
            .open(&flags.out)
    }
    .with_context(|| format!("cannot write {}", flags.out.display()))?;
    let (limit, _) = limits::memory_limit(flags.max_memory);
    let options = BatchOptions {
        solve: SolveOptions {
            solver: flags.solver,
            ..SolveOptions::default()
        },
        threads: flags.jobs.unwrap_or(0),
        shard,
        max_memory_bytes: limit,
        ..BatchOptions::default()
    };
    let scenes = input.for_each(&|_| false, &mut |_| Ok(()))?;
    let in_shard = (0..scenes).filter(|&i| shard.takes(i)).count();
    let bar = ProgressBar::new(in_shard.saturating_sub(done.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} scenes ({elapsed}, eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut w = BufWriter::new(file);
    let summary = run_batch(input, &done, &options, (&mut w, &flags.out), &mut |n| {
        bar.set_position(n as u64)
    })?;
    w.flush()?;
    bar.finish_and_clear();
    print!(
        "{}",
        summary_text(&summary, shard, pool_threads(flags.jobs))
    );
    println!("wrote {}", flags.out.display());
    Ok(ExitCode::SUCCESS)
}

fn pool_threads(jobs: Option<usize>) -> usize {
    match jobs {
        Some(j) if j > 0 => j,
        _ => std::thread::available_parallelism().map_or(1, |n| n.get()),
    }
}

fn summary_text(s: &BatchSummary, shard: Shard, threads: usize) -> String {
    let mut o = format!(
        "batch: {} scenes in the input, {} in shard {}/{}",
        s.scenes, s.in_shard, shard.index, shard.count
    );
    if s.resumed > 0 {
        o.push_str(&format!(", {} already in the output (resumed)", s.resumed));
    }
    let n = s.solved + s.no_equilibrium + s.no_convergence + s.invalid;
    o.push_str(&format!(
        "\nresults: {n} lines: solved {}, no equilibrium {}, no convergence {}, invalid {}\n",
        s.solved, s.no_equilibrium, s.no_convergence, s.invalid
    ));
    o.push_str(&format!(
        "time: {:.3} s wall on {threads} threads ({:.1} scenes/s), {:.3} s of solves\n",
        s.wall_time_s,
        n as f64 / s.wall_time_s.max(1e-9),
        s.solve_time_s
    ));
    o
}

/// `grasp batch --merge SHARDS --out OUT`.
fn merge(shards: &[PathBuf], out: &Path, force: bool) -> Result<ExitCode> {
    let inputs: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    output::check_targets(&[out], &inputs, force)?;
    let lines = grasp_batch::merge::merge(shards)?;
    let mut text = String::new();
    for l in &lines {
        text.push_str(&serde_json::to_string(l)?);
        text.push('\n');
    }
    output::write_new(out, text.as_bytes(), force)?;
    println!(
        "merged {} shards: {} results, none missing; wrote {}",
        shards.len(),
        lines.len(),
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}
