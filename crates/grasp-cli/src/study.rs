//! `grasp study`: a grid-refinement table (and CSV, plot) so a user can pick a grid for the
//! accuracy they need.

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_model::refinement::{self, refinement_study, StudyReference, StudyRow};
use grasp_model::SolveOptions;

use crate::output::{check_targets, commit_all, write_all, PendingOutput};

/// Peak resident memory of this process (Linux `VmHWM`), bytes. Grids run in ascending order,
/// so after each solve it is that grid's peak.
fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Output files of a study.
pub struct Outputs<'a> {
    pub csv: Option<&'a Path>,
    pub plot: Option<&'a Path>,
    pub force: bool,
}

pub fn run(
    scene: &Path,
    grids: &[usize],
    reference: &str,
    out: Outputs,
    max_memory: Option<u64>,
    solver: grasp_model::SolverChoice,
) -> Result<ExitCode> {
    if grids.contains(&0) {
        bail!("--grids has a 0; give element counts >= 1, e.g. --grids 5,9,17");
    }
    let (csv, plot) = (out.csv, out.plot);
    let targets: Vec<&Path> = [csv, plot].into_iter().flatten().collect();
    check_targets(&targets, &[scene], out.force)?;
    let scene_obj = crate::load_scene(scene)?;
    let limit = crate::limits::memory_limit(max_memory);
    let finest = grids.iter().copied().max().unwrap_or(1);
    let finest_scene = refinement::with_grids(&scene_obj, |_, g| {
        refinement::grid_with_first_side(g, finest)
    });
    crate::limits::check_memory(&finest_scene, scene, (limit.0, &limit.1)).with_context(|| {
        format!("the finest grid of the study ({finest} elements along the first side)")
    })?;
    let reference = if reference == "hertz" {
        StudyReference::Hertz
    } else {
        StudyReference::FinestGrid
    };
    let rows = match refinement_study(
        &scene_obj,
        grids,
        reference,
        SolveOptions {
            solver,
            ..SolveOptions::default()
        },
        peak_memory_bytes,
    ) {
        Ok(r) => r,
        Err(e) => bail!("study of {} failed: {e}", scene.display()),
    };
    let (e1, e2) = match reference {
        StudyReference::Hertz => ("p0 error", "approach error"),
        StudyReference::FinestGrid => ("force error", ""),
    };
    print!("{}", table_text(scene, reference, &rows, e1, e2));
    let mut pending = Vec::new();
    if let Some(p) = csv {
        let (o, f) = PendingOutput::create(p)?;
        write_all(&o, f, csv_text(&rows).as_bytes())?;
        pending.push(o);
    }
    if let Some(p) = plot {
        let svg = study_svg(&rows, e1, e2, &scene.display().to_string());
        let (o, f) = PendingOutput::create(p)?;
        write_all(&o, f, svg.as_bytes())?;
        pending.push(o);
    }
    commit_all(pending)?;
    for p in targets {
        println!("wrote {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The Markdown table of the study.
fn table_text(
    scene: &Path,
    reference: StudyReference,
    rows: &[StudyRow],
    e1: &str,
    e2: &str,
) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: error against {}",
        scene.display(),
        if reference == StudyReference::Hertz {
            "the Hertz closed form"
        } else {
            "the finest grid (force error over the load)"
        }
    );
    let _ = writeln!(
        t,
        "| grid | unknowns | {e1} | {} wall time [s] | peak memory [MiB] |",
        if e2.is_empty() {
            String::new()
        } else {
            format!("{e2} |")
        }
    );
    let _ = writeln!(
        t,
        "|---|---|---|{}---|---|",
        if e2.is_empty() { "" } else { "---|" }
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {}x{} | {} | {:.2e} | {}{:.3} | {} |",
            r.grid[0],
            r.grid[1],
            r.unknowns,
            r.error,
            r.error_2.map_or(String::new(), |e| format!("{e:.2e} | ")),
            r.wall_time_s,
            r.peak_memory_bytes
                .map_or("-".into(), |b| format!("{:.0}", b as f64 / 1048576.0))
        );
    }
    t
}

/// The study as CSV (numbers only: no field needs quoting).
fn csv_text(rows: &[StudyRow]) -> String {
    let mut c = String::from(
        "nx,ny,unknowns,error,error_2,wall_time_s,peak_memory_bytes,equilibrium_residual\n",
    );
    for r in rows {
        let _ = writeln!(
            c,
            "{},{},{},{},{},{},{},{}",
            r.grid[0],
            r.grid[1],
            r.unknowns,
            r.error,
            r.error_2.map_or(String::new(), |e| e.to_string()),
            r.wall_time_s,
            r.peak_memory_bytes.map_or(String::new(), |b| b.to_string()),
            r.equilibrium_residual
        );
    }
    c
}

