//! Batch throughput: 1,000 variants of cube A (a grid of friction coefficients and weights;
//! 200 when quick) solved by `grasp batch`'s runner in this process, on one thread and on every
//! core, output discarded. Rows: the median scenes per second of each over [`BATCH_ROUNDS`]
//! alternating runs (after one untimed run of each), and the ratio of the medians against
//! [`BATCH_SPEED_UP_TARGET`].

use std::time::Instant;

use grasp_batch::{Axis, Sweep};
use grasp_batch::{BatchInput, BatchOptions};
use grasp_model::{SolveOptions, SolverChoice};

use crate::error::BenchError;
use crate::table::{speed_up_verdict, Row};

/// Timed runs of each thread count (after one untimed run).
const BATCH_ROUNDS: usize = 5;

/// Every core (two on this project's machine) must solve at least this many times the scenes
/// per second of one.
const BATCH_SPEED_UP_TARGET: f64 = 1.8;

/// The rows of the batch throughput with `solver`.
pub(crate) fn batch_throughput_rows(
    solver: SolverChoice,
    quick: bool,
) -> Result<Vec<Row>, BenchError> {
    let lines = variants(quick)?;
    let n = lines.len();
    let input = BatchInput::Lines(lines);
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    // One untimed run of each (thread pool, first-touch memory), then alternating timed runs:
    // a slow moment of the machine falls on both, and the median of each is reported.
    let configs = [1, cores];
    let mut samples: Vec<Vec<f64>> = vec![Vec::new(); configs.len()];
    for round in 0..=BATCH_ROUNDS {
        for (c, &threads) in configs.iter().enumerate() {
            let rate = batch_rate(&input, n, solver, threads)?;
            if round > 0 {
                samples[c].push(rate);
            }
        }
    }
    let mut rates = Vec::new();
    let mut rows = Vec::new();
    for (c, threads) in configs.into_iter().enumerate() {
        let mut v = samples[c].clone();
        v.sort_by(f64::total_cmp);
        let median = v[v.len() / 2];
        rates.push(median);
        rows.push(Row {
            case: format!("batch cube A x{n}"),
            timed: format!("{threads} thread(s)"),
            solver: solver.to_string(),
            median: format!("{median:.0} scenes/s"),
            range: format!("{:.0}-{:.0}", v[0], v[v.len() - 1]),
            runs: v.len().to_string(),
            ..Row::default()
        });
    }
    let speed_up = rates[1] / rates[0];
    rows.push(Row {
        case: "batch speed-up".into(),
        timed: format!("{cores} cores / 1"),
        solver: solver.to_string(),
        median: format!("{speed_up:.2}x"),
        target: speed_up_verdict(speed_up, BATCH_SPEED_UP_TARGET),
        ..Row::default()
    });
    Ok(rows)
}

/// The variants of cube A, one scene a line: 10 friction coefficients times 100 weights (20
/// when quick).
fn variants(quick: bool) -> Result<Vec<String>, BenchError> {
    let weights = if quick { 20 } else { 100 };
    cube_a_variants("batch cube A", [10, weights], &|_| Ok(()))
}

/// The variants of bundled cube A, one scene a line, after `edit` (named `case` in errors):
/// `counts[0]` friction coefficients from 0.4 to 1 times `counts[1]` weights from 1 to 10 N.
pub(crate) fn cube_a_variants(
    case: &str,
    counts: [usize; 2],
    edit: &dyn Fn(&mut serde_json::Value) -> Result<(), String>,
) -> Result<Vec<String>, BenchError> {
    let input_error = |message: String| BenchError::Input {
        case: case.into(),
        message,
    };
    let (scene, _) = crate::case::bundled("cube_a")
        .ok_or_else(|| input_error("no bundled scene cube_a".into()))?;
    let mut scene: serde_json::Value =
        serde_json::from_str(scene).map_err(|e| input_error(e.to_string()))?;
    edit(&mut scene).map_err(input_error)?;
    let axes = [
        Axis::parse(&format!("fingers[*].friction.mu=0.4:1.0:{}", counts[0]))?,
        Axis::parse(&format!("object.weight=1:10:{}", counts[1]))?,
    ];
    let sweep = Sweep::new(scene, "cube_a", &axes)?;
    let lines = (0..sweep.len()).map(|k| sweep.line(k));
    Ok(lines.collect::<Result<_, _>>()?)
}

/// Scenes per second of one in-process batch run of the `n` variants on `threads` threads
/// (output discarded).
fn batch_rate(
    input: &BatchInput,
    n: usize,
    solver: SolverChoice,
    threads: usize,
) -> Result<f64, BenchError> {
    let options = BatchOptions {
        solve: SolveOptions {
            solver,
            ..SolveOptions::default()
        },
        threads,
        ..BatchOptions::default()
    };
    let t = Instant::now();
    let index = input.index()?;
    let s = grasp_batch::run_batch(
        input,
        &index,
        &Default::default(),
        &options,
        &mut std::io::sink(),
        std::path::Path::new("(discarded)"),
        &mut |_, _| Ok(()),
    )?;
    let wall = t.elapsed().as_secs_f64();
    if s.solved != n {
        return Err(BenchError::BatchUnsolved {
            solved: s.solved,
            variants: n,
        });
    }
    Ok(n as f64 / wall)
}
