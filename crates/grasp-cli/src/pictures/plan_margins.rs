//! A plot of a planned hand-off beside its template, against the schedule's time, each
//! threshold as a dashed line (SVG or PNG, see [`crate::pictures::picture`]): per step the
//! smallest slip margin `1 - |Q|/(mu P)` over the fingers carrying at least 5 % of the load
//! scale; when the plan kept a disturbance margin (`--min-margin`), below it the smallest
//! disturbance margin over the axis directions (N); and at the bottom each planned finger's
//! commanded normal load (N), or its commanded approach (mm) when the plan drives it by its
//! position (a panel for each kind planned), solid along the plan, dashed along the template.
//!
//! The time axis spans the plan's own duration. A template longer than the plan gets its own
//! time axis along the top of every panel, spanning the template's duration, so that neither
//! is squeezed into a part of the width (a plan of a seventh of its template's duration took
//! a seventh of the width); a template as long as the plan or shorter shares the plan's axis.

use anyhow::Result;
use grasp_model::{ControlSpec, Scene};
use grasp_transfer::{Command, MarginsAtStep, PlanReport, Schedule};
use plotters::chart::DualCoordChartContext;
use plotters::coord::types::RangedCoordf64;
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
    /// The planned fingers' commanded loads along the plan.
    pub loads: Vec<LoadCurve>,
    /// The same fingers' along the template (empty without one).
    pub template_loads: Vec<LoadCurve>,
    /// The planned position-controlled fingers' commanded approaches along the plan, mm.
    pub approaches: Vec<LoadCurve>,
    /// The same fingers' along the template (empty without one).
    pub template_approaches: Vec<LoadCurve>,
}

/// One finger's commanded normal load (or approach) along a schedule.
pub struct LoadCurve {
    /// The finger's name.
    pub finger: String,
    /// `(time s, load N)` at the schedule's steps where the finger is force-controlled or
    /// released (0 N); or `(time s, approach mm)` where it is position-controlled.
    pub points: Vec<(f64, f64)>,
}

/// The commanded approaches of `fingers` at every step of `schedule`, mm: the steps where
/// each is pressed in by an approach (a held finger at 0 mm).
pub fn approach_curves(schedule: &Schedule, scene: &Scene, fingers: &[String]) -> Vec<LoadCurve> {
    let mut curves = Vec::new();
    for name in fingers {
        let Some(i) = scene.fingers.iter().position(|f| &f.name == name) else {
            continue;
        };
        let scene_command = match scene.fingers[i].control {
            ControlSpec::Approach(a) => Command::Approach(a.approach_m),
            _ => Command::Held,
        };
        let points = schedule
            .times
            .iter()
            .filter_map(|&t| match schedule.command(i, t, 0.0, scene_command) {
                Command::Approach(a) => Some((t, 1e3 * a)),
                Command::Held => Some((t, 0.0)),
                Command::Load(_) | Command::Released => None,
            })
            .collect();
        curves.push(LoadCurve {
            finger: name.clone(),
            points,
        });
    }
    curves
}

/// The commanded normal loads of `fingers` (names of `scene`'s fingers) at every step of
/// `schedule`: a ramp's `"current"` resolved to the finger's load in the scene at the first
/// step and to its last commanded load when a later phase begins (a force-controlled finger
/// carries what it is commanded), a released finger at 0 N, a held or pressed-in one left out.
pub fn load_curves(schedule: &Schedule, scene: &Scene, fingers: &[String]) -> Vec<LoadCurve> {
    let mut curves = Vec::new();
    for name in fingers {
        let Some(i) = scene.fingers.iter().position(|f| &f.name == name) else {
            continue;
        };
        let (scene_load, scene_command) = match scene.fingers[i].control {
            ControlSpec::Load(l) => (l.normal_load, Command::Load(l.normal_load)),
            _ => (0.0, Command::Held),
        };
        let (mut phase, mut current, mut last) = (None, scene_load, scene_load);
        let mut points = Vec::new();
        for &t in &schedule.times {
            let p = schedule.phase_index(i, t);
            if p != phase {
                (phase, current) = (p, last);
            }
            let load = match schedule.command(i, t, current, scene_command) {
                Command::Load(n) => n,
                Command::Released => 0.0,
                Command::Held | Command::Approach(_) => continue,
            };
            last = load;
            points.push((t, load));
        }
        curves.push(LoadCurve {
            finger: name.clone(),
            points,
        });
    }
    curves
}

