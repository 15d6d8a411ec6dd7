//! Running a batch: the scenes of one shard, a chunk at a time, each chunk solved in parallel
//! on a pool of `threads` workers and written in input order (so the output is the same for any
//! number of threads, times apart), flushed after every chunk (a crashed run keeps what it
//! wrote and resumes from there).

use std::collections::HashSet;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use grasp_io::{MemoryLimit, RunInputs};

use grasp_model::{GraspModel, GraspSolver, SolveOptions, StepInputs};
use grasp_model::{InputProblem, ModelError, OutOfMemory};
use rayon::prelude::*;

use crate::memory_budget::MemoryBudget;

use crate::error::{io, BatchError};
use crate::input::{BatchInput, SceneLine, UnparsedScene};
use crate::input_index::InputIndex;
use crate::option_names;
use crate::result_line::{ResultLine, ResultStatus};
use crate::shard::Shard;

/// Options of a batch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchOptions {
    /// Options of each solve.
    pub solve: SolveOptions,
    /// Worker threads; 0: one per core.
    pub threads: usize,
    /// The part of the input this run takes.
    pub shard: Shard,
    /// Scenes whose memory estimate exceeds this limit are refused (an `invalid` line).
    pub max_memory: MemoryLimit,
    /// Scenes solved between two writes of the output.
    pub chunk: usize,
}

impl Default for BatchOptions {
    fn default() -> Self {
        BatchOptions {
            solve: SolveOptions::default(),
            threads: 0,
            shard: Shard::ALL,
            max_memory: MemoryLimit::given(u64::MAX),
            chunk: 256,
        }
    }
}

/// What a batch did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BatchSummary {
    /// Scenes in the whole input.
    pub scenes: usize,
    /// Scenes of this shard.
    pub in_shard: usize,
    /// Scenes of this shard skipped because they were already in the output.
    pub resumed: usize,
    /// Lines written, by outcome.
    pub solved: usize,
    /// See [`ResultStatus::NoEquilibrium`].
    pub no_equilibrium: usize,
    /// See [`ResultStatus::NoConvergence`].
    pub no_convergence: usize,
    /// See [`ResultStatus::Invalid`].
    pub invalid: usize,
    /// Sum of the scenes' solve times, s.
    pub solve_time_s: f64,
    /// Wall time of the run, s.
    pub wall_time_s: f64,
    /// The files the scenes read (a folder's scene files, mesh files).
    pub inputs: RunInputs,
}

impl BatchSummary {
    fn count(&mut self, line: &ResultLine) {
        match line.status {
            ResultStatus::Solved | ResultStatus::ReducedAccuracy => self.solved += 1,
            ResultStatus::NoEquilibrium => self.no_equilibrium += 1,
            ResultStatus::NoConvergence => self.no_convergence += 1,
            ResultStatus::Invalid => self.invalid += 1,
        }
        self.solve_time_s += line.time_s;
    }
}

/// Solves one scene into its line, once its memory estimate is admitted by `budget` (the
/// batch's limit shared by the scenes solved at once).
pub fn solve_line(
    line: SceneLine,
    of: usize,
    options: &BatchOptions,
    budget: &MemoryBudget,
) -> ResultLine {
    let SceneLine {
        index,
        id,
        vary,
        scene,
        files: _,
    } = line;
    let mut out = match scene {
        Err(p) => ResultLine::invalid(id, index, of, p),
        Ok(scene) => match options.max_memory.check(&scene, options.solve.compliance) {
            Err(e) => ResultLine::invalid(id, index, of, vec![e.problem()]),
            Ok(need) => {
                let _admitted = budget.admit(need);
                let clock = Instant::now();
                match GraspModel::from_validated_with(&scene, options.solve.compliance) {
                    Err(e) => ResultLine::invalid(id, index, of, e.problems()),
                    Ok(model) => {
                        let model = std::sync::Arc::new(model);
                        let inputs = StepInputs::of_scene(&model);
                        let shared = std::sync::Arc::clone(&model);
                        let mut solver = GraspSolver::new(shared, options.solve);
                        match solver.solve(&inputs) {
                            Ok(sol) => {
                                let t = clock.elapsed().as_secs_f64();
                                let mut l = ResultLine::of_solution(id, index, of, &sol, t);
                                match sensors_of(&scene, &model, &sol, index) {
                                    Ok(read) => {
                                        l.sensors = (!read.is_empty())
                                            .then(|| serde_json::to_value(&read).ok())
                                            .flatten();
                                        l.readings = read;
                                    }
                                    Err(why) => l.warnings.push(why),
                                }
                                l
                            }
                            // Too little memory for the solve: the scene fails, the batch
                            // goes on.
                            Err(ModelError::OutOfMemory(e)) => {
                                let p = InputProblem::new(".", e.message(), OutOfMemory::FIX);
                                ResultLine::invalid(id, index, of, vec![p])
                            }
                            Err(e) => {
                                let mut l = ResultLine::invalid(id, index, of, Vec::new());
                                l.status = ResultStatus::NoConvergence;
                                l.reason = Some(e.to_string());
                                l.time_s = clock.elapsed().as_secs_f64();
                                l
                            }
                        }
                    }
                }
            }
        },
    };
    out.vary = vary;
    out
}

