//! The whole `grasp transfer` command timed from outside: the bundled plate hand-off with MCAP,
//! Rerun and CSV outputs in a scratch folder, process start to exit, median of 3 runs (1 when
//! quick), against [`WHOLE_COMMAND_TARGET_S`]. The `grasp` executable is the caller's to give
//! (`grasp bench` gives itself).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use grasp_model::SolverChoice;

use crate::error::BenchError;
use crate::scratch_folder::ScratchFolder;
use crate::statistics::median_and_range;
use crate::table::{time, verdict, Row};

/// The row's name.
const NAME: &str = "plate hand-off command";

/// Largest median of the whole command, s.
const WHOLE_COMMAND_TARGET_S: f64 = 0.5;

/// Times `grasp transfer` of the executable `grasp` on the plate hand-off with `solver`.
pub(crate) fn whole_command_row(
    grasp: &Path,
    solver: SolverChoice,
    quick: bool,
) -> Result<Row, BenchError> {
    let dir = ScratchFolder::create()?;
    let missing = |what: &str| BenchError::Input {
        case: NAME.into(),
        message: format!("no bundled {what}"),
    };
    let (scene, schedule) =
        crate::case::bundled("plate_transfer").ok_or_else(|| missing("scene plate_transfer"))?;
    let schedule = schedule.ok_or_else(|| missing("schedule plate_transfer"))?;
    let scene_path = dir.path().join("scene.json");
    let schedule_path = dir.path().join("schedule.json");
    for (path, text) in [(&scene_path, scene), (&schedule_path, schedule)] {
        std::fs::write(path, text).map_err(|source| BenchError::Io {
            doing: format!("writing {}", path.display()),
            source,
        })?;
    }
    let mut transfer = Command::new(grasp);
    transfer
        .arg("transfer")
        .arg(&scene_path)
        .arg("--schedule")
        .arg(&schedule_path)
        .args(["--solver", &solver.to_string(), "--force"])
        .arg("--mcap")
        .arg(dir.path().join("run.mcap"))
        .arg("--rrd")
        .arg(dir.path().join("run.rrd"))
        .arg("--csv")
        .arg(dir.path().join("run.csv"));
    let mut times = Vec::new();
    for _ in 0..if quick { 1 } else { 3 } {
        times.push(timed_run(&mut transfer)?);
    }
    drop(dir);
    let (median, lo, hi) = median_and_range(&times).ok_or_else(|| BenchError::Run {
        case: NAME.into(),
        message: "no timing".into(),
    })?;
    Ok(Row {
        case: NAME.into(),
        timed: "whole process".into(),
        solver: solver.to_string(),
        median: time(median),
        range: format!("{}-{}", time(lo), time(hi)),
        runs: times.len().to_string(),
        target: verdict(median, WHOLE_COMMAND_TARGET_S, time),
        ..Row::default()
    })
}

/// Runs `command` to its end, its output captured: the time from start to exit, s.
fn timed_run(command: &mut Command) -> Result<f64, BenchError> {
    let t = Instant::now();
    let out = command.output().map_err(|source| BenchError::Io {
        doing: "running grasp transfer".into(),
        source,
    })?;
    let elapsed_s = t.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(BenchError::TransferCommand {
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        });
    }
    Ok(elapsed_s)
}