/// A panel of the planned commands of one kind: loads or approaches.
struct Commands<'a> {
    plan: &'a [LoadCurve],
    template: &'a [LoadCurve],
    caption: &'a str,
    y_desc: &'a str,
    unit: &'a str,
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
            Some(_) => (1060, 1260),
            None => (1060, 860),
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
        let kinds = [&self.loads, &self.approaches];
        let commands = kinds.iter().filter(|c| !c.is_empty()).count().max(1);
        let panels = 1 + usize::from(self.min_margin_n.is_some()) + commands;
        let areas = root.split_evenly((panels, 1));
        self.panel((root, &areas[0]), &slip)?;
        if let Some(min_margin_n) = self.min_margin_n {
            let disturbance = Panel {
                caption: "Smallest disturbance margin over the axis directions".to_owned(),
                y_desc: "margin [N]",
                value: |m| m.disturbance_n,
                threshold: min_margin_n,
            };
            self.panel((root, &areas[1]), &disturbance)?;
        }
        let mut next = panels - commands;
        if !self.loads.is_empty() || self.approaches.is_empty() {
            let loads = Commands {
                plan: &self.loads,
                template: &self.template_loads,
                caption: "Planned normal loads (solid: plan, dashed: template)",
                y_desc: "normal load [N]",
                unit: "N",
            };
            self.commands_panel(root, &areas[next], &loads)?;
            next += 1;
        }
        if !self.approaches.is_empty() {
            let approaches = Commands {
                plan: &self.approaches,
                template: &self.template_approaches,
                caption: "Planned approaches (solid: plan, dashed: template)",
                y_desc: "approach [mm]",
                unit: "mm",
            };
            self.commands_panel(root, &areas[next], &approaches)?;
        }
        Ok(())
    }
}

/// A panel's chart: the plan's time along the bottom, the template's along the top when it is
/// longer (its own coordinates otherwise the plan's).
type TimeChart<'a, DB> = DualCoordChartContext<
    'a,
    DB,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
>;

