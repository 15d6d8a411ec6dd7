//! `grasp bench`: the benchmark table's flags, checked and turned into a
//! `grasp_bench::BenchConfig` before any case runs. The run and its rows are
//! `grasp_bench::run_bench`'s; here its report is printed (with how to install the peer when it
//! was missing), and which case runs is said on standard error.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_bench::{BenchConfig, Peer};
use grasp_model::SolverChoice;

/// Benchmark table: the solver's cases (cube A grids, Hertz 41x41, both hand-offs warm
/// and cold, the whole transfer command) with each solver, medians against targets.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The smoke run: only the cases that take well under a second (1 to 3 timing runs each,
    /// until --min-time has passed), the whole transfer command once, and the batch
    /// throughput on 200 variants instead of 1,000.
    #[arg(long)]
    pub quick: bool,
    /// Print the table as Markdown.
    #[arg(long)]
    pub markdown: bool,
    /// Solvers to compare (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "native,clarabel",
        value_name = "auto|native|clarabel"
    )]
    pub solver: Vec<SolverChoice>,
    /// Run only these cases (comma-separated names from the table; `outputs`: the rows on
    /// writing a fine patch's solution as JSON and as `.npz`).
    #[arg(long = "case", value_delimiter = ',', value_name = "NAME")]
    pub cases: Vec<String>,
    /// Keep timing a case until this many seconds have passed (at least 2 runs, at most
    /// 50), in [0, 3600].
    #[arg(long, default_value_t = 1.0, value_name = "SECONDS")]
    pub min_time: f64,
    /// Python with the peer library (tamaas, installed by scripts/install-checkers.sh) that
    /// solves the Hertz FFT cases' grids beside ours (default: ~/.cache/grasp-venv/bin/python
    /// where it exists; without the peer the table says so and the bench goes on).
    #[arg(long, value_name = "PYTHON", conflicts_with = "no_peer")]
    pub peer: Option<PathBuf>,
    /// Do not run the peer on the Hertz FFT cases.
    #[arg(long)]
    pub no_peer: bool,
}

/// The reason of a bench run without the peer when asked so.
const NO_PEER: &str = "--no-peer";

/// The peer's Python in the project's virtualenv (scripts/install-checkers.sh).
const VENV_PYTHON: &str = ".cache/grasp-venv/bin/python";

/// Largest `--min-time`, s (50 runs cap a case anyway).
const MAX_MIN_TIME_S: f64 = 3600.0;

/// `grasp bench`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let config = config(args)?;
    let report = grasp_bench::run_bench(&config.bench, &progress)?;
    if std::io::stderr().is_terminal() {
        eprint!("\r{:<60}\r", "");
    }
    print!("{}", report.text(config.markdown));
    if let Some(reason) = &report.peer_absent {
        println!("{}", peer_missing_note(reason));
    }
    Ok(ExitCode::SUCCESS)
}

/// The flags, checked: what to run, and how to print it.
struct Config {
    /// What the bench runs.
    bench: BenchConfig,
    /// Print a Markdown table (for docs/benchmarks.md) instead of aligned text.
    markdown: bool,
}

/// The flags checked (before any case runs) and turned into the bench's configuration.
fn config(args: Args) -> Result<Config> {
    if !(0.0..=MAX_MIN_TIME_S).contains(&args.min_time) {
        bail!(
            "--min-time is {}; give a number of seconds in [0, {MAX_MIN_TIME_S}], e.g. 1",
            grasp_model::readable(args.min_time)
        );
    }
    for (i, s) in args.solver.iter().enumerate() {
        if args.solver[..i].contains(s) {
            bail!("--solver lists {s} twice; name each solver once, e.g. --solver native,clarabel");
        }
    }
    for (i, c) in args.cases.iter().enumerate() {
        if args.cases[..i].contains(c) {
            bail!("--case lists {c} twice; name each case once");
        }
    }
    let peer = peer_python(&args)?;
    let names = grasp_bench::case_names();
    if let Some(name) = args.cases.iter().find(|c| !names.contains(&c.as_str())) {
        bail!(
            "--case {name}: no such case; choose from {}",
            names.join(", ")
        );
    }
    let grasp = std::env::current_exe().context("locating the grasp executable")?;
    Ok(Config {
        bench: BenchConfig {
            quick: args.quick,
            solvers: args.solver,
            cases: args.cases,
            min_time_s: args.min_time,
            peer,
            grasp_executable: Some(grasp),
        },
        markdown: args.markdown,
    })
}

/// The Python that runs the peer: `--peer` (which must exist), else the virtualenv's where it
/// exists; [`Peer::Absent`] says why there is none (printed under the table).
fn peer_python(args: &Args) -> Result<Peer> {
    if args.no_peer {
        return Ok(Peer::Absent(NO_PEER.into()));
    }
    if let Some(p) = &args.peer {
        if !p.is_file() {
            bail!(
                "--peer {}: no such file; give a Python with tamaas, e.g. {}",
                p.display(),
                Path::new("~").join(VENV_PYTHON).display()
            );
        }
        return Ok(Peer::Python(p.clone()));
    }
    let home = std::env::var_os("HOME").map(PathBuf::from);
    Ok(match home.map(|h| h.join(VENV_PYTHON)) {
        Some(p) if p.is_file() => Peer::Python(p),
        Some(p) => Peer::Absent(format!("no Python at {}", p.display())),
        None => Peer::Absent("HOME is not set".into()),
    })
}

/// The line under the table when the peer was not measured: why, and how to install it
/// (unless the reason says so already, or `--no-peer` was given).
fn peer_missing_note(reason: &str) -> String {
    if reason == NO_PEER || reason.contains("scripts/install-checkers.sh") {
        return format!("peer not measured ({reason})");
    }
    format!(
        "peer not measured ({reason}); install it with `bash scripts/install-checkers.sh` \
         (tamaas into ~/.cache/grasp-venv) or give --peer <PYTHON>"
    )
}

/// Says which case runs now on standard error: on a terminal one line rewritten in place
/// (carriage returns), elsewhere (a file, a pipe, CI logs) one plain line per case.
fn progress(what: &str) {
    if std::io::stderr().is_terminal() {
        eprint!("\r{what:<60}");
    } else {
        eprintln!("{what}");
    }
}
