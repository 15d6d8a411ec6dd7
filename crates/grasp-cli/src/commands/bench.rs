//! `grasp bench`: the benchmark table, both solvers side by side. Each case runs
//! once to read its peak memory, then again until `--min-time` has passed (at least twice, at
//! most 50 times); the table gives the median and the range of those timing runs, against the
//! case's target. Derived rows: warm/cold iteration ratios of both hand-offs, the growth
//! exponent of solve time against unknowns over the cube A series, the whole `grasp
//! transfer` command with MCAP, Rerun and CSV outputs (a child process, timed from outside),
//! the batch runner's throughput on one thread and on every core, and the time to
//! write a fine patch's solution in each output format ([`outputs`]). Beside the
//! Hertz FFT cases, the peer library (tamaas, `scripts/peer-hertz.py`) solves the
//! same grid in the same run: a row with its time and error, and the ratio of its time to ours.

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use grasp_bench::{
    growth_exponent, median_and_range, Case, CaseKind, PeerError, PeerProblem, PeerRecord, Sample,
    CASES, FFT_CASES, HELD_CASES, LAYER_CASES, LAYER_PAIRS, MARGIN_PAIRS, PEER_CASES,
};
use grasp_model::SolverChoice;

mod outputs;

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

/// The Python that runs the peer: `--peer` (which must exist), else the virtualenv's where it
/// exists; `Err` is the reason there is none (printed under the table).
fn peer_python(args: &Args) -> Result<Result<PathBuf, String>> {
    if args.no_peer {
        return Ok(Err(NO_PEER.into()));
    }
    if let Some(p) = &args.peer {
        if !p.is_file() {
            bail!(
                "--peer {}: no such file; give a Python with tamaas, e.g. {}",
                p.display(),
                Path::new("~").join(VENV_PYTHON).display()
            );
        }
        return Ok(Ok(p.clone()));
    }
    let home = std::env::var_os("HOME").map(PathBuf::from);
    match home.map(|h| h.join(VENV_PYTHON)) {
        Some(p) if p.is_file() => Ok(Ok(p)),
        Some(p) => Ok(Err(format!("no Python at {}", p.display()))),
        None => Ok(Err("HOME is not set".into())),
    }
}

/// Largest `--min-time`, s (50 runs cap a case anyway).
const MAX_MIN_TIME_S: f64 = 3600.0;

/// `grasp bench`.
pub fn execute(args: Args) -> Result<ExitCode> {
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
    run(Flags {
        quick: args.quick,
        markdown: args.markdown,
        solvers: args.solver,
        cases: args.cases,
        min_time_s: args.min_time,
        peer,
    })
}

/// What to run and how to print it.
pub struct Flags {
    /// Only the quick cases, 1 to 3 timing runs each, the whole command once, 200 batch
    /// variants (the CI smoke run).
    pub quick: bool,
    /// Print a Markdown table (for docs/benchmarks.md) instead of aligned text.
    pub markdown: bool,
    /// Solvers, one column group each.
    pub solvers: Vec<SolverChoice>,
    /// Case names to run (all when empty).
    pub cases: Vec<String>,
    /// Timing runs of a case continue until this much time has passed, s.
    pub min_time_s: f64,
    /// The Python that runs the peer on the Hertz FFT cases, or why there is none.
    pub peer: Result<PathBuf, String>,
}

/// Median, range and the first (memory) sample of one case with one solver.
struct Measured {
    case: Case,
    solver: SolverChoice,
    median_s: f64,
    min_s: f64,
    max_s: f64,
    median_solve_s: f64,
    runs: usize,
    first: Sample,
}

fn measure(case: &Case, solver: SolverChoice, flags: &Flags) -> Result<Measured> {
    let prepared = case.prepare(solver)?;
    let first = prepared.run(true)?;
    let (min_runs, max_runs) = if flags.quick { (1, 3) } else { (2, 50) };
    let start = Instant::now();
    let mut runs: Vec<Sample> = Vec::new();
    while runs.len() < min_runs
        || (runs.len() < max_runs && start.elapsed().as_secs_f64() < flags.min_time_s)
    {
        runs.push(prepared.run(false)?);
    }
    let times: Vec<f64> = runs.iter().map(|s| s.time_s).collect();
    let solves: Vec<f64> = runs.iter().map(|s| s.solve_s).collect();
    let (median_s, min_s, max_s) = median_and_range(&times).context("no finite timing")?;
    let (median_solve_s, _, _) = median_and_range(&solves).context("no finite timing")?;
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

/// A time in the unit that reads best.
fn time(s: f64) -> String {
    match s {
        s if s < 1e-3 => format!("{:.1} us", s * 1e6),
        s if s < 1.0 => format!("{:.3} ms", s * 1e3),
        s => format!("{s:.2} s"),
    }
}

fn per(case: &Case) -> &'static str {
    match case.kind {
        CaseKind::Solve => "per solve",
        CaseKind::OneShot => "build + solve",
        CaseKind::HandOff { .. } => "per step",
        CaseKind::Margins => "margins per step",
        CaseKind::Plan => "whole plan (runs)",
    }
}

