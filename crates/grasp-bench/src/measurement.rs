//! A case measured with one solver: one run for its peak memory, then timing runs until a
//! minimum time has passed (within a least and a most number of runs); the median and range of
//! their times, and the case's row of the table.

use std::time::Instant;

use grasp_model::SolverChoice;

use crate::case::Case;
use crate::error::BenchError;
use crate::sample::Sample;
use crate::statistics::median_and_range;
use crate::table::{mib, time, verdict, Row};

/// How many timing runs a case gets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TimingRuns {
    /// Runs made whatever the time.
    pub least: usize,
    /// Runs never exceeded.
    pub most: usize,
    /// Runs continue (up to `most`) until this much time has passed since the first, s.
    pub min_time_s: f64,
}

/// Median, range and the first (memory) sample of one case with one solver.
pub(crate) struct Measured {
    /// The case.
    pub case: Case,
    /// The solver asked for.
    pub solver: SolverChoice,
    /// Median time of the timing runs, s.
    pub median_s: f64,
    /// Fastest timing run, s.
    pub min_s: f64,
    /// Slowest timing run, s.
    pub max_s: f64,
    /// Median time of the solves alone, s.
    pub median_solve_s: f64,
    /// Timing runs.
    pub runs: usize,
    /// The untimed first run (its memory, iterations and error).
    pub first: Sample,
}

/// Measures `case` with `solver`: one run with its memory, then the timing runs.
pub(crate) fn measure(
    case: &Case,
    solver: SolverChoice,
    timing: TimingRuns,
) -> Result<Measured, BenchError> {
    let prepared = case.prepare(solver)?;
    let first = prepared.run(true)?;
    let start = Instant::now();
    let mut runs: Vec<Sample> = Vec::new();
    while runs.len() < timing.least
        || (runs.len() < timing.most && start.elapsed().as_secs_f64() < timing.min_time_s)
    {
        runs.push(prepared.run(false)?);
    }
    let no_timing = || BenchError::Run {
        case: case.name.to_string(),
        message: "no finite timing".into(),
    };
    let times: Vec<f64> = runs.iter().map(|s| s.time_s).collect();
    let solves: Vec<f64> = runs.iter().map(|s| s.solve_s).collect();
    let (median_s, min_s, max_s) = median_and_range(&times).ok_or_else(no_timing)?;
    let (median_solve_s, _, _) = median_and_range(&solves).ok_or_else(no_timing)?;
    Ok(Measured {
        case: *case,
        solver,
        median_s,
        min_s,
        max_s,
        median_solve_s,
        runs: runs.len(),
        first,
    })
}

/// The measurement of the case named `name` with `solver`, if it was measured.
pub(crate) fn find<'a>(
    all: &'a [Measured],
    name: &str,
    solver: SolverChoice,
) -> Option<&'a Measured> {
    all.iter()
        .find(|m| m.case.name == name && m.solver == solver)
}

impl Measured {
    /// The case's row: its times, runs, the first run's unknowns, iterations, factorisations,
    /// memory and error, and its target.
    pub(crate) fn row(&self) -> Row {
        let s = &self.first;
        let solver = match s.fallbacks {
            0 => self.solver.to_string(),
            n => format!("{} ({n} fallbacks)", self.solver),
        };
        let iterations = match s.inner_iterations > 0.0 {
            true => format!("{:.2} ({:.0} CG)", s.iterations, s.inner_iterations),
            false => format!("{:.2}", s.iterations),
        };
        Row {
            case: self.case.name.to_string(),
            timed: self.case.kind.timed().to_string(),
            solver,
            median: time(self.median_s),
            range: format!("{}-{}", time(self.min_s), time(self.max_s)),
            runs: self.runs.to_string(),
            unknowns: s.unknowns.to_string(),
            iterations,
            factorizations: format!("{:.2}", s.factorizations),
            peak_mib: mib(s.peak_memory_bytes),
            error: format!("{:.1e}", s.error),
            target: self
                .case
                .target
                .map_or("-".into(), |t| verdict(self.median_s, t.limit_s, time)),
        }
    }
}