/// Log-log plot of error against wall time, one point per grid.
fn study_svg(rows: &[StudyRow], e1: &str, e2: &str, title: &str) -> String {
    let (w, h, ml, mr, mt, mb) = (700.0, 460.0, 80.0, 30.0, 40.0, 55.0);
    // Points of a log-log plot need positive errors; each keeps its row for the label.
    let pts: Vec<(f64, f64, Option<f64>, &StudyRow)> = rows
        .iter()
        .filter(|r| r.error > 0.0)
        .map(|r| (r.wall_time_s, r.error, r.error_2.filter(|e| *e > 0.0), r))
        .collect();
    let xs: Vec<f64> = pts.iter().map(|p| p.0.log10()).collect();
    let ys: Vec<f64> = pts
        .iter()
        .flat_map(|p| std::iter::once(p.1.log10()).chain(p.2.map(f64::log10)))
        .collect();
    let (x0, x1) = (
        xs.iter().cloned().fold(f64::INFINITY, f64::min).floor(),
        xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil(),
    );
    let (y0, y1) = (
        ys.iter().cloned().fold(f64::INFINITY, f64::min).floor(),
        ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil(),
    );
    let (x1, y1) = (x1.max(x0 + 1.0), y1.max(y0 + 1.0));
    let x = |v: f64| ml + (v.log10() - x0) / (x1 - x0) * (w - ml - mr);
    let y = |v: f64| h - mb - (v.log10() - y0) / (y1 - y0) * (h - mt - mb);
    let mut s = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">
<rect width="{w}" height="{h}" fill="white"/>
<text x="{}" y="22" text-anchor="middle" font-size="14">Error against run time: {}</text>
<line x1="{ml}" y1="{}" x2="{}" y2="{}" stroke="#000"/><line x1="{ml}" y1="{mt}" x2="{ml}" y2="{}" stroke="#000"/>
"##,
        w / 2.0,
        title.replace('&', "&amp;").replace('<', "&lt;"),
        h - mb,
        w - mr,
        h - mb,
        h - mb
    );
    for e in (x0 as i32)..=(x1 as i32) {
        let v = 10f64.powi(e);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">1e{e}</text>"#,
            x(v),
            h - mb + 18.0
        );
    }
    for e in (y0 as i32)..=(y1 as i32) {
        let v = 10f64.powi(e);
        let _ = writeln!(
            s,
            r##"<line x1="{ml}" y1="{0}" x2="{1}" y2="{0}" stroke="#ddd"/><text x="{2}" y="{3}" text-anchor="end">1e{e}</text>"##,
            y(v),
            w - mr,
            ml - 6.0,
            y(v) + 4.0
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">wall time [s]</text><text x="16" y="{}" transform="rotate(-90 16 {})" text-anchor="middle">relative error</text>"#,
        w / 2.0,
        h - 12.0,
        h / 2.0,
        h / 2.0
    );
    for (k, (label, color)) in [(e1, "#d62728"), (e2, "#1f77b4")].iter().enumerate() {
        if label.is_empty() {
            continue;
        }
        let line: Vec<String> = pts
            .iter()
            .filter_map(|p| {
                let r = p.3;
                let v = if k == 0 { Some(p.1) } else { p.2 };
                v.map(|v| {
                    let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{color}"/><text x="{:.1}" y="{:.1}" font-size="10">{}x{}</text>"#, x(p.0), y(v), x(p.0) + 5.0, y(v) - 5.0, r.grid[0], r.grid[1]);
                    format!("{:.1},{:.1}", x(p.0), y(v))
                })
            })
            .collect();
        let _ = writeln!(
            s,
            r#"<polyline fill="none" stroke="{color}" stroke-width="1.5" points="{}"/><text x="{}" y="{}" fill="{color}">{label}</text>"#,
            line.join(" "),
            w - mr - 120.0,
            mt + 15.0 + 16.0 * k as f64
        );
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(n: usize, error: f64) -> StudyRow {
        StudyRow {
            grid: [n, n],
            unknowns: 3 * n * n,
            error,
            error_2: None,
            wall_time_s: 0.01 * n as f64,
            peak_memory_bytes: None,
            equilibrium_residual: 0.0,
        }
    }

    /// A zero error (the reference grid itself) has no point on a log plot; the labels of the
    /// other points stay with their own grids.
    #[test]
    fn plot_labels_stay_with_their_points_when_an_error_is_zero() {
        let rows = [row(3, 1e-2), row(5, 0.0), row(9, 1e-3)];
        let svg = study_svg(&rows, "force error", "", "t");
        assert!(!svg.contains(">5x5<"), "{svg}");
        let label = |g: &str| {
            let i = svg.find(&format!(">{g}<")).unwrap();
            let c = svg[..i].rfind("<circle cx=\"").unwrap() + 12;
            svg[c..].split('"').next().unwrap().parse::<f64>().unwrap()
        };
        // The 9x9 label sits at the 9x9 point, right of the 3x3 one (larger wall time).
        assert!(label("9x9") > label("3x3"), "{svg}");
    }
}