impl PlanMargins<'_> {
    /// The plan's duration and the template's, s (the template's 0 without one).
    fn spans(&self) -> (f64, f64) {
        let r = self.report;
        let span = |m: &[MarginsAtStep]| m.last().map_or(0.0, |s| s.time_s);
        let template = r.template_margins.as_deref().unwrap_or(&[]);
        let loads = |c: &[LoadCurve]| {
            c.iter()
                .filter_map(|c| c.points.last())
                .fold(0.0_f64, |a, p| a.max(p.0))
        };
        let plan = span(&r.margins).max(r.duration_s).max(1e-9);
        let old = span(template)
            .max(r.template_duration_s.unwrap_or(0.0))
            .max(loads(&self.template_loads))
            .max(loads(&self.template_approaches));
        (plan, old)
    }

    /// A chart on `area` captioned `caption` over `low..high` (`y_desc`): the plan's time
    /// along the bottom, and along the top the template's when it is longer (module doc).
    fn time_chart<'a, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
        caption: &str,
        y_desc: &str,
        (low, high): (f64, f64),
    ) -> Result<TimeChart<'a, DB>> {
        let (plan, old) = self.spans();
        let own_axis = old > plan * (1.0 + 1e-9);
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 16))
            .margin(12)
            .margin_right(LEGEND_COLUMN_PX)
            .x_label_area_size(40)
            .top_x_label_area_size(if own_axis { 36 } else { 0 })
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..plan, low..high)
            .map_err(draw_err)?
            .set_secondary_coord(0.0..if own_axis { old } else { plan }, low..high);
        let x_desc = match own_axis {
            true => "plan's time [s]",
            false => "time [s]",
        };
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .max_light_lines(0)
            .draw()
            .map_err(draw_err)?;
        if own_axis {
            chart
                .configure_secondary_axes()
                .x_desc("template's time [s] (grey and dashed curves)")
                .draw()
                .map_err(draw_err)?;
        }
        // A frame around the plot area: its right edge is the plan's end.
        let (xs, ys) = chart.plotting_area().get_pixel_range();
        let (x0, y0) = area.get_base_pixel();
        let frame = [
            (xs.start - x0, ys.start - y0),
            (xs.end - 1 - x0, ys.end - 1 - y0),
        ];
        area.draw(&Rectangle::new(frame, BLACK)).map_err(draw_err)?;
        Ok(chart)
    }

    /// Draws `panel` on `area` of `root`: the template's and the plan's lines, the dashed
    /// threshold and the legend beside them (placed on `root`, in its pixels).
    fn panel<DB: DrawingBackend>(
        &self,
        (root, area): (&DrawingArea<DB, Shift>, &DrawingArea<DB, Shift>),
        panel: &Panel,
    ) -> Result<()> {
        let r = self.report;
        let template = r.template_margins.as_deref().unwrap_or(&[]);
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
        let range = (low - pad, high + pad);
        let mut chart = self.time_chart(area, &panel.caption, panel.y_desc, range)?;
        let plan = ShapeStyle::from(&RGBColor(31, 119, 180)).stroke_width(2);
        let old = ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(2);
        let line = |m: &[MarginsAtStep]| -> Vec<(f64, f64)> {
            m.iter()
                .filter_map(|s| Some((s.time_s, (panel.value)(s)?)))
                .collect()
        };
        let mut legend = Vec::new();
        let points = line(template);
        if !points.is_empty() {
            chart
                .draw_secondary_series(LineSeries::new(points, old))
                .map_err(draw_err)?;
            legend.push(("template".to_owned(), sample(old.color, false)));
        }
        let points = line(&r.margins);
        if !points.is_empty() {
            chart
                .draw_series(LineSeries::new(points, plan))
                .map_err(draw_err)?;
            legend.push(("plan".to_owned(), sample(plan.color, false)));
        }
        let red = ShapeStyle::from(&RGBColor(214, 39, 40)).stroke_width(1);
        let t1 = self.spans().0;
        let limit = [(0.0, panel.threshold), (t1, panel.threshold)];
        chart
            .draw_series(DashedLineSeries::new(limit, 6, 4, red))
            .map_err(draw_err)?;
        legend.push(("threshold".to_owned(), sample(red.color, true)));
        legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)
    }

    /// The planned fingers' commands of one kind, solid along the plan and dashed along the
    /// template, one colour per finger.
    fn commands_panel<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        area: &DrawingArea<DB, Shift>,
        commands: &Commands,
    ) -> Result<()> {
        let values = commands.plan.iter().chain(commands.template);
        let values: Vec<f64> = values.flat_map(|c| c.points.iter().map(|p| p.1)).collect();
        let high = values.iter().fold(0.0_f64, |a, &b| a.max(b));
        let low = values.iter().fold(0.0_f64, |a, &b| a.min(b));
        let pad = 0.05 * (high - low).max(1e-9);
        let range = (low - pad, high + pad);
        let mut chart = self.time_chart(area, commands.caption, commands.y_desc, range)?;
        let mut legend = Vec::new();
        for (k, c) in commands.plan.iter().enumerate() {
            let colour = FINGER_RGB[k % FINGER_RGB.len()];
            let style = ShapeStyle::from(&colour).stroke_width(2);
            if let Some(old) = commands.template.iter().find(|o| o.finger == c.finger) {
                let thin = ShapeStyle::from(&colour.mix(0.7)).stroke_width(1);
                chart
                    .draw_secondary_series(DashedLineSeries::new(old.points.clone(), 6, 4, thin))
                    .map_err(draw_err)?;
            }
            chart
                .draw_series(LineSeries::new(c.points.clone(), style))
                .map_err(draw_err)?;
            // A finger commanded as an earlier one is drawn over it: the legend says so.
            let same = commands.plan[..k].iter().find(|o| o.points == c.points);
            let unit = commands.unit;
            let label = match same {
                Some(o) => format!("{} [{unit}] (= {})", c.finger, o.finger),
                None => format!("{} [{unit}]", c.finger),
            };
            legend.push((label, sample(style.color, false)));
        }
        legend_beside(root, chart.plotting_area().get_pixel_range(), &legend)
    }
}

/// The load curves' colours, one per planned finger in turn.
const FINGER_RGB: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

/// A legend sample of a line of colour `c`, no marker.
fn sample(c: RGBAColor, dashed: bool) -> Sample {
    Sample {
        color: RGBColor(c.0, c.1, c.2),
        dashed,
        marker: None,
    }
}
