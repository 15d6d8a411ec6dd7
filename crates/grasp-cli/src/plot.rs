//! An SVG plot of force histories (normal force solid, friction dashed per finger), like
//! thesis figures 15 and 17, drawn with plotters (its SVG backend needs no system fonts).

use grasp_transfer::StepRecord;
use plotters::prelude::*;

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

/// What the plot needs of a run, gathered step by step: the first and last step times and,
/// per step with forces, every finger's normal and friction force (2 numbers per finger and
/// step).
pub struct ForceHistory {
    names: Vec<String>,
    span: Option<(f64, f64)>,
    /// `(time s, [P, |Q|] per finger in scene order)` of every step with forces.
    points: Vec<(f64, Vec<[f64; 2]>)>,
}

impl ForceHistory {
    /// An empty history of these fingers.
    pub fn new(names: &[String]) -> Self {
        ForceHistory {
            names: names.to_vec(),
            span: None,
            points: Vec::new(),
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
            .collect();
        self.points.push((r.time_s, forces));
    }

    /// The SVG document (see [`force_history_svg`]).
    pub fn svg(&self, title: &str) -> String {
        force_history_svg(self, title)
    }
}

/// Returns an SVG document plotting every finger's normal force (solid) and friction force
/// (dashed) against time, drawn with plotters.
fn force_history_svg(hist: &ForceHistory, title: &str) -> String {
    let mut out = String::new();
    if let Err(e) = draw_history(hist, title, &mut out) {
        // plotters writes into a String: a failure here is a bug, reported in the picture.
        out = format!("<svg xmlns=\"http://www.w3.org/2000/svg\"><text y=\"20\">plot failed: {e}</text></svg>\n");
    }
    out
}

fn draw_history(hist: &ForceHistory, title: &str, out: &mut String) -> Result<(), String> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let t0 = hist.span.map_or(0.0, |s| s.0);
    let t1 = hist.span.map_or(1.0, |s| s.1).max(t0 + 1e-9);
    let fmax = hist
        .points
        .iter()
        .flat_map(|p| p.1.iter().flatten())
        .fold(0.0_f64, |m, x| m.max(*x))
        .max(1e-9);
    let root = SVGBackend::with_string(out, (900, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Forces during the hand-off: {title}"),
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, 0.0..fmax * 1.05)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("force [N]")
        .max_light_lines(0)
        .draw()
        .map_err(|x| e(&x))?;
    for (i, name) in hist.names.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let style = ShapeStyle::from(&color).stroke_width(2);
        let series = |pick: usize| hist.points.iter().map(move |(t, f)| (*t, f[i][pick]));
        chart
            .draw_series(LineSeries::new(series(0), style))
            .map_err(|x| e(&x))?
            .label(format!("{name} normal P"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        chart
            .draw_series(DashedLineSeries::new(series(1), 6, 4, style))
            .map_err(|x| e(&x))?
            .label(format!("{name} friction |Q|"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], style));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