/// The readings of the scene's sensors (empty when it has none or the solve found no forces),
/// the line's `index` the noise's draw (so that equal scenes on other lines draw other
/// noise); a read-out refused (too much work: its reason names the field and the fix) is a
/// warning of the line, which keeps its forces.
fn sensors_of(
    scene: &grasp_model::Scene,
    model: &GraspModel,
    sol: &grasp_model::Solution,
    index: usize,
) -> Result<Vec<grasp_model::SensorReadings>, String> {
    if !sol.status.has_forces() {
        return Ok(Vec::new());
    }
    grasp_model::sensor_readings_drawn(scene, model, sol, index as u64).map_err(|e| e.to_string())
}

/// Most worker threads a batch may have: more threads than cores only add switching, and each
/// worker holds one solve's memory (up to [`BatchOptions::max_memory`]), so a large
/// count multiplies the memory a batch can take; 256 covers the largest common machines.
pub const MAX_THREADS: usize = 256;

/// The pool of `threads` workers (0: one per core), at most [`MAX_THREADS`].
fn worker_pool(threads: usize) -> Result<rayon::ThreadPool, BatchError> {
    let usage = |message: String| BatchError::Usage {
        what: format!("`{}`", option_names::THREADS),
        message,
    };
    if threads > MAX_THREADS {
        return Err(usage(format!(
            "{threads} worker threads: give at most {MAX_THREADS} (more threads than cores \
             only add switching, and each holds a solve's memory)"
        )));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| usage(format!("cannot start the worker threads: {e}")))
}

/// A chunk of scenes parsed, solved and serialised on the workers: each line with its text
/// and the files read for it.
fn solve_chunk(
    pool: &rayon::ThreadPool,
    chunk: Vec<UnparsedScene>,
    of: usize,
    budget: &MemoryBudget,
    options: &BatchOptions,
    out_name: &Path,
) -> Result<Vec<(ResultLine, String, RunInputs)>, BatchError> {
    pool.install(|| {
        chunk
            .into_par_iter()
            .map(|u| {
                let mut line = u.parse();
                let files = std::mem::take(&mut line.files);
                let r = solve_line(line, of, options, budget);
                let text = serde_json::to_string(&r).map_err(|e| io(out_name, e))?;
                Ok((r, text, files))
            })
            .collect()
    })
}