/// One printed row: cells in column order.
type Row = Vec<String>;

const HEADER: [&str; 12] = [
    "case",
    "timed",
    "solver",
    "median",
    "range",
    "runs",
    "unknowns",
    "iterations",
    "factorizations",
    "peak MiB",
    "error",
    "target",
];

fn verdict(value: f64, limit: f64, show: impl Fn(f64) -> String) -> String {
    let mark = if value <= limit { "met" } else { "MISSED" };
    format!("<= {} ({mark})", show(limit))
}

fn case_row(m: &Measured) -> Row {
    let s = &m.first;
    let mib = s
        .peak_memory_bytes
        .map_or("-".into(), |b| format!("{:.2}", b as f64 / 1048576.0));
    let solver = match s.fallbacks {
        0 => m.solver.to_string(),
        n => format!("{} ({n} fallbacks)", m.solver),
    };
    vec![
        m.case.name.to_string(),
        per(&m.case).to_string(),
        solver,
        time(m.median_s),
        format!("{}-{}", time(m.min_s), time(m.max_s)),
        m.runs.to_string(),
        s.unknowns.to_string(),
        match s.inner_iterations > 0.0 {
            true => format!("{:.2} ({:.0} CG)", s.iterations, s.inner_iterations),
            false => format!("{:.2}", s.iterations),
        },
        format!("{:.2}", s.factorizations),
        mib,
        format!("{:.1e}", s.error),
        m.case
            .target
            .map_or("-".into(), |t| verdict(m.median_s, t.limit_s, time)),
    ]
}

fn find<'a>(all: &'a [Measured], name: &str, solver: SolverChoice) -> Option<&'a Measured> {
    all.iter()
        .find(|m| m.case.name == name && m.solver == solver)
}

/// Warm/cold iteration ratios (target 1/5) and growth exponents, per solver.
fn derived_rows(all: &[Measured], solvers: &[SolverChoice]) -> Vec<Row> {
    let mut rows = Vec::new();
    for &solver in solvers {
        for (label, warm, cold) in [
            (
                "plate hand-off warm/cold",
                "plate_handoff_warm",
                "plate_handoff_cold",
            ),
            (
                "coulomb hand-off warm/cold",
                "coulomb_handoff_warm",
                "coulomb_handoff_cold",
            ),
        ] {
            let (Some(w), Some(c)) = (find(all, warm, solver), find(all, cold, solver)) else {
                continue;
            };
            let ratio = w.first.iterations / c.first.iterations;
            let fact = w.first.factorizations / c.first.factorizations;
            let mut row = vec![String::new(); HEADER.len()];
            row[0] = label.into();
            row[1] = "iterations ratio".into();
            row[2] = solver.to_string();
            row[3] = format!("{ratio:.3}");
            row[7] = format!("{:.2} / {:.2}", w.first.iterations, c.first.iterations);
            row[8] = if fact.is_finite() {
                format!("ratio {fact:.3}")
            } else {
                "-".into()
            };
            row[11] = verdict(ratio, 0.2, |x| format!("{x:.1}"));
            rows.push(row);
        }
        rows.extend(layer_ratio_rows(all, solver));
        let series: Vec<(f64, f64)> = all
            .iter()
            // The dense series (the solver cases); the FFT case grows differently.
            .filter(|m| m.solver == solver && m.case.name.starts_with("cube_a_"))
            .filter(|m| CASES.iter().any(|c| c.name == m.case.name))
            .map(|m| (m.first.unknowns as f64, m.median_solve_s))
            .collect();
        if let Some(k) = growth_exponent(&series).filter(|_| series.len() >= 3) {
            let mut row = vec![String::new(); HEADER.len()];
            row[0] = "cube A series growth".into();
            row[1] = "solve ~ unknowns^k".into();
            row[2] = solver.to_string();
            row[3] = format!("k = {k:.2}");
            row[6] = series
                .iter()
                .map(|p| format!("{}", p.0))
                .collect::<Vec<_>>()
                .join(", ");
            rows.push(row);
        }
    }
    rows
}

