//! `grasp study`: a grid-refinement table (and CSV, plot) so a user can pick a grid for the
//! accuracy they need.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use grasp_model::{
    grid_with_first_side, hertz_parameters, peak_trend, refinement_study, with_grids, SolveAt,
    StudyReference, StudyRow, WarningTally, GROWING_PEAK_EXPONENT,
};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::output::{self, ForceArg};
use crate::pictures::legend::{legend_beside, Sample, LEGEND_COLUMN_PX};
use crate::pictures::picture::{self, draw_err, Picture};
use crate::solve_flags::SolveFlags;

/// Peak resident memory of this process (Linux `VmHWM`), bytes. Grids run in ascending order,
/// so after each solve it is that grid's peak.
fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Grid-refinement study: error, unknowns, wall time and peak memory per grid.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// Elements along the first side of every patch, one solve each (aspect ratio kept):
    /// at most 32 grids, each in [1, 2048] (a patch has at most 2048 x 2048 elements).
    #[arg(long, value_delimiter = ',', default_value = "5,9,17")]
    pub grids: Vec<usize>,
    /// Error reference: `hertz` (the closed form: one spherical tip on a flat), `finest` (the
    /// finest grid of the study: differences from it, which underestimate the error), or
    /// `auto`: the closed form where the scene has one, else the finest grid.
    #[arg(long, default_value = "auto", value_parser = ["auto", "hertz", "finest"])]
    pub reference: String,
    /// Write the table as CSV.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Write an error-versus-time plot (.svg or .png).
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArg,
    #[command(flatten)]
    pub solve: SolveFlags,
}

/// `grasp study`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let outputs = Outputs {
        csv: args.csv.as_deref(),
        plot: args.plot.as_deref(),
        force: args.force.force,
    };
    run(
        &args.scene,
        &args.grids,
        &args.reference,
        outputs,
        args.solve,
    )
}

/// Output files of a study.
pub struct Outputs<'a> {
    pub csv: Option<&'a Path>,
    pub plot: Option<&'a Path>,
    pub force: bool,
}

