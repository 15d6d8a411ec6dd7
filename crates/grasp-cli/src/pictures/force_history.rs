//! A plot of force histories (normal force solid with filled markers, friction dashed with
//! hollow ones, a colour per finger), like thesis figures 15 and 17, drawn with plotters (SVG
//! or PNG, see [`crate::pictures::picture`]). Symmetric fingers have identical curves: the
//! markers sit at different steps for different fingers and a note names the pairs, so every
//! finger shows.

use anyhow::Result;
use grasp_transfer::{IdenticalCurves, StepRecord};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::pictures::legend::{legend_beside, Sample, LEGEND_COLUMN_PX};
use crate::pictures::picture::{draw_err, Picture};

const COLORS: [RGBColor; 8] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Radius of the markers, px.
const MARKER_PX: u32 = 4;

/// Markers per curve (about).
const MARKERS_PER_CURVE: usize = 12;

/// The steps that carry finger `i`'s markers (of `n` fingers, over `points` steps): about
/// [`MARKERS_PER_CURVE`] evenly spaced, each finger's shifted by its share of the spacing, so
/// no two fingers mark the same step (while the spacing allows: at least `n` steps).
fn marker_steps(points: usize, i: usize, n: usize) -> Vec<usize> {
    let spacing = (points / MARKERS_PER_CURVE).max(n).max(1);
    let offset = spacing * i / n.max(1);
    (offset..points).step_by(spacing).collect()
}

/// Every finger's markers: filled on its normal force, hollow on its friction force, at the
/// steps [`marker_steps`] gives it.
fn draw_markers<DB: DrawingBackend>(
    chart: &mut ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    hist: &ForceHistory,
) -> Result<()> {
    let n = hist.names.len();
    for i in 0..n {
        let color = COLORS[i % COLORS.len()];
        let at = marker_steps(hist.points.len(), i, n);
        let point = |k: usize, pick: usize| (hist.points[k].0, hist.points[k].1[i][pick]);
        let filled = at
            .iter()
            .map(|&k| Circle::new(point(k, 0), MARKER_PX, color.filled()));
        chart.draw_series(filled).map_err(draw_err)?;
        let hollow = at
            .iter()
            .map(|&k| Circle::new(point(k, 1), MARKER_PX, color.stroke_width(2)));
        chart.draw_series(hollow).map_err(draw_err)?;
    }
    Ok(())
}

/// What the plot needs of a run, gathered step by step: the first and last step times and,
/// per step with forces, every finger's normal and friction force (2 numbers per finger and
/// step).
pub struct ForceHistory {
    names: Vec<String>,
    span: Option<(f64, f64)>,
    /// `(time s, [P, |Q|] per finger in scene order)` of every step with forces.
    points: Vec<(f64, Vec<[f64; 2]>)>,
    /// The fingers whose curves coincide (a symmetric pair), for the note.
    same: IdenticalCurves,
}

impl ForceHistory {
    /// An empty history of these fingers.
    pub fn new(names: &[String]) -> Self {
        ForceHistory {
            names: names.to_vec(),
            span: None,
            points: Vec::new(),
            same: IdenticalCurves::new(names),
        }
    }

    /// Adds a step.
    pub fn push(&mut self, r: &StepRecord) {
        let t0 = self.span.map_or(r.time_s, |s| s.0);
        self.span = Some((t0, r.time_s));
        if !r.solution.status.has_forces() {
            return;
        }
        let forces = self
            .names
            .iter()
            .map(|n| {
                r.solution
                    .finger(n)
                    .map_or([0.0, 0.0], |f| [f.normal_force_n, f.tangential_magnitude_n])
            })
            .collect::<Vec<_>>();
        self.same.push(&forces);
        self.points.push((r.time_s, forces));
    }

    /// The plot of this history, titled after `title` (the scene).
    pub fn picture<'a>(&'a self, title: &'a str) -> HistoryPlot<'a> {
        HistoryPlot { hist: self, title }
    }
}

/// Every finger's normal force (solid) and friction force (dashed) against time.
pub struct HistoryPlot<'a> {
    hist: &'a ForceHistory,
    title: &'a str,
}

impl Picture for HistoryPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (1060, 500)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_history(self.hist, self.title, root)
    }
}

fn draw_history<DB: DrawingBackend>(
    hist: &ForceHistory,
    title: &str,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let t0 = hist.span.map_or(0.0, |s| s.0);
    let t1 = hist.span.map_or(1.0, |s| s.1).max(t0 + 1e-9);
    let fmax = hist
        .points
        .iter()
        .flat_map(|p| p.1.iter().flatten())
        .fold(0.0_f64, |m, x| m.max(*x))
        .max(1e-9);
    root.fill(&WHITE).map_err(draw_err)?;
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!("Normal and friction forces along the schedule: {title}"),
            ("sans-serif", 16),
        )
        .margin(12)
        .margin_right(LEGEND_COLUMN_PX)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, 0.0..fmax * 1.05)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("force [N]")
        .max_light_lines(0)
        .draw()
        .map_err(draw_err)?;
    // Every line first, then every marker on top: a finger whose curves lie under another's
    // still shows its markers, which sit at different times for different fingers.
    let mut legend = Vec::new();
    for (i, name) in hist.names.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let style = ShapeStyle::from(&color).stroke_width(2);
        let series = |pick: usize| hist.points.iter().map(move |(t, f)| (*t, f[i][pick]));
        chart
            .draw_series(LineSeries::new(series(0), style))
            .map_err(draw_err)?;
        chart
            .draw_series(DashedLineSeries::new(series(1), 6, 4, style))
            .map_err(draw_err)?;
        for (what, dashed, filled) in [("normal P", false, true), ("friction |Q|", true, false)] {
            let sample = Sample {
                color,
                dashed,
                marker: Some(filled),
            };
            legend.push((format!("{name} {what}"), sample));
        }
    }
    draw_markers(&mut chart, hist)?;
    // Symmetric fingers: one curve lies on the other; the note names them.
    if let Some(note) = hist.same.note().map(|n| format!("{n} (markers staggered)")) {
        let (x, y) = chart.backend_coord(&(t0, fmax * 1.05));
        root.draw(&Text::new(note, (x + 8, y + 6), ("sans-serif", 13)))
            .map_err(draw_err)?;
    }
    legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)?;
    Ok(())
}
