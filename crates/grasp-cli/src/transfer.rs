//! `grasp transfer`: validated inputs, sinks, a progress bar, and the closing summary.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use grasp_transfer::{
    CsvSink, McapSink, RerunSink, Schedule, Sink, SqueezeOutcome, TransferOptions, TransferSummary,
};
use indicatif::{ProgressBar, ProgressStyle};

use crate::output::check_writable;

/// Output files of a transfer.
pub struct Outputs {
    pub mcap: Option<PathBuf>,
    pub rrd: Option<PathBuf>,
    pub csv: Option<PathBuf>,
    pub plot: Option<PathBuf>,
    pub force: bool,
}

/// Switches of a transfer.
pub struct Flags {
    pub keep_going: bool,
    pub cold: bool,
    pub min_squeeze: bool,
    pub solver: grasp_model::SolverChoice,
}

pub fn run(
    scene_path: &PathBuf,
    schedule_path: &PathBuf,
    out: &Outputs,
    flags: Flags,
) -> Result<ExitCode> {
    // Validate everything before any work: outputs, scene, schedule.
    for p in [&out.mcap, &out.rrd, &out.csv, &out.plot]
        .into_iter()
        .flatten()
    {
        check_writable(p, out.force)?;
    }
    let scene = crate::load_scene(scene_path)?;
    let text = std::fs::read_to_string(schedule_path)
        .with_context(|| format!("cannot read schedule file {}", schedule_path.display()))?;
    let names: Vec<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
    let base = schedule_path
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    let schedule = Schedule::from_json_str(&text, &names, &base)
        .with_context(|| format!("{} is not a usable schedule", schedule_path.display()))?;

    let mut mcap = out.mcap.as_deref().map(McapSink::create).transpose()?;
    let mut rrd = out.rrd.as_deref().map(RerunSink::create).transpose()?;
    let mut csv = out.csv.as_deref().map(CsvSink::create).transpose()?;
    let mut sinks: Vec<&mut dyn Sink> = Vec::new();
    if let Some(s) = mcap.as_mut() {
        sinks.push(s);
    }
    if let Some(s) = rrd.as_mut() {
        sinks.push(s);
    }
    if let Some(s) = csv.as_mut() {
        sinks.push(s);
    }
    // indicatif draws only on a terminal; piped output stays quiet.
    let bar = ProgressBar::new(schedule.times.len() as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} steps  t = {msg}  ({elapsed}, eta {eta})",
        )
        .expect("valid template"),
    );
    let options = TransferOptions {
        keep_going: flags.keep_going,
        warm_start: !flags.cold,
        solve: grasp_model::SolveOptions {
            solver: flags.solver,
            ..grasp_model::SolveOptions::default()
        },
    };
    let (records, summary) = grasp_transfer::run(&scene, &schedule, options, &mut sinks, |r| {
        bar.set_message(format!("{:.3} s", r.time_s));
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(p) = &out.plot {
        let svg =
            crate::plot::force_history_svg(&records, &names, &scene_path.display().to_string());
        crate::output::write_new(p, svg.as_bytes(), out.force)?;
    }
    print!(
        "{}",
        summary_text(&summary, records.len(), schedule.times.len())
    );
    if flags.min_squeeze {
        match records.last() {
            Some(last) => {
                let outcome = grasp_transfer::minimum_squeeze(&scene, last, options.solve)?;
                print!("{}", squeeze_text(&outcome));
            }
            None => println!("minimum squeeze: no step was solved"),
        }
    }
    for (p, what) in [
        (&out.mcap, "MCAP"),
        (&out.rrd, "Rerun recording"),
        (&out.csv, "CSV"),
        (&out.plot, "plot"),
    ] {
        if let Some(p) = p {
            println!("wrote {what}: {}", p.display());
        }
    }
    Ok(if summary.failed_steps.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

fn summary_text(s: &TransferSummary, done: usize, planned: usize) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "steps: {done} of {planned}");
    let _ = writeln!(o, "releasing fingers: {}", list(&s.releasing));
    let _ = writeln!(o, "receiving fingers: {}", list(&s.receiving));
    let t = |x: Option<f64>| x.map_or("never".to_string(), |v| format!("t = {v:.3} s"));
    let _ = writeln!(
        o,
        "receiving fingers carry half the load: {}",
        t(s.half_transfer_time_s)
    );
    let _ = writeln!(
        o,
        "receiving fingers carry all the load:  {}",
        t(s.full_transfer_time_s)
    );
    let _ = writeln!(
        o,
        "peak squeeze (sum of normal forces): {:.4} N at t = {:.3} s",
        s.peak_squeeze_n, s.peak_squeeze_time_s
    );
    match &s.smallest_slip_margin {
        Some((m, time, f)) => {
            let _ = writeln!(
                o,
                "smallest slip margin 1 - |Q|/(mu P): {m:.2e} ({f} at t = {time:.3} s)"
            );
        }
        None => {
            let _ = writeln!(o, "smallest slip margin: no loaded frictional finger");
        }
    }
    if s.failed_steps.is_empty() {
        let _ = writeln!(o, "failed steps: none");
    } else {
        let _ = writeln!(o, "failed steps: {}", s.failed_steps.len());
        for (i, time, why) in s.failed_steps.iter().take(5) {
            let _ = writeln!(o, "  step {i} (t = {time:.3} s): {why}");
        }
    }
    if let Some(q) = &s.sequential {
        let _ = writeln!(
            o,
            "sequential solves: {} convex solves, at most {} in a step, {} of {done} steps \
             warm-started, {} cold restarts",
            q.convex_solves, q.most_in_a_step, q.warm_started_steps, q.cold_restarts
        );
    }
    let _ = writeln!(
        o,
        "error: worst equilibrium residual {:.1e} of the load; time: {:.3} s in all, {:.2} ms per step, {} iterations",
        s.worst_equilibrium_residual,
        s.total_wall_time_s,
        1e3 * s.total_wall_time_s / done.max(1) as f64,
        s.total_iterations
    );
    o
}

fn squeeze_text(o: &SqueezeOutcome) -> String {
    match o {
        SqueezeOutcome::NotFound(why) => format!("minimum squeeze: not found: {why}\n"),
        SqueezeOutcome::Found(m) => {
            let fingers: Vec<String> = m
                .fingers
                .iter()
                .map(|f| {
                    format!(
                        "{} {:.4} N (scheduled {:.4} N)",
                        f.name, f.minimum_n, f.scheduled_n
                    )
                })
                .collect();
            format!(
                "minimum squeeze to let go: {}; margin {:.3}x; just below it: {}\n",
                fingers.join(", "),
                m.margin,
                m.limiting
            )
        }
    }
}

fn list(v: &[String]) -> String {
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}
