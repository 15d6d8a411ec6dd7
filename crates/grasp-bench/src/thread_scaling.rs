//! How a case's time scales with the cores: its runs on a one-thread pool and on a pool of
//! every core, alternated (a slow moment of the machine falls on both), medians compared.
//! The solver's parallel parts run on the pool they are called from, so the one-thread pool
//! is the serial program. The fine patches' rows in the table: each time, and the speed-up
//! against [`SCALING_TARGET`].

use grasp_model::SolverChoice;

use crate::case::{Case, Prepared};
use crate::error::BenchError;
use crate::sample::Sample;
use crate::statistics::median_and_range;
use crate::table::{speed_up_verdict, time, Row};

/// The fine patches timed on one thread and on every core (native solver).
pub const SCALING_CASES: [&str; 2] = ["hertz_512x512_fft", "hertz_1024x1024_fft"];

/// Every core (two on this project's machine) must make a fine patch at least this much faster
/// than one.
pub const SCALING_TARGET: f64 = 1.7;

/// A case timed on one thread and on every core.
#[derive(Debug, Clone)]
pub struct ThreadScaling {
    /// Cores of the machine (threads of the second pool).
    pub cores: usize,
    /// Median time on one thread, s.
    pub one_thread_s: f64,
    /// Median time on every core, s.
    pub all_cores_s: f64,
    /// Timed runs of each.
    pub runs: usize,
    /// The first run on every core (its iterations and memory).
    pub sample: Sample,
}

impl ThreadScaling {
    /// One thread's time over every core's: the speed-up.
    pub fn speed_up(&self) -> f64 {
        self.one_thread_s / self.all_cores_s
    }
}

fn pool(threads: usize, p: &Prepared) -> Result<rayon::ThreadPool, BenchError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| BenchError::Run {
            case: p.case.name.to_string(),
            message: format!("thread pool: {e}"),
        })
}

/// Times `p` on one thread and on every core, `rounds` alternating runs of each after one
/// untimed run of each (thread start-up, first-touch memory).
pub fn thread_scaling(p: &Prepared, rounds: usize) -> Result<ThreadScaling, BenchError> {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let (one, all) = (pool(1, p)?, pool(cores, p)?);
    let sample = all.install(|| p.run(true))?;
    one.install(|| p.run(false))?;
    let (mut t1, mut tn) = (Vec::new(), Vec::new());
    for _ in 0..rounds.max(1) {
        t1.push(one.install(|| p.run(false))?.time_s);
        tn.push(all.install(|| p.run(false))?.time_s);
    }
    let median = |v: &[f64]| median_and_range(v).map_or(f64::NAN, |m| m.0);
    Ok(ThreadScaling {
        cores,
        one_thread_s: median(&t1),
        all_cores_s: median(&tn),
        runs: t1.len(),
        sample,
    })
}

/// The rows of `case` (native solver) timed on one thread and on every core, `rounds` runs of
/// each: each median, and the speed-up against [`SCALING_TARGET`].
pub(crate) fn scaling_rows(case: &Case, rounds: usize) -> Result<Vec<Row>, BenchError> {
    let prepared = case.prepare(SolverChoice::Native)?;
    let t = thread_scaling(&prepared, rounds)?;
    let native = SolverChoice::Native.to_string();
    let mut rows = Vec::new();
    for (label, secs) in [
        ("1 thread".to_string(), t.one_thread_s),
        (format!("{} threads", t.cores), t.all_cores_s),
    ] {
        rows.push(Row {
            case: case.name.to_string(),
            timed: format!("build + solve, {label}"),
            solver: native.clone(),
            median: time(secs),
            runs: t.runs.to_string(),
            ..Row::default()
        });
    }
    rows.push(Row {
        case: format!("{} speed-up", case.name),
        timed: format!("{} cores / 1", t.cores),
        solver: native,
        median: format!("{:.2}x", t.speed_up()),
        target: speed_up_verdict(t.speed_up(), SCALING_TARGET),
        ..Row::default()
    });
    Ok(rows)
}