/// Runs the shard of `input` given in `options` (its first pass `index`), skipping the
/// positions in `done` (a resumed run), writing one line per scene to `out` (named `out_name`
/// in errors) in input order; `each_line(n, line)` is given every line as it is written, with
/// the number written so far (progress; a tactile dataset's arrays: `crate::tactile_dataset`).
pub fn run_batch(
    input: &BatchInput,
    index: &InputIndex,
    done: &HashSet<usize>,
    options: &BatchOptions,
    out: &mut dyn Write,
    out_name: &Path,
    each_line: &mut dyn FnMut(usize, &ResultLine) -> Result<(), BatchError>,
) -> Result<BatchSummary, BatchError> {
    let clock = Instant::now();
    let pool = worker_pool(options.threads)?;
    let budget = MemoryBudget::new(options.max_memory.bytes);
    let of = index.scenes;
    let mut summary = BatchSummary {
        scenes: of,
        ..BatchSummary::default()
    };
    let chunk = options.chunk.max(1);
    let mut pending: Vec<UnparsedScene> = Vec::with_capacity(chunk);
    let mut written = 0;
    // Parsing, solving and writing each line's text run on the workers; only the ordered
    // writes stay on this thread.
    let mut flush = |pending: &mut Vec<UnparsedScene>, summary: &mut BatchSummary| {
        let lines = solve_chunk(
            &pool,
            std::mem::take(pending),
            of,
            &budget,
            options,
            out_name,
        )?;
        for (line, text, files) in &lines {
            summary.count(line);
            summary.inputs.extend(files);
            writeln!(out, "{text}").map_err(|e| io(out_name, e))?;
            written += 1;
            each_line(written, line)?;
        }
        out.flush().map_err(|e| io(out_name, e))?;
        Ok::<(), BatchError>(())
    };
    let seen = input.for_each_unparsed(&|i| options.shard.takes(i), &mut |u| {
        summary.in_shard += 1;
        if done.contains(&u.index()) {
            summary.resumed += 1;
            return Ok(());
        }
        pending.push(u);
        if pending.len() >= chunk {
            flush(&mut pending, &mut summary)?;
        }
        Ok(())
    })?;
    if !pending.is_empty() {
        flush(&mut pending, &mut summary)?;
    }
    if seen != of {
        return Err(BatchError::Usage {
            what: "input".into(),
            message: format!(
                "changed while the batch read it ({of} scenes at first, {seen} now); run again \
                 on an input that is not being written"
            ),
        });
    }
    summary.wall_time_s = clock.elapsed().as_secs_f64();
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use serde_json::{json, Value};

    use crate::{run_batch, BatchInput, BatchOptions};

    /// The box pinch with both pads 3 mm below the box's top edge: each 10 mm pad hangs 2 mm
    /// over it (a shape warning), and the grasp still holds.
    fn pinch_over_the_edge(z_m: f64) -> Value {
        let finger = |name: &str, y: f64, load: Option<f64>| {
            let mut f = json!({
                "name": name,
                "place": {"ray": {"origin": [0.0, y, z_m], "direction": [0.0, -y.signum(), 0.0]}},
                "material": {"youngs_modulus": 2e6, "poisson_ratio": 0.45},
                "patch": {"size": [0.01, 0.01], "grid": [5, 5]},
                "friction": {"mu": 0.8}
            });
            if let Some(p) = load {
                f["control"] = json!({"normal_load": p});
            }
            f
        };
        json!({
            "object": {
                "density": 700,
                "material": {"youngs_modulus": 1.1e10, "poisson_ratio": 0.3},
                "shape": {"box": {"size": [0.06, 0.04, 0.1]}, "position": [0, 0, 0.05]}
            },
            "fingers": [finger("left", 0.2, None), finger("right", -0.2, Some(10.0))],
            // The thesis's quadratic gap, blind to the edge, is what the warning is about.
            "gap": "quadratic"
        })
    }

    /// A batch line carries the scene's warnings (a pad over the box's edge, 2.000 mm for
    /// each finger, the text the shape check writes) whatever else it holds; a scene without
    /// warnings writes no `warnings` key.
    #[test]
    fn a_batch_line_carries_the_scenes_warnings() {
        let dir = std::env::temp_dir().join(format!("grasp-batch-warnings-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("in.jsonl");
        let lines = [pinch_over_the_edge(0.097), pinch_over_the_edge(0.055)]
            .map(|v| v.to_string())
            .join("\n");
        std::fs::write(&input, lines + "\n").unwrap();
        let mut out = Vec::new();
        let source = BatchInput::open(&input).unwrap();
        run_batch(
            &source,
            &source.index().unwrap(),
            &HashSet::new(),
            &BatchOptions::default(),
            &mut out,
            &dir.join("out.jsonl"),
            &mut |_, _| Ok(()),
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 2, "{text}");
        assert_eq!(lines[0]["status"], "solved", "{text}");
        let warnings: Vec<&str> = lines[0]["warnings"]
            .as_array()
            .unwrap_or_else(|| panic!("no warnings: {text}"))
            .iter()
            .map(|w| w.as_str().unwrap())
            .collect();
        for name in ["left", "right"] {
            assert!(
                warnings.iter().any(|w| w.starts_with(&format!(
                    "finger {name}: the patch hangs 2.000 mm over the edge"
                ))),
                "{warnings:?}"
            );
        }
        assert!(lines[1].get("warnings").is_none(), "{text}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