/// The layered-pad ratios: a layered pad's time (model build and solve) over the half-space pad's
/// on the same path, target at most [`LAYER_PAIRS`]' bound; and the margins of a hand-off's
/// steps over the stepping, target at most [`MARGIN_PAIRS`]' bound.
fn layer_ratio_rows(all: &[Measured], solver: SolverChoice) -> Vec<Row> {
    let mut rows = Vec::new();
    for (layered, half, bound) in LAYER_PAIRS.into_iter().chain(MARGIN_PAIRS) {
        let (Some(l), Some(h)) = (find(all, layered, solver), find(all, half, solver)) else {
            continue;
        };
        let ratio = l.median_s / h.median_s;
        let mut row = vec![String::new(); HEADER.len()];
        row[0] = format!("{layered} / {half}");
        row[1] = "time ratio".into();
        row[2] = solver.to_string();
        row[3] = format!("{ratio:.2}x");
        row[4] = format!("{} / {}", time(l.median_s), time(h.median_s));
        row[11] = verdict(ratio, bound, |x| format!("{x:.1}x"));
        rows.push(row);
    }
    rows
}

/// The peer's row on a Hertz FFT case (its time, its peak-pressure error) and one row per
/// solver measured on the case with the ratio of the peer's time to ours.
fn peer_rows(record: &PeerRecord, ours: &[Measured]) -> Vec<Row> {
    let Some(case) = ours.first().map(|m| m.case) else {
        return Vec::new();
    };
    let mut row = vec!["-".to_string(); HEADER.len()];
    row[0] = case.name.to_string();
    row[1] = per(&case).to_string();
    row[2] = format!("{} {} (peer)", record.peer, record.version);
    row[3] = time(record.median_s);
    row[4] = format!("{}-{}", time(record.min_s), time(record.max_s));
    row[5] = record.runs.to_string();
    row[6] = (record.grid * record.grid).to_string();
    row[10] = format!("{:.1e}", record.p0_error.abs());
    let mut rows = vec![row];
    for m in ours {
        let mut row = vec![String::new(); HEADER.len()];
        row[0] = format!("{} peer/ours", case.name);
        row[1] = "time ratio".into();
        row[2] = m.solver.to_string();
        row[3] = format!("{:.2}x", record.median_s / m.median_s);
        row[4] = format!("{} / {}", time(record.median_s), time(m.median_s));
        rows.push(row);
    }
    rows
}

