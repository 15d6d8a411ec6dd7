//! A plot of the margins along a planned hand-off beside its template's, against the
//! schedule's time, each with its threshold as a dashed line (SVG or PNG, see
//! [`crate::pictures::picture`]): per step the smallest slip margin `1 - |Q|/(mu P)` over the
//! fingers carrying at least 5 % of the load scale and, when the plan kept a disturbance
//! margin (`--min-margin`), below it the smallest disturbance margin over the axis directions
//! (N).

use anyhow::Result;
use grasp_transfer::{MarginsAtStep, PlanReport};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::pictures::legend::{legend_beside, Sample, LEGEND_COLUMN_PX};
use crate::pictures::picture::{draw_err, Picture};

/// The plot of one plan.
pub struct PlanMargins<'a> {
    /// The planner's answer.
    pub report: &'a PlanReport,
    /// The slip-margin threshold.
    pub threshold: f64,
    /// The disturbance-margin threshold, N (`--min-margin`), when one was asked.
    pub min_margin_n: Option<f64>,
    /// Title (the scene's file).
    pub title: &'a str,
}

/// One panel: a margin of every step, plan and template, and its threshold.
struct Panel<'a> {
    caption: String,
    y_desc: &'a str,
    value: fn(&MarginsAtStep) -> Option<f64>,
    threshold: f64,
}

impl Picture for PlanMargins<'_> {
    fn size(&self) -> (u32, u32) {
        match self.min_margin_n {
            Some(_) => (1060, 900),
            None => (1060, 500),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(draw_err)?;
        let slip = Panel {
            caption: format!("Smallest slip margin, plan and template: {}", self.title),
            y_desc: "1 - |Q| / (mu P)",
            value: |m| m.smallest,
            threshold: self.threshold,
        };
        let Some(min_margin_n) = self.min_margin_n else {
            return self.panel((root, root), &slip);
        };
        let disturbance = Panel {
            caption: "Smallest disturbance margin over the axis directions".to_owned(),
            y_desc: "margin [N]",
            value: |m| m.disturbance_n,
            threshold: min_margin_n,
        };
        let areas = root.split_evenly((2, 1));
        self.panel((root, &areas[0]), &slip)?;
        self.panel((root, &areas[1]), &disturbance)
    }
}

impl PlanMargins<'_> {
    /// Draws `panel` on `area` of `root`: the template's and the plan's lines, the dashed
    /// threshold and the legend beside them (placed on `root`, in its pixels).
    fn panel<DB: DrawingBackend>(
        &self,
        (root, area): (&DrawingArea<DB, Shift>, &DrawingArea<DB, Shift>),
        panel: &Panel,
    ) -> Result<()> {
        let r = self.report;
        let span = |m: &[MarginsAtStep]| m.last().map_or(0.0, |s| s.time_s);
        let template = r.template_margins.as_deref().unwrap_or(&[]);
        let t1 = span(&r.margins).max(span(template)).max(1e-9);
        let values: Vec<f64> = r
            .margins
            .iter()
            .chain(template)
            .filter_map(panel.value)
            .collect();
        let low = values
            .iter()
            .fold(panel.threshold.min(0.0), |a, &b| a.min(b));
        let high = values
            .iter()
            .fold(panel.threshold.max(1.0), |a, &b| a.max(b));
        let pad = 0.05 * (high - low).max(1e-9);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.caption, ("sans-serif", 16))
            .margin(12)
            .margin_right(LEGEND_COLUMN_PX)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..t1, low - pad..high + pad)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc("time [s]")
            .y_desc(panel.y_desc)
            .max_light_lines(0)
            .draw()
            .map_err(draw_err)?;
        let plan = ShapeStyle::from(&RGBColor(31, 119, 180)).stroke_width(2);
        let old = ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(2);
        let line = |m: &[MarginsAtStep]| -> Vec<(f64, f64)> {
            m.iter()
                .filter_map(|s| Some((s.time_s, (panel.value)(s)?)))
                .collect()
        };
        let mut legend = Vec::new();
        for (points, style, name) in [
            (line(template), old, "template"),
            (line(&r.margins), plan, "plan"),
        ] {
            if points.is_empty() {
                continue;
            }
            chart
                .draw_series(LineSeries::new(points, style))
                .map_err(draw_err)?;
            legend.push((name.to_owned(), sample(style.color, false)));
        }
        let red = ShapeStyle::from(&RGBColor(214, 39, 40)).stroke_width(1);
        let limit = [(0.0, panel.threshold), (t1, panel.threshold)];
        chart
            .draw_series(DashedLineSeries::new(limit, 6, 4, red))
            .map_err(draw_err)?;
        legend.push(("threshold".to_owned(), sample(red.color, true)));
        legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)
    }
}

/// A legend sample of a line of colour `c`, no marker.
fn sample(c: RGBAColor, dashed: bool) -> Sample {
    Sample {
        color: RGBColor(c.0, c.1, c.2),
        dashed,
        marker: None,
    }
}