fn run(
    scene: &Path,
    grids: &[usize],
    reference: &str,
    out: Outputs,
    solve: SolveFlags,
) -> Result<ExitCode> {
    let options = solve.options();
    check_grids(grids)?;
    let (csv, plot) = (out.csv, out.plot);
    let plot_format = plot.map(|p| picture::Format::of(p, "--plot")).transpose()?;
    let targets: Vec<&Path> = [csv, plot].into_iter().flatten().collect();
    let outs = output::claim(&targets, &[scene], out.force)?;
    let scene_obj = crate::load_scene::load_scene(scene)?;
    let finest = grids.iter().copied().max().unwrap_or(1);
    let finest_scene = with_grids(&scene_obj, |_, g| grid_with_first_side(g, finest));
    solve.check_memory(&finest_scene, scene).with_context(|| {
        format!("the finest grid of the study ({finest} elements along the first side)")
    })?;
    let (reference, why) = choose_reference(&scene_obj, reference, finest);
    let mut distinct = grids.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    let bar = crate::progress::bar(distinct.len(), "grids");
    // Called after each grid's solve: the bar moves on as the peak memory is read.
    let after_solve = || {
        bar.inc(1);
        peak_memory_bytes()
    };
    let studied = refinement_study(&scene_obj, grids, reference, options, after_solve);
    bar.finish_and_clear();
    let rows = match studied {
        Ok(r) => r,
        Err(e) => bail!("study of {} failed: {e}", scene.display()),
    };
    let (e1, e2) = match reference {
        StudyReference::Hertz => ("p0 error", "approach error"),
        StudyReference::FinestGrid => ("force error", ""),
    };
    println!("reference: {why}");
    print!("{}", table_text(scene, reference, &rows, e1, e2));
    if let Some(line) = peak_trend_line(&rows) {
        println!("{line}");
    }
    print!("{}", crate::flag_names::in_flags(&warning_lines(&rows)));
    let mut pending = Vec::new();
    if let Some(p) = csv {
        let mut o = outs.create(p)?;
        o.write_all(csv_text(&rows).as_bytes())?;
        pending.push(o);
    }
    if let (Some(p), Some(format)) = (plot, plot_format) {
        let title = scene.display().to_string();
        let chart = StudyPlot {
            rows: &rows,
            errors: (e1, e2),
            title: &title,
        };
        // A picture that cannot be drawn costs the study no other output.
        match picture::render(&chart, format) {
            Ok(bytes) => {
                let mut o = outs.create(p)?;
                o.write_all(&bytes)?;
                pending.push(o);
            }
            Err(e) => eprintln!("warning: the plot {} was not written: {e:#}", p.display()),
        }
    }
    let written: Vec<std::path::PathBuf> =
        pending.iter().map(|o| o.target().to_path_buf()).collect();
    outs.commit(pending)?;
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The error reference `asked` for (`auto`, `hertz` or `finest`) and a sentence saying what
/// it is and why it matters: against the finest grid the errors are differences between
/// grids (the finest row shows 0, and every error is understated), against a closed form
/// they are true errors. `auto` takes the closed form where the scene has one.
fn choose_reference(
    scene: &grasp_model::Scene,
    asked: &str,
    finest: usize,
) -> (StudyReference, String) {
    let closed_form = hertz_parameters(scene);
    let finest_words = format!(
        "the finest grid ({finest} elements along the first side): each error is the \
         difference from it, so the finest row shows 0 and the errors are understated"
    );
    match (asked, closed_form) {
        ("hertz", _) => (
            StudyReference::Hertz,
            "the Hertz closed form (Johnson 4.2): true errors".into(),
        ),
        ("auto", Ok(_)) => (
            StudyReference::Hertz,
            "the Hertz closed form (Johnson 4.2), chosen automatically: the scene is one \
             spherical tip on a flat, so the errors are true errors (--reference finest \
             compares grids instead)"
                .into(),
        ),
        ("auto", Err(why)) => (
            StudyReference::FinestGrid,
            format!("{finest_words}; no closed form applies ({why})"),
        ),
        (_, Ok(_)) => (
            StudyReference::FinestGrid,
            format!(
                "{finest_words}; this scene has a closed form: --reference hertz (or auto) \
                 measures the true error"
            ),
        ),
        (_, Err(_)) => (StudyReference::FinestGrid, finest_words),
    }
}

/// How the largest peak pressure changed over the grids, in a sentence: its first and last
/// value, the exponent of its fitted growth `n^b`, and whether it converges (`None` with fewer
/// than two grids).
fn peak_trend_line(rows: &[StudyRow]) -> Option<String> {
    let trend = peak_trend(rows)?;
    let (first, last) = (rows.first()?, rows.last()?);
    let b = trend.exponent;
    let verdict = match (trend.at_sharp_edge, b >= GROWING_PEAK_EXPONENT) {
        (true, true) => format!(
            "the peak grows as n^{b:.2}: a singular edge (the peak lies at a sharp edge of the \
             contact, where the pressure is unbounded); not a converged value (the forces \
             converge)"
        ),
        (true, false) => format!(
            "the peak changes as n^{b:.2} here, but it lies at a sharp edge of the contact, \
             where the pressure is singular: it grows on finer grids; not a converged value"
        ),
        (false, true) => {
            format!("the peak grows as n^{b:.2}: not converged at these grids")
        }
        (false, false) => format!("the peak changes as n^{b:.2}: converging"),
    };
    Some(format!(
        "peak pressure: {:.3e} Pa at {}x{} to {:.3e} Pa at {}x{} (n elements along the first \
         side, fitted over {} grids): {verdict}",
        first.peak_pressure_pa,
        first.grid[0],
        first.grid[1],
        last.peak_pressure_pa,
        last.grid[0],
        last.grid[1],
        rows.len()
    ))
}

/// The warnings of the grids' solves, each once with the grids it applies to.
fn warning_lines(rows: &[StudyRow]) -> String {
    let mut tally = WarningTally::new();
    for (index, r) in rows.iter().enumerate() {
        tally.add(
            SolveAt {
                index,
                time_s: None,
            },
            &r.warnings,
        );
    }
    let label = |k: usize| format!("{}x{}", rows[k].grid[0], rows[k].grid[1]);
    let grids = crate::report::Solves {
        total: rows.len(),
        singular: "grid",
        plural: "grids",
        label: &label,
    };
    crate::report::tallied_warning_lines(&tally.warnings(), &grids)
}

/// Most grids of one study (each is a solve).
const MAX_GRIDS: usize = 32;

/// `--grids`: between 1 and [`MAX_GRIDS`] counts, each in [1, 2048] (a patch has at most
/// `MAX_GRID_SIDE` elements a side).
fn check_grids(grids: &[usize]) -> Result<()> {
    let most = grasp_model::limits::MAX_GRID_SIDE;
    if grids.is_empty() || grids.len() > MAX_GRIDS {
        bail!(
            "--grids lists {} grids; give between 1 and {MAX_GRIDS}, e.g. --grids 5,9,17",
            grids.len()
        );
    }
    if let Some(g) = grids.iter().find(|&&g| g == 0 || g > most) {
        bail!("--grids has {g}; give element counts in [1, {most}], e.g. --grids 5,9,17");
    }
    Ok(())
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
        "| grid | unknowns | {e1} | {}p_max [Pa] | wall time [s] | peak memory [MiB] |",
        if e2.is_empty() {
            String::new()
        } else {
            format!("{e2} | ")
        }
    );
    let _ = writeln!(
        t,
        "|---|---|---|{}---|---|---|",
        if e2.is_empty() { "" } else { "---|" }
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {}x{} | {} | {:.2e} | {}{:.3e}{} | {:.3} | {} |",
            r.grid[0],
            r.grid[1],
            r.unknowns,
            r.error,
            r.error_2.map_or(String::new(), |e| format!("{e:.2e} | ")),
            r.peak_pressure_pa,
            if r.peak_pressure_grid_dependent {
                " (at an edge)"
            } else {
                ""
            },
            r.wall_time_s,
            r.peak_memory_bytes
                .map_or("-".into(), |b| format!("{:.0}", b as f64 / 1048576.0))
        );
    }
    if rows.iter().any(|r| r.peak_pressure_grid_dependent) {
        t.push_str(
            "p_max (at an edge): at a sharp edge of the contact, where the pressure is \
             singular: it grows with the grid\n",
        );
    }
    t
}

