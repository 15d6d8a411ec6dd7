//! Tactile dataset throughput: 10,000 variants of cube A (three 5 x 5 patches; 200 when quick),
//! each finger's pad with 4 x 4 taxels one pitch deep, run by `grasp batch`'s runner in this
//! process on every core with every output written: the result lines to a file and the
//! tactile dataset (`grasp_batch::TactileDataset`, the sensor arrays and labels of every grasp)
//! to an `.npz`, both in a scratch folder. The row: the median grasps per second over
//! [`DATASET_ROUNDS`] runs (after one untimed run), against [`DATASET_RATE_TARGET`].

use std::fs::File;
use std::io::{BufWriter, Write};
use std::time::Instant;

use grasp_batch::{BatchInput, BatchOptions, TactileDataset};
use grasp_model::{SolveOptions, SolverChoice};

use crate::batch_throughput::cube_a_variants;
use crate::error::BenchError;
use crate::scratch_folder::ScratchFolder;
use crate::table::Row;

/// The pseudo-case that selects the row (`grasp bench --case tactile_dataset`).
pub const TACTILE_DATASET_CASE: &str = "tactile_dataset";

/// Timed runs (after one untimed run).
const DATASET_ROUNDS: usize = 3;

/// Grasps per second the dataset must be written at, on every core.
const DATASET_RATE_TARGET: f64 = 2000.0;

/// The row of the tactile dataset's throughput with `solver`.
pub(crate) fn tactile_dataset_rows(
    solver: SolverChoice,
    quick: bool,
) -> Result<Vec<Row>, BenchError> {
    let lines = variants(quick)?;
    let n = lines.len();
    let input = BatchInput::Lines(lines);
    let scratch = ScratchFolder::create()?;
    let mut rates = Vec::new();
    for round in 0..=DATASET_ROUNDS {
        let rate = dataset_rate(&input, n, solver, &scratch)?;
        if round > 0 {
            rates.push(rate);
        }
    }
    rates.sort_by(f64::total_cmp);
    let median = rates[rates.len() / 2];
    let mark = if median >= DATASET_RATE_TARGET {
        "met"
    } else {
        "MISSED"
    };
    Ok(vec![Row {
        case: format!("tactile dataset cube A x{n}"),
        timed: "all cores, all outputs".into(),
        solver: solver.to_string(),
        median: format!("{median:.0} grasps/s"),
        range: format!("{:.0}-{:.0}", rates[0], rates[rates.len() - 1]),
        runs: rates.len().to_string(),
        target: format!(">= {DATASET_RATE_TARGET} grasps/s ({mark})"),
        ..Row::default()
    }])
}

/// Cube A with 4 x 4 taxels one pitch deep tiling each 5 x 5 patch's shorter side: 100
/// friction coefficients times 100 weights (10 x 20 when quick).
fn variants(quick: bool) -> Result<Vec<String>, BenchError> {
    let counts = if quick { [10, 20] } else { [100, 100] };
    cube_a_variants("tactile dataset", counts, &|scene| {
        let fingers = scene["fingers"].as_array_mut();
        for f in fingers.ok_or("cube_a has no fingers")? {
            let size = &f["patch"]["size"];
            let side = size[0]
                .as_f64()
                .unwrap_or(0.0)
                .min(size[1].as_f64().unwrap_or(0.0));
            let pitch = side / 4.0;
            f["sensor"] = serde_json::json!({"taxels": {"count": [4, 4], "pitch_m": pitch,
                                                        "size_m": pitch, "depth_m": pitch}});
        }
        Ok(())
    })
}

/// Grasps per second of one run writing the result lines and the dataset into `scratch`.
fn dataset_rate(
    input: &BatchInput,
    n: usize,
    solver: SolverChoice,
    scratch: &ScratchFolder,
) -> Result<f64, BenchError> {
    let io = |doing: &str, source: std::io::Error| BenchError::Io {
        doing: doing.to_string(),
        source,
    };
    let options = BatchOptions {
        solve: SolveOptions {
            solver,
            ..SolveOptions::default()
        },
        ..BatchOptions::default()
    };
    let (lines_path, npz_path) = (scratch.path().join("d.jsonl"), scratch.path().join("d.npz"));
    let t = Instant::now();
    let index = input.index()?;
    let mut out = BufWriter::new(File::create(&lines_path).map_err(|e| io("creating d.jsonl", e))?);
    let npz = File::create(&npz_path).map_err(|e| io("creating d.npz", e))?;
    let mut dataset = TactileDataset::new(BufWriter::with_capacity(1 << 20, npz));
    let s = grasp_batch::run_batch(
        input,
        &index,
        &Default::default(),
        &options,
        &mut out,
        &lines_path,
        &mut |_, line| {
            dataset.add(line).map_err(|e| grasp_batch::BatchError::Io {
                path: npz_path.clone(),
                message: e.to_string(),
            })
        },
    )?;
    out.flush().map_err(|e| io("writing d.jsonl", e))?;
    let mut w = dataset.finish().map_err(|e| io("writing d.npz", e))?;
    w.flush().map_err(|e| io("writing d.npz", e))?;
    let wall = t.elapsed().as_secs_f64();
    if s.solved != n {
        return Err(BenchError::BatchUnsolved {
            solved: s.solved,
            variants: n,
        });
    }
    Ok(n as f64 / wall)
}
