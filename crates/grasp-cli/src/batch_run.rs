//! `grasp batch` and `grasp sweep`: many scenes, one result line each ([`grasp_batch`]), with a
//! progress bar, resume, shards and merge.

use std::collections::HashSet;
use std::fs::OpenOptions;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_batch::sweep::{expand, Axis};
use grasp_batch::{run_batch, BatchInput, BatchOptions, BatchSummary, ResultLine, Shard};
use grasp_model::{SolveOptions, SolverChoice};
use indicatif::{ProgressBar, ProgressStyle};

use crate::{limits, output};

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
pub fn run(input: &BatchInput, input_path: Option<&Path>, flags: &Flags) -> Result<ExitCode> {
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
pub fn merge(shards: &[PathBuf], out: &Path, force: bool) -> Result<ExitCode> {
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

/// `grasp sweep SCENE --vary ... --out F`: the variants as JSONL, or (`run`) their results.
pub fn sweep(scene_path: &Path, vary: &[String], run_it: bool, flags: &Flags) -> Result<ExitCode> {
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
    let lines: Vec<String> = expand(&scene, &stem, &axes)?
        .into_iter()
        .map(|(id, vary, scene)| {
            serde_json::json!({"id": id, "vary": vary, "scene": scene}).to_string()
        })
        .collect();
    if run_it {
        return run(&BatchInput::Lines(lines), Some(scene_path), flags);
    }
    output::check_targets(&[&flags.out], &[scene_path], flags.force)?;
    let mut body = lines.join("\n");
    body.push('\n');
    output::write_new(&flags.out, body.as_bytes(), flags.force)?;
    println!("{} variants; wrote {}", lines.len(), flags.out.display());
    Ok(ExitCode::SUCCESS)
}