/// The study as CSV (numbers and booleans only: no field needs quoting).
fn csv_text(rows: &[StudyRow]) -> String {
    let mut c = String::from(
        "nx,ny,unknowns,error,error_2,wall_time_s,peak_memory_bytes,equilibrium_residual,\
         peak_pressure_pa,peak_pressure_grid_dependent\n",
    );
    for r in rows {
        let _ = writeln!(
            c,
            "{},{},{},{},{},{},{},{},{},{}",
            r.grid[0],
            r.grid[1],
            r.unknowns,
            r.error,
            r.error_2.map_or(String::new(), |e| e.to_string()),
            r.wall_time_s,
            r.peak_memory_bytes.map_or(String::new(), |b| b.to_string()),
            r.equilibrium_residual,
            r.peak_pressure_pa,
            r.peak_pressure_grid_dependent
        );
    }
    c
}

/// Log-log plot of error against wall time, one point per grid labelled with it; `errors`
/// names the first and (if not empty) second error column.
struct StudyPlot<'a> {
    rows: &'a [StudyRow],
    errors: (&'a str, &'a str),
    title: &'a str,
}

impl Picture for StudyPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (860, 460)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_study(self.rows, self.errors, self.title, root)
    }
}

/// A run's point on the plot: its wall time, its errors, and its row (for the label).
struct StudyPoint<'a> {
    /// Wall time of the run, s.
    time_s: f64,
    /// The first error.
    error: f64,
    /// The second error, where there is one and it is positive.
    error_2: Option<f64>,
    /// The run.
    row: &'a StudyRow,
}

/// The log-log chart of every run's errors against its wall time, a line per error, each
/// point labelled with its grid once, and the legend beside it.
fn draw_study<DB: DrawingBackend>(
    rows: &[StudyRow],
    (e1, e2): (&str, &str),
    title: &str,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    // Points of a log-log plot need positive errors; each keeps its row for the label.
    let pts: Vec<StudyPoint> = rows
        .iter()
        .filter(|r| r.error > 0.0 && r.wall_time_s > 0.0)
        .map(|r| StudyPoint {
            time_s: r.wall_time_s,
            error: r.error,
            error_2: r.error_2.filter(|e| *e > 0.0),
            row: r,
        })
        .collect();
    let xs = decades(pts.iter().map(|p| p.time_s), 1e-3);
    let ys = decades(
        pts.iter()
            .flat_map(|p| std::iter::once(p.error).chain(p.error_2)),
        1e-6,
    );
    root.fill(&WHITE).map_err(draw_err)?;
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!("Error against run time: {title}"),
            ("sans-serif", 15),
        )
        .margin(12)
        .margin_right(LEGEND_COLUMN_PX)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d(xs.log_scale(), ys.log_scale())
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .x_desc("wall time [s]")
        .y_desc("relative error")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(draw_err)?;
    let mut legend = Vec::new();
    for (k, (label, color)) in [(e1, RGBColor(214, 39, 40)), (e2, RGBColor(31, 119, 180))]
        .into_iter()
        .enumerate()
    {
        if label.is_empty() {
            continue;
        }
        let sample = Sample {
            color,
            dashed: false,
            marker: Some(true),
        };
        legend.push((label.to_owned(), sample));
        draw_errors(&mut chart, &pts, k == 1, color)?;
    }
    legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)?;
    Ok(())
}

/// A log axis's range over `values`: from the decade at or below the smallest to the decade
/// at or above the largest, at least one decade wide; from `empty_low` without values.
fn decades(values: impl Iterator<Item = f64> + Clone, empty_low: f64) -> std::ops::Range<f64> {
    let decade = |v: f64, up: bool| {
        10f64.powf(if up {
            v.log10().ceil()
        } else {
            v.log10().floor()
        })
    };
    let low = decade(values.clone().fold(f64::INFINITY, f64::min), false);
    let high = decade(values.fold(0.0, f64::max), true);
    let low = if low.is_finite() { low } else { empty_low };
    low..high.max(low * 10.0)
}

