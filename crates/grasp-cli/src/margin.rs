//! `grasp margin`: disturbance margins of one grasp ([`grasp_model::margin`]) as a table, JSON,
//! a bar chart and a Rerun recording of the wrench surface.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_model::margin::{
    axis_directions, disturbance_margins, plane_directions, spread_directions, DirectionMargin,
    Failure, MarginOptions, MarginReport, WrenchDirection,
};
use grasp_model::scene::ModelKind;
use grasp_model::{ContactState, GraspModel, SolveOptions, SolverChoice};
use grasp_transfer::{RerunSink, RunInfo, Sink};
use serde::Deserialize;

use crate::{limits, load_scene, output};

/// What to compute.
pub struct Flags {
    /// `N` or a JSON file of directions.
    pub directions: Option<String>,
    /// Contact law override.
    pub model: Option<String>,
    /// Characteristic length, m.
    pub length_m: Option<f64>,
    /// Relative bracket width.
    pub tolerance: f64,
    /// Solver.
    pub solver: SolverChoice,
    /// Memory limit, bytes.
    pub max_memory: Option<u64>,
}

/// Where to write.
pub struct Outputs {
    pub json: Option<PathBuf>,
    pub plot: Option<PathBuf>,
    pub rrd: Option<PathBuf>,
    pub force: bool,
}

/// One direction as written in a directions file: a force (N) and a couple (N m), either
/// may be omitted.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionSpec {
    #[serde(default)]
    force: [f64; 3],
    #[serde(default)]
    torque: [f64; 3],
}

/// The directions the user asked for.
fn directions(
    model: &GraspModel,
    arg: Option<&str>,
    length_m: f64,
) -> Result<Vec<WrenchDirection>> {
    let Some(arg) = arg else {
        return Ok(axis_directions(model));
    };
    if let Some(k) = arg.strip_prefix("planes:") {
        return match k.parse::<usize>() {
            Ok(k) if (4..=360).contains(&k) => Ok(plane_directions(model, k)),
            _ => bail!("--directions planes:{k}: give between 4 and 360 directions per plane, e.g. planes:24"),
        };
    }
    if let Ok(n) = arg.parse::<usize>() {
        if !(1..=10_000).contains(&n) {
            bail!("--directions {n}: give between 1 and 10000 directions, or a JSON file");
        }
        return Ok(spread_directions(model, n));
    }
    let path = Path::new(arg);
    let text = limits::read_input(path, "directions file")?;
    let specs: Vec<DirectionSpec> = serde_json::from_str(&text).with_context(|| {
        format!(
            "{arg} is not a list of directions; write [{{\"force\": [0, 0, -1]}}, {{\"torque\": \
             [1, 0, 0]}}] (force in N, couple in N m)"
        )
    })?;
    if specs.is_empty() {
        bail!("{arg} lists no direction; give at least one");
    }
    specs
        .iter()
        .enumerate()
        .map(|(i, d)| {
            WrenchDirection::of_wrench(d.force, d.torque, length_m).with_context(|| {
                format!("{arg}: directions[{i}] has no finite nonzero force or torque; give one")
            })
        })
        .collect()
}

