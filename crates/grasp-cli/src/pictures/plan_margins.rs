//! A plot of the slip margins along a planned hand-off beside its template's: per step the
//! smallest `1 - |Q|/(mu P)` over the fingers carrying at least 5 % of the load scale,
//! against the schedule's time, with the threshold as a dashed line (SVG or PNG, see
//! [`crate::pictures::picture`]).

use anyhow::Result;
use grasp_transfer::plan::{MarginsAtStep, PlanReport};
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
    /// Title (the scene's file).
    pub title: &'a str,
}

impl Picture for PlanMargins<'_> {
    fn size(&self) -> (u32, u32) {
        (1060, 500)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let r = self.report;
        let span = |m: &[MarginsAtStep]| m.last().map_or(0.0, |s| s.time_s);
        let template = r.template_margins.as_deref().unwrap_or(&[]);
        let t1 = span(&r.margins).max(span(template)).max(1e-9);
        let values = r.margins.iter().chain(template).filter_map(|m| m.smallest);
        let low = values.fold(self.threshold.min(0.0), f64::min);
        root.fill(&WHITE).map_err(draw_err)?;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Smallest slip margin, plan and template: {}", self.title),
                ("sans-serif", 16),
            )
            .margin(12)
            .margin_right(LEGEND_COLUMN_PX)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..t1, low - 0.05..1.05)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc("time [s]")
            .y_desc("1 - |Q| / (mu P)")
            .max_light_lines(0)
            .draw()
            .map_err(draw_err)?;
        let plan = ShapeStyle::from(&RGBColor(31, 119, 180)).stroke_width(2);
        let old = ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(2);
        let line = |m: &[MarginsAtStep]| -> Vec<(f64, f64)> {
            m.iter()
                .filter_map(|s| Some((s.time_s, s.smallest?)))
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
        let limit = [(0.0, self.threshold), (t1, self.threshold)];
        chart
            .draw_series(DashedLineSeries::new(limit, 6, 4, red))
            .map_err(draw_err)?;
        legend.push(("threshold".to_owned(), sample(red.color, true)));
        legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)?;
        Ok(())
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