/// One error's line and points (the first error's, or the `second`'s), the first error's
/// points labelled with their grids (the second error's point is at the same time, straight
/// above or below it).
/// The points of one error curve `(time s, error, row)`, in order of run time: the line runs
/// left to right (in grid order it zigzagged wherever a finer grid happened to run faster).
fn error_series<'a>(pts: &[StudyPoint<'a>], second: bool) -> Vec<(f64, f64, &'a StudyRow)> {
    let mut series: Vec<(f64, f64, &StudyRow)> = pts
        .iter()
        .filter_map(|p| {
            let error = if second { p.error_2 } else { Some(p.error) };
            error.map(|v| (p.time_s, v, p.row))
        })
        .collect();
    series.sort_by(|a, b| a.0.total_cmp(&b.0));
    series
}

fn draw_errors<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    pts: &[StudyPoint],
    second: bool,
    color: RGBColor,
) -> Result<()> {
    let series = error_series(pts, second);
    chart
        .draw_series(LineSeries::new(series.iter().map(|p| (p.0, p.1)), &color))
        .map_err(draw_err)?;
    for (t, v, r) in &series {
        chart
            .draw_series(std::iter::once(Circle::new((*t, *v), 3, color.filled())))
            .map_err(draw_err)?;
        if !second {
            let grid = format!("{}x{}", r.grid[0], r.grid[1]);
            chart
                .draw_series(std::iter::once(Text::new(
                    grid,
                    (*t, *v),
                    ("sans-serif", 10),
                )))
                .map_err(draw_err)?;
        }
    }
    Ok(())
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
            peak_pressure_pa: 1e5,
            peak_pressure_grid_dependent: false,
            warnings: Vec::new(),
        }
    }

    /// The study plot zigzagged in grid order where a finer grid ran faster: its curve now runs
    /// in order of run time, each point still with its own grid.
    #[test]
    fn the_error_curve_runs_in_order_of_time_not_of_grid() {
        let mut rows = [row(3, 1e-2), row(5, 5e-3), row(9, 1e-3)];
        rows[1].wall_time_s = 0.2; // the 5x5 grid ran slowest
        let pts: Vec<StudyPoint> = rows
            .iter()
            .map(|r| StudyPoint {
                time_s: r.wall_time_s,
                error: r.error,
                error_2: None,
                row: r,
            })
            .collect();
        let series = error_series(&pts, false);
        let times: Vec<f64> = series.iter().map(|p| p.0).collect();
        assert_eq!(times, [0.03, 0.09, 0.2]);
        let grids: Vec<usize> = series.iter().map(|p| p.2.grid[0]).collect();
        assert_eq!(grids, [3, 9, 5]);
    }

    /// A zero error (the reference grid itself) has no point on a log plot; the labels of the
    /// other points stay with their own grids.
    #[test]
    fn plot_labels_stay_with_their_points_when_an_error_is_zero() {
        let rows = [row(3, 1e-2), row(5, 0.0), row(9, 1e-3)];
        let chart = StudyPlot {
            rows: &rows,
            errors: ("force error", ""),
            title: "t",
        };
        let svg =
            String::from_utf8(picture::render(&chart, picture::Format::Svg).unwrap()).unwrap();
        assert!(!svg.contains("5x5"), "{svg}");
        // The x of the text element holding a grid's label.
        let label = |g: &str| {
            let i = svg.find(g).unwrap();
            let c = svg[..i].rfind("<text x=\"").unwrap() + 9;
            svg[c..].split('"').next().unwrap().parse::<f64>().unwrap()
        };
        // The 9x9 label sits at the 9x9 point, right of the 3x3 one (larger wall time).
        assert!(label("9x9") > label("3x3"), "{svg}");
    }

    /// With two errors per run, each run's grid label is printed once, not once per error.
    #[test]
    fn each_grid_label_is_printed_once_with_two_errors() {
        let mut rows = [row(3, 1e-2), row(9, 1e-3)];
        rows[0].error_2 = Some(2e-2);
        rows[1].error_2 = Some(3e-3);
        let chart = StudyPlot {
            rows: &rows,
            errors: ("force error", "pressure error"),
            title: "t",
        };
        let svg =
            String::from_utf8(picture::render(&chart, picture::Format::Svg).unwrap()).unwrap();
        for grid in ["3x3", "9x9"] {
            assert_eq!(svg.matches(grid).count(), 1, "{grid}: {svg}");
        }
    }
}