/// Runs the command.
pub fn run(scene_path: &Path, flags: Flags, outputs: &Outputs) -> Result<ExitCode> {
    if !(flags.tolerance.is_finite() && flags.tolerance > 0.0 && flags.tolerance < 0.5) {
        bail!(
            "--tolerance {}: give a relative width in (0, 0.5), e.g. 1e-3",
            flags.tolerance
        );
    }
    if let Some(l) = flags.length_m {
        if !(l.is_finite() && l > 0.0) {
            bail!("--length {l}: give a length in metres > 0, e.g. 0.05");
        }
    }
    let targets: Vec<&Path> = [&outputs.json, &outputs.plot, &outputs.rrd]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .collect();
    output::check_targets(&targets, &[scene_path], outputs.force)?;
    let mut scene = load_scene(scene_path)?;
    match flags.model.as_deref() {
        Some("coulomb") => scene.model = ModelKind::Coulomb,
        Some("energy") => scene.model = ModelKind::Energy,
        _ => {}
    }
    let (limit, what) = limits::memory_limit(flags.max_memory);
    limits::check_memory(&scene, scene_path, (limit, &what))?;
    let model = GraspModel::from_scene(&scene)
        .with_context(|| format!("{} is not a usable scene", scene_path.display()))?;
    let length_m = flags.length_m.unwrap_or(model.scales.length_m);
    let dirs = directions(&model, flags.directions.as_deref(), length_m)?;
    let options = MarginOptions {
        length_m: Some(length_m),
        relative_tolerance: flags.tolerance,
        ..MarginOptions::default()
    };
    let solve = SolveOptions {
        solver: flags.solver,
        ..SolveOptions::default()
    };
    let report = disturbance_margins(&model, &ContactState::new(&model), solve, &dirs, &options)?;
    print!("{}", table(scene_path, &report));
    if let Some(out) = &outputs.json {
        let text = serde_json::to_string_pretty(&report)?;
        output::write_new(out, text.as_bytes(), outputs.force)?;
        println!("wrote {}", out.display());
    }
    if let Some(out) = &outputs.plot {
        output::write_new(out, bar_chart(&model, &report).as_bytes(), outputs.force)?;
        println!("wrote {}", out.display());
    }
    if let Some(out) = &outputs.rrd {
        let run = RunInfo {
            scene: &scene,
            geometry: &model,
        };
        let mut sink = RerunSink::create(out)?;
        sink.begin(&run)?;
        sink.log_wrench_surface(&run, &report)?;
        sink.finish()?;
        println!("wrote {}", out.display());
    }
    // Exit 2 when the grasp does not hold undisturbed (no direction was searched); a direction
    // the grasp does not resist at all (margin 0) is a result like any other.
    let holds = report.directions.iter().any(|d| d.solves > 0);
    if !holds {
        let why = report.directions[0].failure.as_ref().map(failure_words_of);
        println!(
            "the grasp does not hold without disturbance: {}",
            why.unwrap_or_default()
        );
    }
    Ok(if holds {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

/// A short label of a direction: its nonzero components.
pub fn label(d: &WrenchDirection) -> String {
    let part = |v: &[f64; 3], unit: &str| -> Option<String> {
        (v.iter().any(|c| c.abs() > 1e-12))
            .then(|| format!("{unit}[{:+.2},{:+.2},{:+.2}]", v[0], v[1], v[2]))
    };
    [part(&d.force, "F"), part(&d.torque, "T")]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(" ")
}

/// A failure with its reason.
fn failure_words_of(f: &Failure) -> String {
    match f {
        Failure::Slides { finger } => format!("{finger} slides as a whole"),
        Failure::NoEquilibrium { reason } | Failure::NoConvergence { reason } => reason.clone(),
    }
}

fn failure_words(m: &DirectionMargin) -> String {
    match &m.failure {
        None => "holds up to the cap".into(),
        Some(Failure::Slides { finger }) => format!("{finger} slides"),
        Some(Failure::NoEquilibrium { .. }) => "no equilibrium".into(),
        Some(Failure::NoConvergence { .. }) => "no convergence".into(),
    }
}

/// The report as a table.
fn table(scene: &Path, r: &MarginReport) -> String {
    let mut s = String::new();
    let crit = match r.model {
        ModelKind::Energy => "energy: an equilibrium within the friction cones",
        ModelKind::Coulomb => {
            "coulomb: equilibrium and every loaded finger keeps a sticking element"
        }
    };
    let _ = writeln!(
        s,
        "{}: disturbance margins ({crit}); magnitude s = force s N at the centre of mass plus \
         couple s L N m, L = {:.4} m",
        scene.display(),
        r.length_m
    );
    let _ = writeln!(
        s,
        "{:<4}{:<44}{:>14}{:>14}{:>12}  {:<22}{:>8}",
        "#", "direction", "margin [N]", "torque [N m]", "first", "failure", "solves"
    );
    for (i, m) in r.directions.iter().enumerate() {
        let torque = m.torque_nm.iter().map(|v| v * v).sum::<f64>().sqrt();
        let margin = if m.bounded {
            format!("{:.5e}", m.margin_n)
        } else {
            format!(">{:.3e}", m.margin_n)
        };
        let _ = writeln!(
            s,
            "{:<4}{:<44}{:>14}{:>14.4e}{:>12}  {:<22}{:>8}",
            i,
            label(&m.direction),
            margin,
            torque,
            m.failing_finger.as_deref().unwrap_or("-"),
            failure_words(m),
            m.solves
        );
    }
    if !r.sliding_undisturbed.is_empty() {
        let _ = writeln!(
            s,
            "already sliding without disturbance (not judged by sliding): {}",
            r.sliding_undisturbed.join(", ")
        );
    }
    if !r.unresisted.is_empty() && r.unresisted.len() < r.directions.len() {
        let _ = writeln!(
            s,
            "not resisted at all (margin 0; the commanded loads cannot react): {}",
            r.unresisted
                .iter()
                .map(|&i| format!("#{i}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let w = &r.directions[r.smallest];
    let _ = writeln!(
        s,
        "smallest margin: {:.5e} N along #{} {} ({}, first to fail: {})",
        w.margin_n,
        r.smallest,
        label(&w.direction),
        failure_words(w),
        w.failing_finger.as_deref().unwrap_or("-")
    );
    let _ = writeln!(
        s,
        "cost: {} solves in {:.1} ms (directions in parallel; each a warm-started step from the \
         last magnitude that held)",
        r.solves,
        r.time_s * 1e3
    );
    s
}

/// The coordinate planes of the polar panels: name and in-plane axes `(a, b)` (3-D: `xy`,
/// `yz`, `zx`; planar: the plane of motion).
fn panel_planes(model: &GraspModel) -> Vec<(&'static str, [f64; 3], [f64; 3])> {
    match model.plane {
        None => vec![
            ("force in the x-y plane", [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ("force in the y-z plane", [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            ("force in the z-x plane", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        ],
        Some((e1, e2, _)) => vec![(
            "force in the plane (e1, e2)",
            [e1.x, e1.y, e1.z],
            [e2.x, e2.y, e2.z],
        )],
    }
}

/// One polar panel (SVG fragment at `x0`, size `size`): the margins of the pure-force
/// directions lying in the plane `(a, b)`, at their angle, radius proportional to the margin
/// (`r_max` at the rim; unbounded ones on the rim, hollow).
fn polar_panel(r: &MarginReport, plane: (&str, [f64; 3], [f64; 3]), x0: f64, r_max: f64) -> String {
    let (title, a, b) = plane;
    let dot = |u: &[f64; 3], v: &[f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let size = 200.0;
    let (cx, cy, rad) = (x0 + size / 2.0, 40.0 + size / 2.0, size / 2.0 - 14.0);
    let mut s = format!("<text x=\"{cx}\" y=\"34\" text-anchor=\"middle\">{title}</text>\n");
    for k in 1..=4 {
        let rr = rad * k as f64 / 4.0;
        let _ = writeln!(
            s,
            "<circle cx=\"{cx}\" cy=\"{cy}\" r=\"{rr:.1}\" fill=\"none\" stroke=\"#ddd\"/>"
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"#888\">{:.3e} N</text>",
        cx + 2.0,
        cy - rad - 2.0,
        r_max
    );
    let mut pts: Vec<(f64, f64, f64, bool, usize)> = Vec::new();
    for (i, d) in r.directions.iter().enumerate() {
        let f = d.direction.force;
        let (fa, fb) = (dot(&f, &a), dot(&f, &b));
        let in_plane =
            d.direction.torque.iter().all(|t| *t == 0.0) && (fa * fa + fb * fb - 1.0).abs() < 1e-9;
        if in_plane {
            let m = if d.bounded {
                d.margin_n.min(r_max)
            } else {
                r_max
            };
            pts.push((fb.atan2(fa), m / r_max * rad, d.margin_n, d.bounded, i));
        }
    }
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    let xy = |p: &(f64, f64, f64, bool, usize)| (cx + p.1 * p.0.cos(), cy - p.1 * p.0.sin());
    if pts.len() >= 3 {
        let poly: Vec<String> = pts
            .iter()
            .map(|p| {
                let (x, y) = xy(p);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        let _ = writeln!(
            s,
            "<polygon points=\"{}\" fill=\"#1f77b4\" fill-opacity=\"0.15\" stroke=\"#1f77b4\"/>",
            poly.join(" ")
        );
    }
    for p in &pts {
        let (x, y) = xy(p);
        let colour = if p.4 == r.smallest {
            "#d62728"
        } else {
            "#1f77b4"
        };
        let fill = if p.3 { colour } else { "white" };
        let _ = writeln!(
            s,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3.5\" fill=\"{fill}\" stroke=\"{colour}\"/>"
        );
    }
    s
}

/// The picture of the margins (SVG): polar panels of the force directions in each coordinate
/// plane (`--directions planes:K` fills them), then one bar per direction; the smallest in
/// red, unbounded ones pale (hollow in the panels, drawn at the cap).
fn bar_chart(model: &GraspModel, r: &MarginReport) -> String {
    let planes = panel_planes(model);
    let bounded_max = r
        .directions
        .iter()
        .filter(|d| d.bounded)
        .map(|d| d.margin_n)
        .fold(0.0_f64, f64::max);
    let r_max = if bounded_max > 0.0 {
        bounded_max
    } else {
        r.directions
            .iter()
            .map(|d| d.margin_n)
            .fold(f64::MIN_POSITIVE, f64::max)
    };
    let panels: String = planes
        .iter()
        .enumerate()
        .map(|(k, p)| polar_panel(r, *p, 10.0 + 220.0 * k as f64, r_max))
        .collect();
    let bars = bars(r, 270.0);
    let n = r.directions.len();
    let height = 270.0 + 40.0 + 18.0 * n as f64;
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"{height}\" \
         font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" \
         fill=\"white\"/>\n<text x=\"10\" y=\"16\" font-size=\"13\">Disturbance margins \
         (N; a couple is the margin times L = {:.4} m)</text>\n{panels}{bars}</svg>\n",
        r.length_m
    )
}

/// One bar per direction (SVG fragment starting at `top`).
fn bars(r: &MarginReport, top: f64) -> String {
    let (left, width, row) = (260.0, 420.0, 18.0);
    // Scaled to the largest bounded margin; unbounded ones fill the row.
    let max = r
        .directions
        .iter()
        .filter(|d| d.bounded)
        .map(|d| d.margin_n)
        .fold(0.0_f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut s = format!(
        "<text x=\"10\" y=\"{:.0}\">margin per direction</text>\n",
        top + 16.0
    );
    for (i, d) in r.directions.iter().enumerate() {
        let y = top + 26.0 + row * i as f64;
        let len = if d.bounded {
            width * d.margin_n / max
        } else {
            width
        };
        let fill = if i == r.smallest {
            "#d62728"
        } else if d.bounded {
            "#1f77b4"
        } else {
            "#aec7e8"
        };
        let _ = writeln!(
            s,
            "<text x=\"{x}\" y=\"{ty}\" text-anchor=\"end\">{}</text>\
             <rect x=\"{left}\" y=\"{y}\" width=\"{len:.1}\" height=\"{h}\" fill=\"{fill}\"/>\
             <text x=\"{tx:.1}\" y=\"{ty}\">{}{:.3e}</text>",
            label(&d.direction),
            if d.bounded { "" } else { ">" },
            d.margin_n,
            x = left - 6.0,
            ty = y + 12.0,
            h = row - 4.0,
            tx = left + len + 4.0
        );
    }
    s
}