/// Runs the peer on a Hertz FFT case just measured (`ours`: its rows, one per solver) with as
/// many timing runs as ours had; the rows, and a note under the table with the peer's checks
/// against the closed form. A missing peer is not retried on the next case (`python` becomes
/// the reason); any other failure is a note. The bench never fails for the peer.
fn peer_case(
    ours: &[Measured],
    python: &mut Result<PathBuf, String>,
    notes: &mut Vec<String>,
) -> Vec<Row> {
    let (Some(first), Ok(exe)) = (ours.first(), python.as_ref()) else {
        return Vec::new();
    };
    let case = first.case;
    progress(&format!("bench: {} (peer)", case.name));
    let record = case
        .prepare(SolverChoice::Native)
        .map_err(|e| PeerError::Problem {
            case: case.name.to_string(),
            message: e.to_string(),
        })
        .and_then(|p| PeerProblem::of(&p))
        .and_then(|problem| problem.measure(exe, first.runs));
    match record {
        Ok(r) => {
            notes.push(format!(
                "peer {} {} on {}: tolerance {:e} (its own relative measure), {} timed runs \
                 after an untimed one; against Hertz: peak pressure {:+.1e}, contact radius \
                 {:+.1e}, load {:+.1e}",
                r.peer,
                r.version,
                case.name,
                r.tolerance,
                r.runs,
                r.p0_error,
                r.contact_radius_error,
                r.load_error
            ));
            peer_rows(&r, ours)
        }
        Err(e @ PeerError::Missing { .. }) => {
            *python = Err(e.to_string());
            Vec::new()
        }
        Err(e) => {
            notes.push(format!("peer not measured on {}: {e}", case.name));
            Vec::new()
        }
    }
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

/// Runs `grasp transfer` on the bundled plate hand-off with MCAP, Rerun and CSV outputs in a
/// temporary folder, timed from outside (process start to exit), median of 3 (1 when quick).
fn whole_command(solver: SolverChoice, quick: bool) -> Result<Row> {
    let dir = ScratchFolder::create()?;
    let (scene, schedule) =
        grasp_bench::bundled("plate_transfer").context("bundled plate_transfer")?;
    let schedule = schedule.context("bundled plate_transfer schedule")?;
    let (scene_path, schedule_path) = (dir.path.join("scene.json"), dir.path.join("schedule.json"));
    std::fs::write(&scene_path, scene)?;
    std::fs::write(&schedule_path, schedule)?;
    let exe = std::env::current_exe().context("locating the grasp executable")?;
    let mut times = Vec::new();
    for _ in 0..if quick { 1 } else { 3 } {
        let t = Instant::now();
        let out = std::process::Command::new(&exe)
            .arg("transfer")
            .arg(&scene_path)
            .arg("--schedule")
            .arg(&schedule_path)
            .args(["--solver", &solver.to_string(), "--force"])
            .arg("--mcap")
            .arg(dir.path.join("run.mcap"))
            .arg("--rrd")
            .arg(dir.path.join("run.rrd"))
            .arg("--csv")
            .arg(dir.path.join("run.csv"))
            .output()
            .context("running grasp transfer")?;
        times.push(t.elapsed().as_secs_f64());
        if !out.status.success() {
            bail!(
                "grasp transfer failed in the bench: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
    drop(dir);
    let (median, lo, hi) = median_and_range(&times).context("no timing")?;
    let mut row = vec![String::new(); HEADER.len()];
    row[0] = "plate hand-off command".into();
    row[1] = "whole process".into();
    row[2] = solver.to_string();
    row[3] = time(median);
    row[4] = format!("{}-{}", time(lo), time(hi));
    row[5] = times.len().to_string();
    row[11] = verdict(median, 0.5, time);
    Ok(row)
}

/// Attempts at a fresh scratch folder name.
const SCRATCH_ATTEMPTS: usize = 16;

/// A private scratch folder (`grasp-bench-<pid>-<random>` in the temporary folder, mode 0700),
/// created fresh (an existing folder or link of that name is never used), removed on drop.
struct ScratchFolder {
    path: std::path::PathBuf,
}

impl ScratchFolder {
    fn create() -> Result<ScratchFolder> {
        use std::hash::{BuildHasher, Hasher};
        use std::os::unix::fs::DirBuilderExt;
        let base = std::env::temp_dir();
        for attempt in 0..SCRATCH_ATTEMPTS {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_usize(attempt);
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos()),
            );
            let path = base.join(format!(
                "grasp-bench-{}-{:016x}",
                std::process::id(),
                h.finish()
            ));
            // mkdir never follows a link and fails on any existing name.
            match std::fs::DirBuilder::new().mode(0o700).create(&path) {
                Ok(()) => return Ok(ScratchFolder { path }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e).with_context(|| format!("creating {}", path.display())),
            }
        }
        bail!("cannot create a fresh scratch folder in {}", base.display())
    }
}

impl Drop for ScratchFolder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

/// Timed runs of each batch configuration (after one untimed run).
/// The fine patches timed on one thread and on every core, with their speed-up target.
const SCALING_CASES: [&str; 2] = ["hertz_512x512_fft", "hertz_1024x1024_fft"];

/// Two cores must make a fine patch at least this much faster than one.
const SCALING_TARGET: f64 = 1.7;

/// The 1024 x 1024 patch's conjugate-gradient iterations and peak memory must stay within
/// these.
const FINE_CG_LIMIT: f64 = 40.0;
const FINE_MEMORY_LIMIT_MIB: f64 = 500.0;

/// Rows of a fine patch timed on one thread and on every core: each time, and the speed-up
/// against [`SCALING_TARGET`].
fn scaling_rows(case: &Case, flags: &Flags) -> Result<Vec<Row>> {
    let prepared = case.prepare(SolverChoice::Native)?;
    let rounds = if flags.min_time_s > 0.0 { 3 } else { 1 };
    let t = grasp_bench::thread_scaling(&prepared, rounds)?;
    let mut rows = Vec::new();
    for (label, secs) in [
        ("1 thread".to_string(), t.one_thread_s),
        (format!("{} threads", t.cores), t.all_cores_s),
    ] {
        let mut row = vec![String::new(); HEADER.len()];
        row[0] = case.name.to_string();
        row[1] = format!("build + solve, {label}");
        row[2] = SolverChoice::Native.to_string();
        row[3] = time(secs);
        row[5] = t.runs.to_string();
        rows.push(row);
    }
    let mut row = vec![String::new(); HEADER.len()];
    row[0] = format!("{} speed-up", case.name);
    row[1] = format!("{} cores / 1", t.cores);
    row[2] = SolverChoice::Native.to_string();
    row[3] = format!("{:.2}x", t.speed_up());
    row[11] = match t.speed_up() >= SCALING_TARGET {
        true => format!(">= {SCALING_TARGET}x (met)"),
        false => format!(">= {SCALING_TARGET}x (MISSED)"),
    };
    rows.push(row);
    Ok(rows)
}

/// The 1024 x 1024 patch's conjugate-gradient iterations and peak memory against their
/// limits.
fn fine_limit_rows(all: &[Measured]) -> Vec<Row> {
    let Some(m) = find(all, "hertz_1024x1024_fft", SolverChoice::Native) else {
        return Vec::new();
    };
    let mut rows = Vec::new();
    let mib = m.first.peak_memory_bytes.map(|b| b as f64 / 1048576.0);
    for (what, value, limit) in [
        (
            "CG iterations",
            Some(m.first.inner_iterations),
            FINE_CG_LIMIT,
        ),
        ("peak MiB", mib, FINE_MEMORY_LIMIT_MIB),
    ] {
        let Some(value) = value else { continue };
        let mut row = vec![String::new(); HEADER.len()];
        row[0] = format!("hertz_1024x1024_fft {what}");
        row[1] = "per solve".into();
        row[2] = SolverChoice::Native.to_string();
        row[3] = format!("{value:.0}");
        row[11] = verdict(value, limit, |x| format!("{x:.0}"));
        rows.push(row);
    }
    rows
}

const BATCH_ROUNDS: usize = 5;

/// Scenes per second of one in-process batch run on `threads` threads (output discarded).
fn batch_rate(
    input: &grasp_batch::BatchInput,
    n: usize,
    solver: SolverChoice,
    threads: usize,
) -> Result<f64> {
    let options = grasp_batch::BatchOptions {
        solve: grasp_model::SolveOptions {
            solver,
            ..grasp_model::SolveOptions::default()
        },
        threads,
        ..grasp_batch::BatchOptions::default()
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
        &mut |_| {},
    )?;
    let wall = t.elapsed().as_secs_f64();
    if s.solved != n {
        bail!("batch bench: {} of {n} variants solved", s.solved);
    }
    Ok(n as f64 / wall)
}

/// Batch throughput: 1,000 variants of cube A (mu x weight grid; 200 when quick)
/// solved by `grasp batch`'s runner in-process, on one thread and on every core, output
/// discarded; rows: the median scenes per second of each over [`BATCH_ROUNDS`] alternating
/// runs, and the ratio of the medians against its >= 1.8x target.
fn batch_throughput(solver: SolverChoice, quick: bool) -> Result<Vec<Row>> {
    use grasp_batch::{Axis, Sweep};
    let (scene, _) = grasp_bench::bundled("cube_a").context("bundled cube_a")?;
    let scene: serde_json::Value = serde_json::from_str(scene)?;
    let weights = if quick { 20 } else { 100 };
    let axes = [
        Axis::parse("fingers[*].friction.mu=0.4:1.0:10")?,
        Axis::parse(&format!("object.weight=1:10:{weights}"))?,
    ];
    let sweep = Sweep::new(scene, "cube_a", &axes)?;
    let lines: Vec<String> = (0..sweep.len())
        .map(|k| sweep.line(k))
        .collect::<Result<_, _>>()?;
    let n = lines.len();
    let input = grasp_batch::BatchInput::Lines(lines);
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
        let mut row = vec![String::new(); HEADER.len()];
        row[0] = format!("batch cube A x{n}");
        row[1] = format!("{threads} thread(s)");
        row[2] = solver.to_string();
        row[3] = format!("{median:.0} scenes/s");
        row[4] = format!("{:.0}-{:.0}", v[0], v[v.len() - 1]);
        row[5] = v.len().to_string();
        rows.push(row);
    }
    let mut row = vec![String::new(); HEADER.len()];
    row[0] = "batch speed-up".into();
    row[1] = format!("{cores} cores / 1");
    row[2] = solver.to_string();
    let speedup = rates[1] / rates[0];
    row[3] = format!("{speedup:.2}x");
    row[11] = format!(
        ">= 1.8x ({})",
        if speedup >= 1.8 { "met" } else { "MISSED" }
    );
    rows.push(row);
    Ok(rows)
}

fn render(rows: &[Row], markdown: bool) -> String {
    let mut out = String::new();
    if markdown {
        let line = |cells: &[String]| format!("| {} |\n", cells.join(" | "));
        out.push_str(&line(&HEADER.map(String::from)));
        out.push_str(&line(&HEADER.map(|_| "---".to_string())));
        for r in rows {
            out.push_str(&line(r));
        }
        return out;
    }
    let widths: Vec<usize> = (0..HEADER.len())
        .map(|j| {
            rows.iter()
                .map(|r| r[j].chars().count())
                .chain([HEADER[j].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut line = |cells: Vec<&str>| {
        for (j, c) in cells.iter().enumerate() {
            let _ = write!(out, "{c:<w$}  ", w = widths[j]);
        }
        out.push('\n');
    };
    line(HEADER.to_vec());
    for r in rows {
        line(r.iter().map(String::as_str).collect());
    }
    out
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

/// Runs the bench and prints the table.
fn run(flags: Flags) -> Result<ExitCode> {
    let all = || {
        let cases = CASES.iter().chain(&FFT_CASES).chain(&LAYER_CASES);
        cases.chain(&HELD_CASES)
    };
    for name in &flags.cases {
        if !all().any(|c| c.name == name) && name != outputs::CASE {
            let names: Vec<&str> = all().map(|c| c.name).chain([outputs::CASE]).collect();
            bail!(
                "--case {name}: no such case; choose from {}",
                names.join(", ")
            );
        }
    }
    let chosen: Vec<&Case> = all()
        .filter(|c| flags.cases.is_empty() || flags.cases.iter().any(|n| n == c.name))
        .filter(|c| !flags.quick || c.quick || !flags.cases.is_empty())
        .collect();
    let mut measured = Vec::new();
    let mut rows = Vec::new();
    let (mut peer, mut notes) = (flags.peer.clone(), Vec::new());
    for case in &chosen {
        let fft = FFT_CASES.iter().any(|c| c.name == case.name) || case.name.ends_with("_fft");
        let native_only = fft || HELD_CASES.iter().any(|c| c.name == case.name);
        let start = measured.len();
        for &solver in &flags.solvers {
            if solver == SolverChoice::Clarabel && native_only {
                continue;
            }
            progress(&format!("bench: {} ({solver})", case.name));
            let m = measure(case, solver, &flags)?;
            rows.push(case_row(&m));
            measured.push(m);
        }
        if PEER_CASES.contains(&case.name) {
            rows.extend(peer_case(&measured[start..], &mut peer, &mut notes));
        }
        if SCALING_CASES.contains(&case.name) && flags.solvers.contains(&SolverChoice::Native) {
            progress(&format!(
                "bench: {} on 1 thread and on every core",
                case.name
            ));
            rows.extend(scaling_rows(case, &flags)?);
        }
    }
    rows.extend(fine_limit_rows(&measured));
    if let Err(reason) = &peer {
        if chosen.iter().any(|c| PEER_CASES.contains(&c.name)) {
            notes.push(peer_missing_note(reason));
        }
    }
    rows.extend(derived_rows(&measured, &flags.solvers));
    if flags.cases.is_empty() {
        for &solver in &flags.solvers {
            progress(&format!("bench: whole transfer command ({solver})"));
            rows.push(whole_command(solver, flags.quick)?);
            progress(&format!("bench: batch throughput ({solver})"));
            rows.extend(batch_throughput(solver, flags.quick)?);
        }
    }
    if flags.cases.is_empty() || flags.cases.iter().any(|c| c == outputs::CASE) {
        progress(&format!("bench: {}", outputs::CASE));
        rows.extend(outputs::output_rows(flags.quick)?);
    }
    if std::io::stderr().is_terminal() {
        eprint!("\r{:<60}\r", "");
    }
    print!("{}", render(&rows, flags.markdown));
    println!(
        "\n(release build, this machine; times are medians of the timing runs; iterations: \
         Newton steps (native) or interior-point iterations (Clarabel) per solve or step (the plan: hand-off runs); \
         peak MiB: resident memory above the start of the case's first run; error: Hertz \
         peak-pressure error for hertz_*, the stick radius's error in elements against \
         Cattaneo's for cattaneo_*, how far the plan's margin falls short for the plan, else the \
         worst relative residual)"
    );
    for note in &notes {
        println!("{note}");
    }
    Ok(ExitCode::SUCCESS)
}
