//! `grasp batch`: many scenes, one result line each ([`grasp_batch`]), with a
//! progress bar, resume, shards and merge.

use std::collections::HashSet;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_batch::{
    read_batch_output, run_batch, BatchInput, BatchOptions, BatchSummary, Shard, TactileDataset,
};
use grasp_io::{FileIdentity, PendingOutput, RunInputs};

use crate::limits;
use crate::output::{self, ForceArg};
use crate::solve_flags::SolveFlags;

/// Solve many scenes: one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare
/// scene) or one per file of a folder; one result line each, in input order, on all cores.
#[derive(clap::Args, Debug)]
#[command(mut_arg("force", |a| a.help(crate::output::FORCE_OUT_HELP)))]
pub struct Args {
    /// JSONL file or folder of scene files (omit with --merge).
    pub input: Option<PathBuf>,
    /// Result lines (JSONL).
    #[arg(long, value_name = "RESULTS.jsonl")]
    pub out: PathBuf,
    /// Append to OUT, skipping the scenes already in it (OUT is checked whole first: it must
    /// be this input's batch output; nothing is changed otherwise).
    #[arg(long)]
    pub resume: bool,
    /// Take every N-th scene from the I-th (0-based). Default: Slurm's
    /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT, or Kubernetes' JOB_COMPLETION_INDEX with
    /// GRASP_SHARD_COUNT, else everything.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Worker threads, at most 256 (default, or 0: one per core). More threads than cores
    /// only add switching, and each holds one solve's memory.
    #[arg(long, value_name = "J", value_parser = jobs_in_range)]
    pub jobs: Option<usize>,
    /// Also write a tactile dataset (NumPy .npz): per grasp whose scene has a sensor, its
    /// sensor arrays and labels (forces, friction utilisation, stick fraction) under
    /// `g<index>/` (docs/guide/many-grasps.md). Not with --resume.
    #[arg(long, value_name = "DATASET.npz")]
    pub npz: Option<PathBuf>,
    /// Join these shard outputs into OUT (checked complete) instead of solving.
    #[arg(long, num_args = 1.., value_name = "SHARD.jsonl", conflicts_with_all = ["input", "resume", "shard"])]
    pub merge: Vec<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// `grasp batch`: a run, or with `--merge` the join of shard outputs.
pub fn execute(args: Args) -> Result<ExitCode> {
    if !args.merge.is_empty() {
        return merge(&args.merge, &args.out, args.force.force);
    }
    let Some(input) = args.input else {
        bail!("give a JSONL file or a folder of scenes (or --merge SHARDS...)");
    };
    let flags = Flags {
        out: args.out,
        resume: args.resume,
        force: args.force.force,
        shard: args.shard,
        jobs: args.jobs,
        solve: args.solve,
        npz: args.npz,
    };
    let source = BatchInput::open(&input)?;
    run(&source, Some(&input), &flags)
}

/// `--jobs`: a whole number from 0 (one per core) to [`grasp_batch::MAX_THREADS`] (clap
/// names the flag in its error).
pub fn jobs_in_range(text: &str) -> Result<usize, String> {
    let max = grasp_batch::MAX_THREADS;
    match text.trim().parse::<usize>() {
        Ok(j) if j <= max => Ok(j),
        _ => Err(format!(
            "`{text}` is not a thread count from 0 (one per core) to {max}; more threads than \
             cores only add switching, and each holds one solve's memory"
        )),
    }
}

/// Flags of `grasp batch` (and of a sweep's run).
pub struct Flags {
    pub out: PathBuf,
    pub resume: bool,
    pub force: bool,
    pub shard: Option<String>,
    pub jobs: Option<usize>,
    pub solve: SolveFlags,
    /// The tactile dataset to write (`--npz`).
    pub npz: Option<PathBuf>,
}

/// The shard: `--shard`, else the job array's environment, else all.
fn shard(flag: Option<&str>) -> Result<Shard> {
    Ok(match flag {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env(|k| std::env::var(k).ok())?.unwrap_or(Shard::ALL),
    })
}

/// Where the result lines go: a temporary file moved into place on success, or (`--resume`)
/// the output itself, appended to after the check of what it holds.
enum Sink {
    Fresh(PendingOutput),
    Append(File),
}

/// Runs a batch of `input` into `flags.out`.
pub(crate) fn run(
    input: &BatchInput,
    input_path: Option<&Path>,
    flags: &Flags,
) -> Result<ExitCode> {
    let named: Vec<&Path> = input_path.into_iter().collect();
    limits::note_inputs(&input.files());
    if flags.resume && flags.npz.is_some() {
        bail!("--npz with --resume: a dataset is written whole; run without --resume (a new OUT), or drop --npz");
    }
    let mut targets = vec![flags.out.as_path()];
    targets.extend(flags.npz.as_deref());
    // --resume appends to the output: it may exist (but may not be a folder, a link, an input).
    let outs = output::claim(&targets, &named, flags.force || flags.resume)?;
    let shard = shard(flags.shard.as_deref())?;
    let index = input.index()?;
    let (done, sink) = if flags.resume {
        let point = read_batch_output(&flags.out, &index, shard)?;
        let file = outs.open_append(&flags.out)?;
        if point
            .identity
            .is_some_and(|id| Some(id) != identity_of(&file))
        {
            bail!(
                "{} changed while it was checked; run again",
                flags.out.display()
            );
        }
        if let Some(cut) = point.cut_at {
            // The unfinished last line of an interrupted run (checked to be one).
            file.set_len(cut).with_context(|| {
                format!(
                    "cannot cut the unfinished last line of {}",
                    flags.out.display()
                )
            })?;
        }
        (point.done, Sink::Append(file))
    } else {
        (HashSet::new(), Sink::Fresh(outs.create(&flags.out)?))
    };
    let options = BatchOptions {
        solve: flags.solve.options(),
        threads: flags.jobs.unwrap_or(0),
        shard,
        max_memory: flags.solve.memory.limit(),
        ..BatchOptions::default()
    };
    let in_shard = (0..index.scenes).filter(|&i| shard.takes(i)).count();
    let bar = crate::progress::bar(in_shard.saturating_sub(done.len()), "scenes");
    let file = match &sink {
        Sink::Fresh(p) => p.file_handle()?,
        Sink::Append(f) => f.try_clone()?,
    };
    let mut w = BufWriter::new(file);
    let mut dataset = Dataset::open(&outs, flags.npz.as_deref())?;
    let summary = run_batch(
        input,
        &index,
        &done,
        &options,
        &mut w,
        &flags.out,
        &mut |n, line| {
            bar.set_position(n as u64);
            dataset.add(line)
        },
    )?;
    w.flush()?;
    drop(w);
    bar.finish_and_clear();
    limits::note_inputs(&summary.inputs);
    let written = dataset.finish()?;
    match sink {
        Sink::Fresh(p) => outs.commit([p].into_iter().chain(written).collect())?,
        Sink::Append(f) => f.sync_all()?,
    }
    print!(
        "{}",
        summary_text(&summary, shard, pool_threads(flags.jobs))
    );
    println!("wrote {}", flags.out.display());
    if let Some(npz) = &flags.npz {
        println!("wrote {} (tactile dataset)", npz.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The tactile dataset being written (`--npz`), or nothing.
struct Dataset {
    target: Option<(PathBuf, PendingOutput, TactileDataset<BufWriter<File>>)>,
}

impl Dataset {
    /// The dataset of `npz`, its file claimed in `outs`.
    fn open(outs: &output::Outputs, npz: Option<&Path>) -> Result<Dataset> {
        let Some(path) = npz else {
            return Ok(Dataset { target: None });
        };
        let pending = outs.create(path)?;
        let file = pending.file_handle()?;
        let dataset = TactileDataset::new(BufWriter::with_capacity(1 << 20, file));
        Ok(Dataset {
            target: Some((path.to_path_buf(), pending, dataset)),
        })
    }

    /// Adds one result line's grasp.
    fn add(&mut self, line: &grasp_batch::ResultLine) -> Result<(), grasp_batch::BatchError> {
        match &mut self.target {
            Some((path, _, d)) => d.add(line).map_err(|e| grasp_batch::BatchError::Io {
                path: path.clone(),
                message: e.to_string(),
            }),
            None => Ok(()),
        }
    }

    /// Completes the archive; its pending output, to commit with the result lines.
    fn finish(self) -> Result<Option<PendingOutput>> {
        let Some((path, pending, d)) = self.target else {
            return Ok(None);
        };
        let mut w = d
            .finish()
            .with_context(|| format!("writing {}", path.display()))?;
        w.flush()?;
        Ok(Some(pending))
    }
}

/// The identity of an open file.
fn identity_of(file: &File) -> Option<FileIdentity> {
    file.metadata().ok().map(|m| FileIdentity::of(&m))
}

fn pool_threads(jobs: Option<usize>) -> usize {
    match jobs {
        Some(j) if j > 0 => j,
        _ => std::thread::available_parallelism().map_or(1, |n| n.get()),
    }
}

fn summary_text(s: &BatchSummary, shard: Shard, threads: usize) -> String {
    use crate::report::count;
    let mut o = format!(
        "batch: {} in the input, {} in shard {}/{}",
        count(s.scenes as u64, "scene", "scenes"),
        s.in_shard,
        shard.index,
        shard.count
    );
    if s.resumed > 0 {
        o.push_str(&format!(", {} already in the output (resumed)", s.resumed));
    }
    let n = s.solved + s.no_equilibrium + s.no_convergence + s.invalid;
    o.push_str(&format!(
        "\nresults: {}: solved {}, no equilibrium {}, no convergence {}, invalid {}\n",
        count(n as u64, "line", "lines"),
        s.solved,
        s.no_equilibrium,
        s.no_convergence,
        s.invalid
    ));
    o.push_str(&format!(
        "time: {:.3} s wall on {} ({:.1} scenes/s), {:.3} s of solves\n",
        s.wall_time_s,
        count(threads as u64, "thread", "threads"),
        n as f64 / s.wall_time_s.max(1e-9),
        s.solve_time_s
    ));
    o
}

/// `grasp batch --merge SHARDS --out OUT`.
fn merge(shards: &[PathBuf], out: &Path, force: bool) -> Result<ExitCode> {
    let inputs: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let outs = output::claim(&[out], &inputs, force)?;
    let pending = outs.create(out)?;
    let mut w = BufWriter::new(pending.file_handle()?);
    let summary = grasp_batch::merge(shards, &mut w, out)?;
    w.flush()?;
    drop(w);
    let mut read = RunInputs::new();
    shards.iter().for_each(|s| read.add_existing(s));
    limits::note_inputs(&read);
    outs.commit(vec![pending])?;
    println!(
        "merged {} shards: {} results, every scene exactly once; wrote {}",
        shards.len(),
        summary.lines,
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}
