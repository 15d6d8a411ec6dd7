//! One run of the benchmark table (`grasp bench`): the chosen cases, each measured with every
//! solver in table order (the peer beside the Hertz FFT cases, the fine patches also on one
//! thread and on every core), then the rows derived from them, the whole `grasp transfer`
//! command, the batch throughput and the cost of writing a fine patch's solution; the report
//! with the notes for under the table. It says which case runs through a callback and prints
//! nothing.

use std::path::PathBuf;

use grasp_model::SolverChoice;

use crate::batch_throughput::batch_throughput_rows;
use crate::case::{all_cases, Case, PEER_CASES};
use crate::derived_rows::{derived_rows, fine_limit_rows};
use crate::error::BenchError;
use crate::measurement::{measure, Measured, TimingRuns};
use crate::output_writing::{output_rows, OUTPUTS_CASE};
use crate::peer::Peer;
use crate::peer_rows::peer_case;
use crate::table::{render, Row, LEGEND};
use crate::tactile_dataset_rows::{tactile_dataset_rows, TACTILE_DATASET_CASE};
use crate::thread_scaling::{scaling_rows, SCALING_CASES};
use crate::whole_command::whole_command_row;

/// What a run measures and how long.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchConfig {
    /// The smoke run: only the quick cases, 1 to 3 timing runs each, the whole command once,
    /// 200 batch variants, a 256 x 256 patch's outputs.
    pub quick: bool,
    /// Solvers, each measured on every case it can run (Clarabel skips
    /// [`Case::native_only`] ones).
    pub solvers: Vec<SolverChoice>,
    /// Names of the cases to run ([`case_names`]), all when empty (which adds the whole
    /// command and the batch throughput); a name that is no case selects nothing.
    pub cases: Vec<String>,
    /// Timing runs of a case continue until this much time has passed, s (at least 2 runs, at
    /// most 50; 1 to 3 when quick); above 0 the fine patches get 3 rounds on each pool, else 1.
    pub min_time_s: f64,
    /// The peer beside the Hertz FFT cases, or why there is none.
    pub peer: Peer,
    /// The `grasp` executable whose whole `transfer` command is timed; `None` leaves those rows
    /// out.
    pub grasp_executable: Option<PathBuf>,
}

/// The outcome of a run: the table's rows and what to say under it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BenchReport {
    /// The rows, in table order.
    pub rows: Vec<Row>,
    /// Notes under the legend: the peer's checks on each case it solved, or why it failed.
    pub notes: Vec<String>,
    /// Why the peer was not measured, when a peer case was run without it (the caller says
    /// how to install it).
    pub peer_absent: Option<String>,
}

impl BenchReport {
    /// The table (aligned text or Markdown), a blank line, the legend, and the notes, a line
    /// each.
    pub fn text(&self, markdown: bool) -> String {
        let mut out = render(&self.rows, markdown);
        out.push('\n');
        out.push_str(LEGEND);
        out.push('\n');
        for note in &self.notes {
            out.push_str(note);
            out.push('\n');
        }
        out
    }
}

/// Every name [`BenchConfig::cases`] takes: the cases in table order, then
/// [`OUTPUTS_CASE`] and [`TACTILE_DATASET_CASE`].
pub fn case_names() -> Vec<&'static str> {
    all_cases()
        .map(|c| c.name)
        .chain([OUTPUTS_CASE, TACTILE_DATASET_CASE])
        .collect()
}

/// Runs the bench of `config`; `progress` is told what runs now (`bench: cube_a_5x5 (native)`).
pub fn run_bench(config: &BenchConfig, progress: &dyn Fn(&str)) -> Result<BenchReport, BenchError> {
    let chosen: Vec<&Case> = all_cases()
        .filter(|c| config.cases.is_empty() || config.cases.iter().any(|n| n == c.name))
        .filter(|c| !config.quick || c.quick || !config.cases.is_empty())
        .collect();
    let mut report = BenchReport::default();
    let mut peer = config.peer.clone();
    let mut measured = Vec::new();
    for case in &chosen {
        let start = measured.len();
        let rows = measure_case(case, config, &mut measured, progress)?;
        report.rows.extend(rows);
        if PEER_CASES.contains(&case.name) {
            let rows = peer_case(&measured[start..], &mut peer, &mut report.notes, progress);
            report.rows.extend(rows);
        }
        if SCALING_CASES.contains(&case.name) && config.solvers.contains(&SolverChoice::Native) {
            progress(&format!(
                "bench: {} on 1 thread and on every core",
                case.name
            ));
            let rounds = if config.min_time_s > 0.0 { 3 } else { 1 };
            report.rows.extend(scaling_rows(case, rounds)?);
        }
    }
    report.rows.extend(fine_limit_rows(&measured));
    if let Peer::Absent(reason) = &peer {
        if chosen.iter().any(|c| PEER_CASES.contains(&c.name)) {
            report.peer_absent = Some(reason.clone());
        }
    }
    report.rows.extend(derived_rows(&measured, &config.solvers));
    report.rows.extend(rows_beyond_the_cases(config, progress)?);
    Ok(report)
}

/// Measures `case` with each solver that can run it, adding the measurements to `measured`;
/// their rows.
fn measure_case(
    case: &Case,
    config: &BenchConfig,
    measured: &mut Vec<Measured>,
    progress: &dyn Fn(&str),
) -> Result<Vec<Row>, BenchError> {
    let timing = match config.quick {
        true => TimingRuns {
            least: 1,
            most: 3,
            min_time_s: config.min_time_s,
        },
        false => TimingRuns {
            least: 2,
            most: 50,
            min_time_s: config.min_time_s,
        },
    };
    let mut rows = Vec::new();
    for &solver in &config.solvers {
        if solver == SolverChoice::Clarabel && case.native_only() {
            continue;
        }
        progress(&format!("bench: {} ({solver})", case.name));
        let m = measure(case, solver, timing)?;
        rows.push(m.row());
        measured.push(m);
    }
    Ok(rows)
}

/// The rows of a whole run beyond the cases (the whole command and the batch throughput per
/// solver), and the output writing's when it is asked for or the run is whole.
fn rows_beyond_the_cases(
    config: &BenchConfig,
    progress: &dyn Fn(&str),
) -> Result<Vec<Row>, BenchError> {
    let mut rows = Vec::new();
    if config.cases.is_empty() {
        for &solver in &config.solvers {
            if let Some(grasp) = &config.grasp_executable {
                progress(&format!("bench: whole transfer command ({solver})"));
                rows.push(whole_command_row(grasp, solver, config.quick)?);
            }
            progress(&format!("bench: batch throughput ({solver})"));
            rows.extend(batch_throughput_rows(solver, config.quick)?);
        }
    }
    if config.cases.is_empty() || config.cases.iter().any(|c| c == OUTPUTS_CASE) {
        progress(&format!("bench: {OUTPUTS_CASE}"));
        rows.extend(output_rows(config.quick)?);
    }
    if config.cases.is_empty() || config.cases.iter().any(|c| c == TACTILE_DATASET_CASE) {
        for &solver in &config.solvers {
            progress(&format!("bench: {TACTILE_DATASET_CASE} ({solver})"));
            rows.extend(tactile_dataset_rows(solver, config.quick)?);
        }
    }
    Ok(rows)
}
